// Dialogues kept in this browser (localStorage): every turn's whole answer, so that a reload
// redraws the charts, and restores the turns even when the server has forgotten the session or
// has no GET /sessions/{id}. The newest MAX_DIALOGUES are kept; storage errors (full, disabled)
// are ignored: the page works without it.
const KEY = "ctburton.dialogues.v1";
const CURRENT = "ctburton.current.v1";
const MAX_DIALOGUES = 8;

function read() {
  try {
    const v = JSON.parse(localStorage.getItem(KEY) || "[]");
    return Array.isArray(v) ? v : [];
  } catch { return []; }
}

function write(list) {
  for (let keep = MAX_DIALOGUES; keep > 0; keep--) {
    try {
      localStorage.setItem(KEY, JSON.stringify(list.slice(-keep)));
      return;
    } catch { /* quota: keep fewer */ }
  }
}

export function dialogue(session) {
  return read().find((d) => d.session === session) || null;
}

// Adds a turn ({command, answer?, error?, at}) to the session's dialogue.
export function addTurn(session, domain, turn) {
  const list = read();
  let d = list.find((x) => x.session === session);
  if (!d) {
    d = { session, domain, turns: [] };
    list.push(d);
  } else {
    list.splice(list.indexOf(d), 1);
    list.push(d);  // most recently used last
  }
  d.turns.push(turn);
  write(list);
}

export function currentSession() {
  const fromUrl = new URLSearchParams(location.search).get("session");
  if (fromUrl && /^[A-Za-z0-9_-]{1,128}$/.test(fromUrl)) return fromUrl;
  try { return localStorage.getItem(CURRENT); } catch { return null; }
}

// Puts the session in the URL (so the address can be bookmarked or reloaded) and in storage.
export function setCurrentSession(session) {
  const url = new URL(location.href);
  if (session) url.searchParams.set("session", session); else url.searchParams.delete("session");
  history.replaceState(null, "", url);
  try {
    if (session) localStorage.setItem(CURRENT, session); else localStorage.removeItem(CURRENT);
  } catch { /* storage disabled */ }
}
