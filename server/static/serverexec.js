// Executions on the server (contract section 14, docs/executive.md): a plan answer offers "Run on
// the server", which starts POST /executions with the turn's domain and state plan on the
// simulated team (a speed, a chance that a commanded move fails, a seed) or on devices over MQTT. The execution then
// runs in the server, not in this page: the panel #server-exec follows its events
// (GET /executions/{id}/events: commands sent, reports received, replans, the end), and a reload
// finds it again (its id is kept in localStorage) and replays what happened. Once it has ended,
// the panel offers the durations seen for the team (GET /domains/{name}/durations).
import { getStream } from "./sse.js";

const KEY = "ctburton.execution.v1";
let following = null;  // AbortController of the stream being followed

function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}
const $ = (id) => document.getElementById(id);

function remember(exec) {
  try {
    if (exec) localStorage.setItem(KEY, JSON.stringify(exec)); else localStorage.removeItem(KEY);
  } catch { /* storage disabled: the panel works until a reload */ }
}
function remembered() {
  try { return JSON.parse(localStorage.getItem(KEY) || "null"); } catch { return null; }
}

// One line of the log for an event.
function line(name, d) {
  const t = (x) => `t = ${Math.round(x * 100) / 100} s`;
  switch (name) {
    case "dispatched": return `${t(d.at)}: sent ${d.automaton} ${d.command} (${d.from} → ${d.to})`;
    case "reported":
      return d.failed ? `${t(d.time)}: ${d.automaton} could not ${d.failed}` : `${t(d.time)}: ${d.automaton} reached ${d.location}`;
    case "replanned": return `t = ${d.now} s: replanned (${d.why}) in ${d.ms} ms: ${d.status}`;
    case "finished": return `finished: ${d.state}${d.why ? ` (${d.why})` : ""}`;
    default: return `${name}`;
  }
}

function setState(state) {
  const s = $("server-exec-state");
  s.textContent = state;
  s.className = `exec-state state-${state}`;
  $("server-exec-stop").hidden = state !== "running";
}

async function showDurations(domain) {
  const box = $("server-exec-durations");
  box.replaceChildren(el("p", { class: "note" }, "reading…"));
  const r = await fetch(`/domains/${encodeURIComponent(domain)}/durations`).catch(() => null);
  const data = r && r.ok ? await r.json() : null;
  if (!data) return box.replaceChildren(el("p", { class: "note" }, "the durations could not be read"));
  const table = el("table", { class: "durations" });
  const head = el("tr");
  for (const h of ["automaton", "transition", "seen", "min s", "max s", "mean s"]) head.appendChild(el("th", { scope: "col" }, h));
  table.appendChild(head);
  for (const x of data.transitions) {
    const tr = el("tr");
    for (const v of [x.automaton, `${x.from} → ${x.to}`, x.count, x.min, x.max, x.mean]) tr.appendChild(el("td", {}, String(v)));
    table.appendChild(tr);
  }
  box.replaceChildren(el("h3", {}, `Durations seen for ${domain}`), table,
    el("p", { class: "note" }, data.suggested
      ? "A revision of the team that admits them is suggested: GET the durations and store \"suggested\" as a new team."
      : "What was seen fits the team as it is."));
}

// Follows execution `exec` ({id, domain}) in the panel, from its first event.
async function follow(exec) {
  if (following) following.abort();
  const ctl = new AbortController();
  following = ctl;
  const panel = $("server-exec");
  panel.hidden = false;
  $("server-exec-id").textContent = exec.id.slice(0, 8);
  $("server-exec-durations").replaceChildren();
  const log = $("server-exec-log");
  log.replaceChildren();
  setState("running");
  let replans = 0;
  const status = await getStream(`/executions/${exec.id}/events`, {
    signal: ctl.signal,
    onEvent: (name, d) => {
      const li = el("li", { class: `ev ev-${name}` }, line(name, d));
      log.appendChild(li);
      li.scrollIntoView({ block: "nearest" });
      if (name === "replanned") $("server-exec-replans").textContent = `${++replans} replan${replans > 1 ? "s" : ""}`;
      if (name === "finished") {
        setState(d.state);
        const b = el("button", { type: "button", id: "server-exec-show-durations" }, "Durations seen for this team");
        b.addEventListener("click", () => showDurations(exec.domain));
        $("server-exec-durations").replaceChildren(b);
      }
    },
  }).catch(() => 0);
  if (status === 404) {
    setState("unknown");
    log.appendChild(el("li", {}, "the server no longer knows this execution"));
    remember(null);
  }
}

// The control under a plan answer: run it on the server. ctx: {domain}.
export function serverRunBlock(data, ctx) {
  const box = el("details", { class: "server-run" });
  box.appendChild(el("summary", {}, "Run on the server"));
  const row = el("div", { class: "form-row" });
  const speed = el("select", { "aria-label": "Speed" });
  for (const s of [1, 2, 5, 20]) speed.appendChild(el("option", { value: String(s) }, s === 1 ? "×1 (real time)" : `×${s}`));
  speed.value = "5";
  const fail = el("select", { "aria-label": "Chance that a commanded move fails" });
  for (const [v, t] of [["0", "no faults"], ["0.1", "10 % of moves fail"], ["0.3", "30 % of moves fail"]])
    fail.appendChild(el("option", { value: v }, t));
  const seed = el("input", { type: "number", min: "0", step: "1", value: "1", "aria-label": "Seed", class: "seed" });
  const adapter = el("select", { "aria-label": "Who carries it out" });
  for (const [v, t] of [["sim", "the simulated team"], ["mqtt", "devices over MQTT"]]) adapter.appendChild(el("option", { value: v }, t));
  adapter.addEventListener("change", () => { fail.disabled = seed.disabled = adapter.value !== "sim"; });
  const go = el("button", { type: "button", class: "server-run-go" }, "Start on the server");
  const note = el("span", { class: "note", role: "status" });
  const speedLabel = el("label", {}, "Speed ");
  speedLabel.appendChild(speed);
  const seedLabel = el("label", {}, "seed ");
  seedLabel.appendChild(seed);
  row.append(adapter, speedLabel, fail, seedLabel, go, note);
  box.appendChild(row);
  box.appendChild(el("p", { class: "note" }, "The server solves the state plan again and carries its plan out, on its simulated team or on devices over MQTT (when it runs with --mqtt-url); the execution goes on if you reload this page."));
  go.addEventListener("click", async () => {
    go.disabled = true;
    note.textContent = "starting…";
    const body = { domain: ctx.domain, state_plan: data.state_plan, adapter: adapter.value, speed: Number(speed.value) };
    if (adapter.value === "sim") body.sim = { fail: Number(fail.value), seed: Math.max(0, Math.floor(Number(seed.value) || 0)) };
    const r = await fetch("/executions", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body) }).catch(() => null);
    const answer = r ? await r.json().catch(() => ({})) : {};
    go.disabled = false;
    if (!r || r.status !== 201) {
      note.textContent = `not started: ${answer.error?.message || (r ? r.status : "no answer")}`;
      return;
    }
    note.textContent = "started";
    const exec = { id: answer.execution, domain: ctx.domain };
    remember(exec);
    follow(exec);
  });
  return box;
}

// At start-up: the execution this browser started last, followed again (it replays its events).
export function initServerExec() {
  $("server-exec-stop").addEventListener("click", async () => {
    const exec = remembered();
    if (exec) await fetch(`/executions/${exec.id}`, { method: "DELETE" }).catch(() => null);
  });
  $("server-exec-close").addEventListener("click", () => {
    if (following) following.abort();
    remember(null);
    $("server-exec").hidden = true;
  });
  const exec = remembered();
  if (exec && typeof exec.id === "string" && /^[0-9a-f]{1,64}$/.test(exec.id)) follow(exec);
}
