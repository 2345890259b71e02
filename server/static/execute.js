// Execution you can watch (issue 21; docs/replanning.md, "On the page"). A plan answer gets a
// Start/Stop control and a speed (×1 is real time); while it runs, a "now" line moves across the
// timeline (timeline.js setNow), the part before it hatched as executed, and the plan's
// transitions are dispatched when due (the execution log lists them). Once started, a click or
// tap on a row of the timeline (a segment, a command, or the row's name, which the keyboard
// reaches with Tab) opens a box to report what went wrong there:
//   "This move failed"  the move is reported blocked (never taken again), and the future is
//                       replanned from now at once;
//   "This took longer"  the stay ends N s late: its automaton's next move is held until then,
//                       reported as happening then, and the future is replanned at that time
//                       (as `ctburton execute --fault delay:...` does);
//   "Or say what happened" (when the server has an LLM) anything else, in words: the replan
//                       sends it as `command` and the LLM reads it into observed/blocked.
// A replan is a POST /replan through ctx.replan (app.js) with the history dispatched so far
// (`executed`), every move reported blocked and the plan being executed; its answer becomes a
// new turn, whose diff shows the new future against the old one, and the execution goes on
// there from the same now. The clock stops while the report box is open and while the planner
// replans. One execution runs at a time.
import { clock } from "./timeline.js";

const SPEEDS = [1, 10, 60];
let active = null;  // the execution whose clock runs

function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

const near = (a, b) => Math.abs(a - b) < 1e-6;
const entryOf = (tr) => ({ time: tr.time, automaton: tr.automaton, from: tr.from, to: tr.to,
  ...(tr.observed ? { observed: true } : {}) });
const moveText = (tr) => `${tr.from} → ${tr.to}${tr.command ? ` (${tr.command})` : ""}`;

// Whether a trajectory can be executed: a plan with transitions still to come.
export function executable(t) {
  return !!t && (t.status === "optimal" || t.status === "feasible") && !!t.timelines &&
    (t.transitions || []).some((tr) => !tr.executed && !tr.observed);
}

// A default delay for "took longer": about a tenth of the plan, in round seconds.
function defaultDelay(span) {
  for (const s of [1, 2, 5, 10, 30, 60, 120, 300, 600]) if (s >= span / 10) return s;
  return 900;
}

// Adds the execution control below `chart` (renderTimeline's answer) in `into`. ctx: {replan(body,
// meta) -> Promise<bool> (true: the replanned answer can be executed), announce(text), carry (the
// state a replan hands over: now, executed, blocked, holds, speed, running), words (true: an LLM
// answers, so the report box offers a report in words)}.
export function attachExecution(into, t, chart, ctx) {
  const carry = ctx.carry || {};
  const start = carry.now ?? t.now ?? 0;
  const ex = {
    now: start,
    // The history: what the carry says, plus the jumps this answer observed at its now.
    executed: carry.executed
      ? [...carry.executed, ...(t.transitions || []).filter((x) => x.observed && x.time >= start).map(entryOf)]
      : (t.transitions || []).filter((x) => x.executed || x.observed).map(entryOf),
    blocked: [...(carry.blocked || [])],
    holds: [...(carry.holds || [])],  // {automaton, location, until}: a stay that ends late
    pending: (t.transitions || []).filter((x) => !x.executed && !x.observed)
      .map((x) => ({ ...x, done: false })).sort((a, b) => a.time - b.time || a.event - b.event),
    speed: SPEEDS.includes(carry.speed) ? carry.speed : SPEEDS[0],
    running: false, started: !!carry.started, over: false, raf: 0, base: 0, t0: 0, box: null,
  };
  const lastTime = Math.max(0, ...(t.transitions || []).map((x) => x.time));
  const end = Math.max(typeof t.goal_reached_at === "number" ? t.goal_reached_at : 0, lastTime);
  const integral = (t.events || []).every((e) => Number.isInteger(e));

  const box = el("div", { class: "exec", role: "group", "aria-label": "Execution" });
  const bar = el("div", { class: "exec-bar" });
  const toggle = el("button", { type: "button", class: "exec-toggle" }, ex.started ? "Resume" : "Start execution");
  const speedLabel = el("label", { class: "exec-speed" }, "Speed ");
  const speed = el("select", {});
  for (const s of SPEEDS) speed.appendChild(el("option", { value: String(s) }, s === 1 ? "×1 (real time)" : `×${s}`));
  speed.value = String(ex.speed);
  speedLabel.appendChild(speed);
  const clockEl = el("span", { class: "exec-clock", role: "timer" });
  bar.append(toggle, speedLabel, clockEl);
  const status = el("p", { class: "exec-status", role: "status" });
  const hint = el("p", { class: "exec-hint" },
    "Something went wrong? Click or tap its row in the timeline (or Tab to the row's name and press Enter).");
  hint.hidden = !ex.started;
  const log = el("details", { class: "exec-log" });
  const logSummary = el("summary", {}, "Execution log (0)");
  const logList = el("ol", {});
  log.append(logSummary, logList);
  box.append(bar, status, hint, log);
  into.appendChild(box);

  const say = (text, loud = false) => {
    status.textContent = text;
    if (loud) ctx.announce?.(text);
  };
  const addLog = (time, text, cls) => {
    const li = el("li", cls ? { class: cls } : {}, `${clock(time)}  ${text}`);
    logList.appendChild(li);
    logSummary.textContent = `Execution log (${logList.children.length})`;
  };
  const showClock = () => { clockEl.textContent = `${clock(Math.floor(ex.now))} / ${clock(end)}`; };
  showClock();

  // --- the clock ---
  function setNow(v) {
    ex.now = v;
    box.dataset.now = v;  // plan seconds, for tests and tools
    chart.setNow(v);
    showClock();
  }
  function firstPending(a) { return ex.pending.find((p) => !p.done && p.automaton === a) || null; }
  // The holds in force: the automaton waits in the held location and its planned exit is before
  // the hold ends. A hold the plan already honours (its exit is later) is dropped.
  function activeHolds() {
    ex.holds = ex.holds.filter((h) => {
      const next = firstPending(h.automaton);
      return next && !(next.from === h.location && next.time >= h.until);
    });
    return ex.holds.filter((h) => firstPending(h.automaton).from === h.location).sort((a, b) => a.until - b.until);
  }
  function advance(target) {
    for (;;) {
      const holds = activeHolds();
      const held = new Set(holds.map((h) => h.automaton));
      const next = ex.pending.find((p) => !p.done && !held.has(p.automaton));
      const th = holds.length ? holds[0].until : Infinity;
      const tn = next ? next.time : Infinity;
      if (Math.min(th, tn) > target) break;
      if (th <= tn) {
        setNow(th);
        lateMove(holds[0]);
        return;
      }
      next.done = true;
      ex.executed.push(entryOf(next));
      addLog(next.time, `${next.automaton}  ${next.command || "(automatic)"}  ${next.from} → ${next.to}`);
    }
    const left = ex.pending.some((p) => !p.done);
    setNow(left ? target : Math.min(target, end));
    if (!left && ex.now >= end) finish();
  }
  function frame() {
    if (!ex.running) return;
    advance(ex.base + ((performance.now() - ex.t0) / 1000) * ex.speed);
    if (ex.running) ex.raf = requestAnimationFrame(frame);
  }
  function run() {
    if (ex.over || ex.running) return;
    if (active && active !== ex) active.pause();
    active = ex;
    ex.running = true;
    ex.base = ex.now;
    ex.t0 = performance.now();
    if (!ex.started) {
      ex.started = true;
      hint.hidden = false;
      chart.setPick(openReport);
    }
    toggle.textContent = "Stop";
    say(`Executing at ×${ex.speed}.`, true);
    ex.raf = requestAnimationFrame(frame);
  }
  function pause(text = `Stopped at ${clock(Math.floor(ex.now))}.`) {
    if (!ex.running) return;
    ex.running = false;
    cancelAnimationFrame(ex.raf);
    toggle.textContent = "Resume";
    if (text) say(text, true);
  }
  ex.pause = () => pause();
  function end_(text, loud = true) {
    pause("");
    ex.over = true;
    toggle.disabled = true;
    speed.disabled = true;
    closeReport();
    chart.setPick(null);
    hint.hidden = true;
    if (active === ex) active = null;
    say(text, loud);
  }
  function finish() {
    end_(`Goal reached at ${clock(end)}: the execution is over.`);
    toggle.textContent = "Finished";
    addLog(end, "goal reached", "exec-log-done");
  }

  toggle.addEventListener("click", () => (ex.running ? pause() : run()));
  speed.addEventListener("change", () => {
    ex.speed = Number(speed.value);
    ex.base = ex.now;
    ex.t0 = performance.now();
  });

  // --- faults ---
  // What a pick on the timeline points at: the move that would fail, and the stay that would
  // take longer (with its exit), among the transitions not yet dispatched.
  function targetOf(a, d) {
    const pend = (pred) => ex.pending.find((p) => !p.done && p.automaton === a && pred(p)) || null;
    if (d.kind === "segment") {
      const entering = pend((p) => p.to === d.location && near(p.time, +d.start));
      const exit = pend((p) => p.from === d.location && near(p.time, +d.end));
      return { title: `${a} · ${d.location}`, where: `${clock(+d.start)} – ${clock(+d.end)}`,
        move: entering || exit, stay: exit ? { location: d.location, exit } : null };
    }
    if (d.kind === "command") {
      const tr = pend((p) => p.from === d.from && p.to === d.to && near(p.time, +d.time));
      return { title: `${a} · ${d.command}`, where: `at ${clock(+d.time)}`, move: tr,
        stay: tr ? { location: tr.from, exit: tr } : null };
    }
    const next = firstPending(a);
    return { title: a, where: next ? `in ${next.from}, next move at ${clock(next.time)}` : "no move left",
      move: next, stay: next ? { location: next.from, exit: next } : null };
  }

  function closeReport(resume = false) {
    if (!ex.box) return;
    const { node, returnFocus } = ex.box;
    ex.box = null;
    node.remove();
    if (returnFocus?.isConnected) returnFocus.focus();
    if (resume) run();
  }

  function openReport(a, d, anchor) {
    if (ex.over || ex.busy) return;
    // A box opened over another keeps the first one's clock state and focus to return to.
    const wasRunning = ex.box ? ex.box.wasRunning : ex.running;
    const returnFocus = ex.box ? ex.box.returnFocus : document.activeElement;
    pause(null);
    if (ex.box) { ex.box.node.remove(); ex.box = null; }
    const target = targetOf(a, d);
    const node = el("div", { class: "fault-box", role: "dialog", "aria-label": `Report what went wrong: ${target.title}` });
    const head = el("div", { class: "fault-head" });
    head.appendChild(el("strong", {}, target.title));
    const close = el("button", { type: "button", class: "fault-close", "aria-label": "Close" }, "×");
    head.appendChild(close);
    node.append(head, el("p", { class: "fault-where" }, `${target.where} · now ${clock(Math.floor(ex.now))}${wasRunning ? " (paused)" : ""}`));
    if (target.move) {
      const fail = el("button", { type: "button", class: "fault-fail" }, "This move failed");
      fail.addEventListener("click", () => moveFailed(target.move, wasRunning));
      const row = el("div", { class: "fault-action" });
      row.append(fail, el("span", { class: "fault-what" }, `${moveText(target.move)}, due ${clock(target.move.time)}: never taken again; replanned from now`));
      node.appendChild(row);
    }
    if (target.stay) {
      const late = el("button", { type: "button", class: "fault-late" }, "This took longer");
      const input = el("input", { type: "number", min: "1", step: "1", class: "fault-seconds",
        value: String(defaultDelay(end)), "aria-label": "by how many seconds" });
      const what = el("span", { class: "fault-what" });
      const explain = () => {
        what.textContent = `by ${input.value || "?"} s: ${a} leaves ${target.stay.location} then, not at ${clock(target.stay.exit.time)}; replanned then`;
      };
      input.addEventListener("input", explain);
      explain();
      late.addEventListener("click", () => {
        const n = Number(input.value);
        if (!(n > 0)) { input.focus(); return; }
        tookLonger(a, target.stay, n, wasRunning);
      });
      const row = el("div", { class: "fault-action" });
      row.append(late, el("span", {}, " by "), input, el("span", {}, " s "), what);
      node.appendChild(row);
    }
    if (!target.move && !target.stay)
      node.appendChild(el("p", { class: "fault-none" }, "Nothing left to report here: this part is executed, or ends the plan."));
    if (ctx.words) node.appendChild(wordsRow(a, wasRunning));
    close.addEventListener("click", () => closeReport(wasRunning));
    node.addEventListener("keydown", (e) => {
      if (e.key === "Escape") { e.stopPropagation(); closeReport(wasRunning); }
    });
    // In the chart, near the pick, inside the chart's width.
    const host = into.querySelector(".chart") || into;
    host.appendChild(node);
    const hb = host.getBoundingClientRect();
    const w = node.offsetWidth;
    node.style.left = `${Math.max(0, Math.min(anchor.x - hb.left - w / 2, hb.width - w))}px`;
    node.style.top = `${Math.max(0, anchor.y - hb.top + 12)}px`;
    ex.box = { node, wasRunning, returnFocus };
    (node.querySelector(".fault-fail, .fault-late") || close).focus();
  }

  // Anything else, in words ("the door took two minutes to open"): the server's LLM reads it into
  // observed locations and blocked moves (POST /replan with `command`), checked like a request.
  function wordsRow(a, wasRunning) {
    const form = el("form", { class: "fault-action fault-words-row" });
    const input = el("input", { type: "text", class: "fault-words", maxlength: "2000",
      placeholder: `e.g. ${a} is stuck`, "aria-label": "What happened, in words" });
    const tell = el("button", { type: "submit", class: "fault-tell" }, "Tell");
    form.append(el("span", { class: "fault-what" }, "Or say what happened: "), input, tell);
    form.addEventListener("submit", (e) => {
      e.preventDefault();
      const text = input.value.trim();
      if (!text) { input.focus(); return; }
      closeReport();
      addLog(ex.now, `FAULT (in words): ${text}`, "exec-log-fault");
      replan(`“${text}”`, wasRunning, { command: text });
    });
    return form;
  }

  function moveFailed(tr, wasRunning) {
    closeReport();
    ex.blocked.push({ automaton: tr.automaton, from: tr.from, to: tr.to });
    addLog(ex.now, `FAULT ${tr.automaton}: ${moveText(tr)} failed (blocked)`, "exec-log-fault");
    replan(`${tr.automaton}: the move ${moveText(tr)} failed`, wasRunning);
  }

  function tookLonger(a, stay, n, wasRunning) {
    closeReport();
    const h = ex.holds.find((x) => x.automaton === a && x.location === stay.location);
    if (h) h.until += n;
    else ex.holds.push({ automaton: a, location: stay.location, until: stay.exit.time + n });
    const until = (h || ex.holds[ex.holds.length - 1]).until;
    addLog(ex.now, `FAULT ${a}: ${stay.location} takes ${n} s longer (leaves at ${clock(until)})`, "exec-log-fault");
    say(`${a} leaves ${stay.location} at ${clock(until)}, ${until - stay.exit.time} s late: replanned then.`, true);
    if (wasRunning) run();
  }

  // A held move comes late: it happened at the hold's end, and the future is replanned from there.
  function lateMove(h) {
    const tr = firstPending(h.automaton);
    tr.done = true;
    ex.holds = ex.holds.filter((x) => x !== h);
    ex.executed.push({ time: h.until, automaton: tr.automaton, from: tr.from, to: tr.to });
    addLog(h.until, `${tr.automaton}  ${tr.command || "(automatic)"}  ${tr.from} → ${tr.to}  (late: planned at ${clock(tr.time)})`, "exec-log-late");
    replan(`${tr.automaton} left ${tr.from} ${h.until - tr.time} s late`, ex.running);
  }

  // `resume`: the clock ran before the fault, so it runs on in the replanned plan.
  async function replan(reason, resume, extra = {}) {
    pause(null);
    ex.busy = true;
    toggle.disabled = true;
    // The planner counts time in its own ticks: send whole seconds when the plan has them.
    const now = integral ? Math.round(ex.now) : Math.round(ex.now * 1000) / 1000;
    setNow(now);
    say(`Replanning from ${clock(now)}…`, true);
    const body = { now, executed: ex.executed, blocked: ex.blocked,
      trajectory: { events: t.events, transitions: t.transitions }, ...extra };
    if (t.objective?.kind) body.options = { objective: t.objective.kind };
    const carry = { now, executed: [...ex.executed], blocked: [...ex.blocked], holds: ex.holds.map((h) => ({ ...h })),
      speed: ex.speed, running: !!resume, started: true };
    let goesOn = false;
    try {
      goesOn = await ctx.replan(body, { label: `Replan at ${clock(now)}: ${reason}`, carry });
    } catch { goesOn = false; }
    ex.busy = false;
    end_(goesOn ? `Replanned at ${clock(now)}: the execution goes on in the replanned plan below.`
      : `Replanned at ${clock(now)}, with no plan to go on with: the execution stopped.`, false);
    toggle.textContent = goesOn ? "Replanned" : "Stopped";
  }

  if (ex.started) {
    chart.setPick(openReport);
    chart.setNow(ex.now);
  }
  if (carry.running) run();
  else if (ex.started) say(`Stopped at ${clock(Math.floor(ex.now))}; Resume goes on from there.`);
  return { run, pause: () => pause(), state: ex };
}
