// API keys for the page (docs/grpc.md, "Access control"): when the server answers 401, the page
// asks for a key in a small dialog, keeps it in sessionStorage (this tab only: never
// localStorage, never a cookie) and sends it as "Authorization: Bearer KEY" with every request
// to its own origin. Loaded before app.js; it wraps window.fetch, so the rest of the page is
// unchanged.
const KEY = "ctburton.apiKey";
const plainFetch = window.fetch.bind(window);

function sameOrigin(input) {
  const url = new URL(typeof input === "string" ? input : input.url, location.href);
  return url.origin === location.origin;
}

function withKey(init) {
  const key = sessionStorage.getItem(KEY);
  if (!key) return init;
  const headers = new Headers((init && init.headers) || {});
  headers.set("Authorization", `Bearer ${key}`);
  return { ...(init || {}), headers };
}

let asking = null;
// Resolves to true once the user gave a key, false when they cancelled.
function askForKey(wrong) {
  if (asking) return asking;
  asking = new Promise((resolve) => {
    const dlg = document.createElement("dialog");
    dlg.className = "key-dialog";
    dlg.innerHTML = `<form method="dialog">
      <h2>This server needs an API key</h2>
      <p>${wrong ? "That key was not accepted. " : ""}It is kept for this tab only.</p>
      <label>API key <input name="key" type="password" autocomplete="off" required></label>
      <menu><button value="cancel" formnovalidate>Cancel</button>
      <button value="ok" class="primary">Use this key</button></menu></form>`;
    document.body.appendChild(dlg);
    dlg.addEventListener("close", () => {
      const key = dlg.querySelector("input").value.trim();
      const ok = dlg.returnValue === "ok" && key !== "";
      if (ok) sessionStorage.setItem(KEY, key);
      dlg.remove();
      asking = null;
      resolve(ok);
    });
    dlg.showModal();
  });
  return asking;
}

window.fetch = async (input, init) => {
  if (!sameOrigin(input)) return plainFetch(input, init);
  let res = await plainFetch(input, withKey(init));
  for (let tries = 0; res.status === 401 && tries < 3; ++tries) {
    const hadKey = sessionStorage.getItem(KEY) !== null;
    sessionStorage.removeItem(KEY);
    if (!(await askForKey(hadKey))) break;
    res = await plainFetch(input, withKey(init));
  }
  return res;
};
