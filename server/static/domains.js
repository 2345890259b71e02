// The team panel (issue 22, contract section 12): the selected domain's diagram
// (GET /domains/{name}/diagram), its action model to edit or a new one to paste, checked and
// stored by the server (POST /domains, PUT /domains/{name}) with every error shown at its place
// in the text, and a draft from words (POST /domains/draft) to edit before it is saved.
const $ = (id) => document.getElementById(id);

// Pretty-printed JSON and where each JSON pointer's value sits in it: {text, spans: Map(pointer
// -> [start, end])}. The server's errors name pointers; these spans turn them into places.
export function layout(value) {
  const spans = new Map();
  let text = "";
  const pad = (n) => "  ".repeat(n);
  const token = (k) => String(k).replace(/~/g, "~0").replace(/\//g, "~1");
  function emit(v, ptr, depth) {
    const start = text.length;
    const items = Array.isArray(v) ? v.map((x, i) => [i, x]) : v && typeof v === "object" ? Object.entries(v) : null;
    if (!items) {
      text += JSON.stringify(v);
    } else if (!items.length) {
      text += Array.isArray(v) ? "[]" : "{}";
    } else {
      text += Array.isArray(v) ? "[\n" : "{\n";
      items.forEach(([k, x], i) => {
        text += pad(depth + 1) + (Array.isArray(v) ? "" : JSON.stringify(String(k)) + ": ");
        emit(x, `${ptr}/${token(k)}`, depth + 1);
        text += i < items.length - 1 ? ",\n" : "\n";
      });
      text += pad(depth) + (Array.isArray(v) ? "]" : "}");
    }
    spans.set(ptr, [start, text.length]);
  }
  emit(value, "", 0);
  return { text: text + "\n", spans };
}

// The span of a pointer, or of its nearest ancestor that exists (a missing field: its object).
export function spanOf(spans, pointer) {
  let p = pointer || "";
  while (!spans.has(p) && p !== "") p = p.slice(0, Math.max(0, p.lastIndexOf("/")));
  return spans.get(p) || [0, 0];
}

const lineOf = (text, offset) => text.slice(0, offset).split("\n").length;

let options = null;   // {currentDomain(), onSaved(name)}
let laidOut = null;   // the editor's text as last laid out: {text, spans}

function status(text, kind = "") {
  const s = $("team-status");
  s.textContent = text;
  s.className = `team-status ${kind}`;
}

// Selects a span of the editor and scrolls it into view.
function goTo([start, end]) {
  const ed = $("team-editor");
  ed.focus();
  ed.setSelectionRange(start, end);
  const line = lineOf(ed.value, start);
  const lh = parseFloat(getComputedStyle(ed).lineHeight) || 18;
  ed.scrollTop = Math.max(0, (line - 3) * lh);
}

function showErrors(details, message) {
  const list = $("team-errors");
  list.replaceChildren();
  $("team-editor").setAttribute("aria-invalid", details.length || message ? "true" : "false");
  if (message) status(message, "bad");
  for (const d of details) {
    const li = document.createElement("li");
    const span = laidOut ? spanOf(laidOut.spans, d.path) : [0, 0];
    const b = document.createElement("button");
    b.type = "button";
    b.className = "team-error";
    b.textContent = `line ${lineOf($("team-editor").value, span[0])} · ${d.path || "/"}: ${d.message}`;
    b.addEventListener("click", () => goTo(span));
    li.appendChild(b);
    list.appendChild(li);
  }
  if (details.length) goTo(laidOut ? spanOf(laidOut.spans, details[0].path) : [0, 0]);
}

function setEditor(doc) {
  laidOut = layout(doc);
  $("team-editor").value = laidOut.text;
  showErrors([]);
}

async function loadDiagram(name) {
  const img = $("team-diagram");
  img.alt = `Diagram of the automata of ${name}`;
  img.src = `/domains/${encodeURIComponent(name)}/diagram`;
  $("team-diagram-link").href = img.src;
}

async function loadDocument(name) {
  const r = await fetch(`/domains/${encodeURIComponent(name)}`);
  if (!r.ok) return status(`could not load ${name} (${r.status})`, "bad");
  setEditor(await r.json());
  const list = await fetch("/domains").then((x) => x.json()).catch(() => ({ domains: [] }));
  const info = (list.domains || []).find((d) => d.name === name);
  const shipped = !info || info.source !== "stored";
  $("team-source").textContent = shipped
    ? "a shipped domain: to change it, give it a new name and save it as a new team"
    : `stored through the API, version ${info.version}`;
  status("");
}

// How long each transition took in this team's executions on the server (contract 14), and the
// suggested revision that admits it, which the user may load into the editor and save.
async function loadDurations(name) {
  const box = $("team-durations-body");
  box.replaceChildren();
  const r = await fetch(`/domains/${encodeURIComponent(name)}/durations`).catch(() => null);
  const data = r && r.ok ? await r.json().catch(() => null) : null;
  const note = (t) => Object.assign(document.createElement("p"), { className: "note", textContent: t });
  if (!data) return box.appendChild(note("the durations could not be read"));
  if (!data.transitions.length) return box.appendChild(note("no execution of this team has run on the server yet"));
  const table = document.createElement("table");
  table.className = "durations";
  const row = (cells, tag) => {
    const tr = document.createElement("tr");
    for (const c of cells) tr.appendChild(Object.assign(document.createElement(tag), { textContent: String(c) }));
    return tr;
  };
  table.appendChild(row(["automaton", "transition", "seen", "min s", "max s", "mean s"], "th"));
  for (const x of data.transitions) table.appendChild(row([x.automaton, `${x.from} → ${x.to}`, x.count, x.min, x.max, x.mean], "td"));
  box.appendChild(table);
  if (!data.suggested) return box.appendChild(note("what was seen fits the team as it is"));
  const use = Object.assign(document.createElement("button"), { type: "button", id: "team-use-durations",
    textContent: "Load the revision that admits them into the editor" });
  use.addEventListener("click", () => {
    const doc = { ...data.suggested };
    if (!/_learned$/.test(doc.name)) doc.name = `${doc.name}_learned`;
    setEditor(doc);
    $("team-edit").open = true;
    status("a revision from what was seen (bounds widened, uncertain where they spread): check it, then save", "ok");
  });
  box.appendChild(use);
}

export async function showTeam(name) {
  if (!name) return;
  $("team-title").textContent = `Team: ${name}`;
  await Promise.all([loadDiagram(name), loadDocument(name), loadDurations(name)]);
}

// Parses the editor; a syntax error is shown at its line.
function parseEditor() {
  const text = $("team-editor").value;
  try {
    return JSON.parse(text);
  } catch (e) {
    const m = /position (\d+)/.exec(String(e.message));
    const at = m ? +m[1] : 0;
    laidOut = null;
    showErrors([], `not JSON: ${e.message}`);
    $("team-editor").setSelectionRange(at, at + 1);
    return undefined;
  }
}

async function save() {
  const doc = parseEditor();
  if (doc === undefined) return;
  // Errors point into the document as the server read it: lay it out the same way first.
  setEditor(doc);
  const name = typeof doc.name === "string" ? doc.name : "";
  const exists = name && (await fetch("/domains").then((r) => r.json()).catch(() => ({ domains: [] })))
    .domains?.some((d) => d.name === name && d.source === "stored");
  status("checking…");
  const r = await fetch(exists ? `/domains/${encodeURIComponent(name)}` : "/domains", {
    method: exists ? "PUT" : "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(doc),
  });
  const data = await r.json().catch(() => ({}));
  if (!r.ok) {
    const e = data.error || {};
    showErrors(Array.isArray(e.details) ? e.details : [], `${r.status}: ${e.message || "refused"}`);
    return;
  }
  // "saved" is said once the page has selected the team and drawn it, never before.
  await options.onSaved(name);
  await showTeam(name);
  status(exists ? `saved ${name} (replaced)` : `saved ${name}`, "ok");
}

async function draft() {
  const description = $("team-description").value.trim();
  if (!description) return $("team-description").focus();
  const button = $("team-draft");
  button.disabled = true;
  status("drafting with the LLM…");
  try {
    const r = await fetch("/domains/draft", {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ description }),
    });
    const data = await r.json().catch(() => ({}));
    if (!r.ok) {
      const e = data.error || {};
      return status(`${r.status}: ${e.message || "the draft failed"}`, "bad");
    }
    setEditor(data.action_model);
    $("team-source").textContent = "a draft: read it, change what is wrong, then save it";
    $("team-restatement").textContent = data.restatement || "";
    const qs = $("team-questions");
    qs.replaceChildren(...(data.questions || []).map((q) => Object.assign(document.createElement("li"), { textContent: q })));
    $("team-draft-answer").hidden = false;
    $("team-edit").open = true;
    status("draft ready: check it, then save", "ok");
  } finally {
    button.disabled = false;
  }
}

export function initTeam(opts) {
  options = opts;
  $("team-toggle").addEventListener("click", async () => {
    const panel = $("team");
    panel.hidden = !panel.hidden;
    $("team-toggle").setAttribute("aria-expanded", String(!panel.hidden));
    if (!panel.hidden) await showTeam(options.currentDomain());
  });
  $("team-save").addEventListener("click", save);
  $("team-format").addEventListener("click", () => {
    const doc = parseEditor();
    if (doc !== undefined) setEditor(doc);
  });
  $("team-new").addEventListener("click", () => {
    setEditor({ name: "my_team", description: "", automata: [] });
    $("team-source").textContent = "a new team: paste or write its action model, then save it";
    $("team-edit").open = true;
    $("team-editor").focus();
  });
  $("team-draft").addEventListener("click", draft);
}

// Called when the page's domain changes: the open panel follows it.
export async function domainChanged(name) {
  if (!$("team").hidden) await showTeam(name);
}
