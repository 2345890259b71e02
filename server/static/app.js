// The ctburton chat page. Each dialogue is a thread (a session on the server); each command a
// turn: POST /plan with "stream": true shows the stage, the elapsed time and the best plan so far
// while it runs (Stop cancels the job on the server), then the answer (answer.js). The session
// id is kept in the URL and in localStorage, and a reload restores the turns: from
// GET /sessions/{id} when the server has it, else from this browser's copy (store.js). A plan can
// be executed on the page (execute.js); a fault reported there replans (POST /replan, in the
// session when the plan is the dialogue's latest) into a turn of its own.
import { postStream } from "./sse.js";
import { renderAnswer, renderRemembered } from "./answer.js";
import { executable } from "./execute.js";
import { clock, seconds } from "./timeline.js";
import * as store from "./store.js";
import { initTeam, domainChanged } from "./domains.js";
import { initServerExec } from "./serverexec.js";
import { initEval } from "./eval.js";

const $ = (id) => document.getElementById(id);
const LIMIT = 8000;  // bytes of UTF-8, as the server counts (translator/pipeline.cpp)
const NOTICE_KEY = "ctburton.llm-notice-dismissed";

const state = {
  session: null,       // the open dialogue's session id, null before its first answer
  dialogue: null,      // its <section>, null until a turn is sent
  dialogues: 0,
  examples: {},
  domainCache: {},
  busy: null,          // {controller} while a request runs
  pendingNote: "",     // said on the next dialogue's separator (why it is new)
  words: false,        // an LLM answers (endpoint or replay): faults may be reported in words
};

// One short sentence for screen readers (the live region), instead of reading whole answers or
// the ticking elapsed time.
function announce(text) {
  $("announcer").textContent = "";
  setTimeout(() => { $("announcer").textContent = text; }, 50);
}

function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

async function domainInfo(name) {
  if (!(name in state.domainCache)) {
    // Expanded: a stored domain written with templates comes as its plain automata.
    state.domainCache[name] = fetch(`/domains/${encodeURIComponent(name)}?expand=true`)
      .then((r) => (r.ok ? r.json() : null)).catch(() => null);
  }
  return state.domainCache[name];
}

function setSessionLabel() {
  $("session-label").textContent = state.session ? `session ${state.session.slice(0, 8)}` : "";
  const head = state.dialogue?.querySelector(".dialogue-session");
  if (head) head.textContent = state.session ? `session ${state.session.slice(0, 8)}` : "";
}

// A new thread in the log, with a separator heading.
function openDialogue(domain, note) {
  state.dialogues += 1;
  const sec = el("section", { class: "dialogue", "data-domain": domain, "aria-label": `Dialogue ${state.dialogues}` });
  const head = el("div", { class: "dialogue-head" });
  head.appendChild(el("h2", {}, `Dialogue ${state.dialogues} · ${domain}`));
  if (note) head.appendChild(el("span", { class: "dialogue-note" }, note));
  head.appendChild(el("span", { class: "dialogue-session" }));
  sec.appendChild(head);
  $("log").appendChild(sec);
  state.dialogue = sec;
  return sec;
}

// Ends the open dialogue: the next command starts a new one (with `note` on its separator).
function endDialogue(note) {
  state.session = null;
  state.dialogue = null;
  state.pendingNote = note || "";
  store.setCurrentSession(null);
  setSessionLabel();
}

function errorText(status, data) {
  const e = data?.error || {};
  let text = `${status || "network"} ${e.code || "error"}: ${e.message || "the request failed"}`;
  if (Array.isArray(e.details) && e.details.length)
    text += "\n" + e.details.map((d) => `${d.path}: ${d.message}`).join("\n");
  return text;
}

function addTurnShell(section, command) {
  const turn = el("article", { class: "turn" });
  turn.appendChild(el("div", { class: "user" }, command));
  section.appendChild(turn);
  return turn;
}

// The live part of a turn: spinner, stage, elapsed time, best plan so far.
function progressView(turn) {
  const box = el("div", { class: "progress" });
  const line = el("div", { class: "progress-line" });
  const spin = el("span", { class: "spinner", "aria-hidden": "true" });
  const stage = el("span", { class: "stage" }, "sending");
  const elapsed = el("span", { class: "elapsed" }, "0.0 s");
  line.append(spin, stage, elapsed);
  const sols = el("ol", { class: "solutions", "aria-label": "Improving plans" });
  box.append(line, sols);
  turn.appendChild(box);
  const t0 = performance.now();
  const timer = setInterval(() => { elapsed.textContent = `${((performance.now() - t0) / 1000).toFixed(1)} s`; }, 100);
  const names = { translating: "translating (LLM)", repairing: "repairing the LLM's answer", solving: "solving" };
  return {
    event(name, data) {
      if (name === "stage") {
        stage.textContent = names[data.stage] || data.stage;
        stage.dataset.stage = data.stage;
        announce(stage.textContent);
      } else if (name === "solution") {
        const v = data.kind === "makespan" ? `makespan ${clock(data.objective)}`
          : data.kind === "cost_then_makespan" ? `cost ${data.cost}, makespan ${clock(data.makespan)}`
            : `cost ${data.objective}`;
        const li = el("li", { class: "solution" },
          `best so far: ${v} · ${data.horizon} events · found at ${seconds((data.elapsed_ms || 0) / 1000)}`);
        sols.appendChild(li);
        announce(li.textContent);
      }
    },
    finish(text) {
      clearInterval(timer);
      spin.remove();
      box.classList.add("finished");
      stage.textContent = text;
      elapsed.textContent = `${((performance.now() - t0) / 1000).toFixed(1)} s`;
    },
  };
}

function showError(turn, status, data, { followUp, command }) {
  const box = el("div", { class: "error", role: "alert" }, errorText(status, data));
  turn.appendChild(box);
  if (followUp) {
    const b = el("button", { type: "button", class: "retry-new" }, "New dialogue with this command");
    b.addEventListener("click", () => {
      endDialogue("restarted after a failed follow-up");
      send(command);
    });
    const p = el("p", { class: "hint" }, "This was sent as a follow-up to the dialogue above. ");
    p.appendChild(b);
    turn.appendChild(p);
  }
}

function setBusy(controller) {
  state.busy = controller ? { controller } : null;
  $("send").disabled = !!controller;
  $("stop").hidden = !controller;
  document.body.classList.toggle("busy", !!controller);
}

// Sends a command: a follow-up in the open dialogue, or the first turn of a new one.
async function send(command, { fresh = false } = {}) {
  if (state.busy || !command) return;
  if (new TextEncoder().encode(command).length > LIMIT) return;
  const domain = $("domain").value;
  if (fresh && state.session) endDialogue();
  const section = state.dialogue || openDialogue(domain, state.pendingNote);
  state.pendingNote = "";
  const turn = addTurnShell(section, command);
  const progress = progressView(turn);
  turn.scrollIntoView({ block: "nearest" });
  const body = { domain, command, prompting: $("prompting").value };
  if ($("objective").value) body.options = { objective: $("objective").value };
  const followUp = !!state.session;
  if (followUp) {
    body.session = state.session;
    delete body.domain;  // a session keeps its domain
  }
  const controller = new AbortController();
  setBusy(controller);
  let result;
  try {
    result = await postStream("/plan", body, { signal: controller.signal, onEvent: (n, d) => progress.event(n, d) });
  } catch (err) {
    const stopped = controller.signal.aborted;
    progress.finish(stopped ? "stopped: the server cancels the job" : "failed");
    announce(stopped ? "Stopped." : "The request failed.");
    if (!stopped) showError(turn, 0, { error: { code: "network", message: String(err) } }, { followUp, command });
    setBusy(null);
    return;
  }
  setBusy(null);
  const at = new Date().toISOString();
  if (result.status !== 200) {
    progress.finish("failed");
    showError(turn, result.status, result.data, { followUp, command });
    announce(`Failed: ${result.data?.error?.message || result.status}`);
    if (state.session) store.addTurn(state.session, domain, { command, error: { status: result.status, data: result.data }, at });
    return;
  }
  const data = result.data;
  const n = turn.querySelectorAll(".solution").length;
  progress.finish(`answered${n ? ` after ${n} improving plan${n > 1 ? "s" : ""}` : ""}`);
  if (data.session) {
    state.session = data.session;
    store.setCurrentSession(data.session);
    setSessionLabel();
  }
  section.dataset.session = state.session || "";
  renderAnswer(turn, data, { domainInfo: await domainInfo(section.dataset.domain), followUp: (c) => send(c),
    execution: executionContext(turn, data), serverRun: { domain: section.dataset.domain } });
  announce(`Answer: ${turn.querySelector(".summary")?.textContent || ""}`);
  if (state.session) store.addTurn(state.session, section.dataset.domain, { command, answer: data, at });
  if ($("command").value.trim() === command) $("command").value = "";
  updateCounter();
}

// What execute.js needs from the page to execute `data` (an answer drawn in `turn`).
function executionContext(turn, data, carry) {
  return { announce, carry, words: state.words, replan: (body, meta) => replanFrom(turn, data, body, meta) };
}

// A fault reported while `data` (drawn in `fromTurn`) was executed: POST /replan (streamed, like
// /plan), the answer drawn as a new turn of the dialogue, the execution handed on to it with
// meta.carry. In the session when `fromTurn` holds the session's current plan (the replan is
// then a turn of the session, and the session's plan becomes the replanned one); otherwise with
// the turn's domain and state plan. Resolves to whether the replanned plan can be executed.
async function replanFrom(fromTurn, data, body, meta) {
  const section = fromTurn.closest(".dialogue");
  const answered = [...section.querySelectorAll(":scope > .turn")].filter((x) => x.querySelector(".summary"));
  const inSession = !!state.session && section.dataset.session === state.session && answered.at(-1) === fromTurn;
  if (inSession) body.session = state.session;
  else Object.assign(body, { domain: section.dataset.domain, state_plan: data.state_plan });
  const turn = addTurnShell(section, meta.label);
  turn.classList.add("replan-turn");
  const progress = progressView(turn);
  turn.scrollIntoView({ block: "nearest" });
  let result;
  try {
    result = await postStream("/replan", body, { onEvent: (n, d) => progress.event(n, d) });
  } catch (err) {
    progress.finish("failed");
    showError(turn, 0, { error: { code: "network", message: String(err) } }, {});
    announce("The replan failed.");
    return false;
  }
  if (result.status !== 200) {
    progress.finish("failed");
    showError(turn, result.status, result.data, {});
    announce(`The replan failed: ${result.data?.error?.message || result.status}`);
    return false;
  }
  const t = result.data;
  progress.finish("replanned");
  // A report in words: what the LLM read in it is blocked from now on, like a move reported failed.
  for (const b of t.report?.blocked || [])
    if (!meta.carry.blocked.some((x) => x.automaton === b.automaton && x.from === b.from && x.to === b.to))
      meta.carry.blocked.push({ automaton: b.automaton, from: b.from, to: b.to });
  const answer = { trajectory: t, state_plan: data.state_plan, previous_goal: data.trajectory?.goal_reached_at };
  if (t.session) answer.session = t.session;
  renderAnswer(turn, answer, { domainInfo: await domainInfo(section.dataset.domain), followUp: (c) => send(c),
    execution: executionContext(turn, answer, meta.carry), serverRun: { domain: section.dataset.domain } });
  announce(`Replanned: ${turn.querySelector(".summary")?.textContent || ""}`);
  if (inSession)
    store.addTurn(state.session, section.dataset.domain, { command: "(replan)", label: meta.label, answer,
      execution: { ...meta.carry, running: false }, at: new Date().toISOString() });
  return executable(t);
}

function updateCounter() {
  const n = new TextEncoder().encode($("command").value).length;
  const c = $("counter");
  c.textContent = `${n.toLocaleString("en")} / ${LIMIT.toLocaleString("en")}`;
  c.classList.toggle("near", n > LIMIT * 0.9);
  c.classList.toggle("over", n > LIMIT);
  $("command").setAttribute("aria-invalid", n > LIMIT ? "true" : "false");
}

function showExamples() {
  const domain = $("domain").value;
  const list = state.examples[domain] || [];
  const chips = $("chips");
  chips.replaceChildren();
  for (const ex of list) {
    const b = el("button", { type: "button", class: "chip", title: ex.command }, ex.label);
    b.dataset.command = ex.command;
    b.addEventListener("click", () => send(ex.command, { fresh: true }));
    chips.appendChild(b);
  }
  $("command").placeholder = list.length ? `e.g. ${list[0].command}` : "Say what the team should do";
  $("examples").hidden = list.length === 0;
}

// Turns kept for a session: the server's (GET /sessions/{id}) drawn with this browser's whole
// answers where it has them; when the server answers 404 (no such route, or the session is
// gone), this browser's own copy.
async function restore() {
  const id = store.currentSession();
  if (!id) return;
  const local = store.dialogue(id);
  let remote = null;
  try {
    const r = await fetch(`/sessions/${encodeURIComponent(id)}`);
    if (r.ok) remote = await r.json();
  } catch { /* offline: use the local copy */ }
  const turns = remote?.turns || local?.turns;
  const domain = remote?.domain || local?.domain;
  if (!turns || !turns.length || !domain) {
    store.setCurrentSession(null);
    return;
  }
  if ([...$("domain").options].some((o) => o.value === domain)) $("domain").value = domain;
  showExamples();
  state.session = id;
  const section = openDialogue(domain, remote ? "restored" : "restored from this browser");
  section.dataset.session = id;
  const info = await domainInfo(domain);
  // The server keeps answered turns only; this browser keeps failed ones too.
  const answered = (local?.turns || []).filter((x) => x.answer);
  turns.forEach((t, i) => {
    const kept = remote ? (answered[i]?.command === t.command ? answered[i] : null) : t;
    const turn = addTurnShell(section, kept?.label || t.command);
    if (t.command === "(replan)") turn.classList.add("replan-turn");
    if (!kept) renderRemembered(turn, t);
    else if (kept.answer) renderAnswer(turn, kept.answer, { domainInfo: info, followUp: (c) => send(c),
      execution: executionContext(turn, kept.answer, kept.execution) });
    else if (kept.error) turn.appendChild(el("div", { class: "error" }, errorText(kept.error.status, kept.error.data)));
  });
  store.setCurrentSession(id);
  setSessionLabel();
}

function domainOption(d) {
  const o = el("option", { value: d.name }, d.source === "stored" ? `${d.name} (yours)` : d.name);
  if (d.description) o.title = d.description;
  return o;
}

// The domain list again (a team was saved): the new one selected, cached documents dropped.
async function reloadDomains(select) {
  const domains = await fetch("/domains").then((r) => r.json()).catch(() => null);
  if (!domains) return;
  state.domainCache = {};
  const before = $("domain").value;
  $("domain").replaceChildren();
  for (const d of domains.domains) $("domain").appendChild(domainOption(d));
  const want = select || before;
  if ([...$("domain").options].some((o) => o.value === want)) $("domain").value = want;
  if ($("domain").value !== before) {
    if (state.session || state.dialogue) endDialogue(`domain changed to ${$("domain").value}`);
    showExamples();
  }
}

async function init() {
  const [domains, examples, info] = await Promise.all([
    fetch("/domains").then((r) => r.json()),
    fetch("/examples.json").then((r) => (r.ok ? r.json() : {})).catch(() => ({})),
    fetch("/info").then((r) => (r.ok ? r.json() : null)).catch(() => null),
  ]);
  state.examples = examples.domains || {};
  for (const d of domains.domains) $("domain").appendChild(domainOption(d));
  const preferred = examples.default_domain;
  if ([...$("domain").options].some((o) => o.value === preferred)) $("domain").value = preferred;
  state.words = info?.llm?.mode === "endpoint" || info?.llm?.mode === "replay";
  $("examples-note").textContent = info?.llm?.mode === "recordings" ? "(answered offline from recordings)" : "";
  let dismissed = false;
  try { dismissed = localStorage.getItem(NOTICE_KEY) === "1"; } catch { /* storage disabled */ }
  const noLlm = info?.llm?.mode === "recordings" || info?.llm?.mode === "none";
  if (info?.llm?.mode === "none")
    $("llm-notice-text").textContent = "No LLM is configured, and the server was started without --demo: " +
      "commands need an endpoint. /solve works.";
  $("llm-notice").hidden = !noLlm || dismissed;
  $("llm-notice-close").addEventListener("click", () => {
    $("llm-notice").hidden = true;
    try { localStorage.setItem(NOTICE_KEY, "1"); } catch { /* storage disabled */ }
    $("command").focus();
  });
  showExamples();

  $("ask").addEventListener("submit", (ev) => {
    ev.preventDefault();
    let command = $("command").value.trim();
    if (!command) {
      // An empty box sends the example it shows.
      const ex = (state.examples[$("domain").value] || [])[0];
      if (!ex) return;
      command = ex.command;
      return send(command, { fresh: true });
    }
    send(command);
  });
  $("command").addEventListener("keydown", (ev) => {
    if (ev.key === "Enter" && !ev.shiftKey && !ev.isComposing && !ev.altKey && !ev.ctrlKey && !ev.metaKey) {
      ev.preventDefault();
      $("ask").requestSubmit();
    }
  });
  $("command").addEventListener("input", updateCounter);
  $("stop").addEventListener("click", () => state.busy?.controller.abort());
  $("new-session").addEventListener("click", () => {
    endDialogue();
    $("command").focus();
  });
  $("domain").addEventListener("change", () => {
    // A session keeps its domain: say so, rather than resetting silently.
    if (state.session || state.dialogue) endDialogue(`domain changed to ${$("domain").value}`);
    showExamples();
    domainChanged($("domain").value);
  });
  initTeam({ currentDomain: () => $("domain").value, onSaved: reloadDomains });
  initServerExec();
  initEval();
  updateCounter();
  await restore();
  document.body.dataset.ready = "1";
}

init();
