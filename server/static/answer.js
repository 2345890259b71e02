// One answer of /plan (or of /replan, wrapped by app.js) drawn into its turn: the verdict, the
// plan in words (state_plan_summary), the explanation of an infeasible plan with its relaxations
// as buttons, the timeline, for a replanned plan its diff against the previous one, the execution
// control (execute.js), the exports, the reasoning and the state plan.
import { renderTimeline, clock, seconds } from "./timeline.js";
import { attachExecution, executable } from "./execute.js";
import { serverRunBlock } from "./serverexec.js";

function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

export function details(summary, text, cls) {
  const d = el("details", cls ? { class: cls } : {});
  d.appendChild(el("summary", {}, summary));
  d.appendChild(el("pre", {}, text));
  return d;
}

function objectiveText(o) {
  if (!o) return "";
  const v = o.value;
  if (v === null || v === undefined) return `${o.kind}: none`;
  if (o.kind === "makespan") return `makespan ${clock(v)} (${seconds(v)})`;
  if (typeof v === "object") return `cost ${v.cost}, makespan ${clock(v.makespan)} (${seconds(v.makespan)})`;
  return `${o.kind} ${v}`;
}

// The verdict after the status: ", verified · cost 7 · goal at 40:30 (2430 s)".
export function verdict(t) {
  const parts = [t.verified ? ", verified" : ""];
  if (t.objective) parts.push(objectiveText(t.objective));
  if (typeof t.goal_reached_at === "number") parts.push(`goal at ${clock(t.goal_reached_at)} (${seconds(t.goal_reached_at)})`);
  if (t.bound !== undefined && t.bound !== null && t.status === "feasible") parts.push(`proven bound ${JSON.stringify(t.bound)}`);
  return parts[0] + parts.slice(1).map((p) => ` · ${p}`).join("");
}

function download(name, type, text) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = el("a", { href: url, download: name });
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

function csvCell(v) {
  const s = v === undefined || v === null ? "" : String(v);
  return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

export function transitionsCsv(t) {
  const rows = [["time_s", "event", "automaton", "from", "to", "command"]];
  for (const tr of t.transitions || []) rows.push([tr.time, tr.event, tr.automaton, tr.from, tr.to, tr.command || ""]);
  return rows.map((r) => r.map(csvCell).join(",")).join("\n") + "\n";
}

async function copyText(text) {
  if (navigator.clipboard && window.isSecureContext) {
    await navigator.clipboard.writeText(text);
    return;
  }
  // Plain http on another host: the Clipboard API is not offered there.
  const ta = el("textarea", { "aria-hidden": "true" });
  ta.value = text;
  ta.style.position = "fixed";
  ta.style.opacity = "0";
  document.body.appendChild(ta);
  ta.select();
  const ok = document.execCommand("copy");
  ta.remove();
  if (!ok) throw new Error("copy refused");
}

function exportsBar(t, statePlan, stamp) {
  const bar = el("div", { class: "exports", role: "group", "aria-label": "Export" });
  if (t) {
    const j = el("button", { type: "button", class: "export-json" }, "Download trajectory (JSON)");
    j.addEventListener("click", () => download(`trajectory-${stamp}.json`, "application/json", JSON.stringify(t, null, 2) + "\n"));
    bar.appendChild(j);
    if ((t.transitions || []).length) {
      const c = el("button", { type: "button", class: "export-csv" }, "Download transitions (CSV)");
      c.addEventListener("click", () => download(`transitions-${stamp}.csv`, "text/csv", transitionsCsv(t)));
      bar.appendChild(c);
    }
  }
  if (statePlan) {
    const s = el("button", { type: "button", class: "copy-plan" }, "Copy state plan");
    const note = el("span", { class: "copy-note", role: "status" });
    s.addEventListener("click", async () => {
      try {
        await copyText(JSON.stringify(statePlan, null, 2));
        note.textContent = "copied";
      } catch {
        note.textContent = "could not copy: open “State plan” below and copy it from there";
      }
      setTimeout(() => { note.textContent = ""; }, 4000);
    });
    bar.append(s, note);
  }
  return bar;
}

// The parts a conflict names, highlighted in the plan-in-words list (and listed by pointer when
// the answer has no words for them).
function explanationBlock(ex, words, followUp) {
  const box = el("div", { class: "explanation", role: "group", "aria-label": "Why there is no plan" });
  box.appendChild(el("h3", {}, "Why there is no plan"));
  for (const c of ex.conflicts || []) {
    const p = el("div", { class: "conflict" });
    p.appendChild(el("p", {}, c.text || "These parts cannot hold together:"));
    const ul = el("ul", { class: "conflict-parts" });
    for (const ptr of c.constraints || []) {
      const li = el("li", { "data-pointer": ptr });
      const w = (words || []).find((x) => x.pointer === ptr);
      li.appendChild(el("mark", {}, w ? w.text : ptr));
      if (w) li.appendChild(el("code", {}, ` ${ptr}`));
      ul.appendChild(li);
    }
    p.appendChild(ul);
    box.appendChild(p);
  }
  if ((ex.relaxations || []).length) {
    box.appendChild(el("p", { class: "relax-intro" }, "Any one of these would make it feasible (sent as a follow-up):"));
    const bar = el("div", { class: "relaxations" });
    for (const r of ex.relaxations) {
      const b = el("button", { type: "button", class: "relax" }, r.text);
      b.title = (r.changes || []).map((ch) => `${ch.pointer} → ${ch.value === null ? "dropped" : JSON.stringify(ch.value)}`).join("; ");
      b.addEventListener("click", () => followUp(r.text));
      bar.appendChild(b);
    }
    box.appendChild(bar);
  }
  return box;
}

function wordsList(words, conflictPointers) {
  const box = el("div", { class: "plan-words" });
  box.appendChild(el("h3", {}, "The plan in words"));
  const ul = el("ul");
  for (const w of words) {
    const li = el("li", { "data-pointer": w.pointer }, w.text);
    if (conflictPointers.has(w.pointer)) li.classList.add("in-conflict");
    ul.appendChild(li);
  }
  box.appendChild(ul);
  return box;
}

// A replanned future against the previous plan's (the answer's diff): counts, then every moved,
// added and dropped transition.
function diffBlock(t, previousGoal) {
  const d = t.diff;
  const box = el("div", { class: "diff", role: "group", "aria-label": "Against the previous plan" });
  box.appendChild(el("h3", {}, "Against the previous plan"));
  const counts = ["kept", "moved", "added", "dropped"].map((k) => `${(d[k] || []).length} ${k}`).join(" · ");
  const goal = typeof t.goal_reached_at === "number" && typeof previousGoal === "number" && t.goal_reached_at !== previousGoal
    ? `goal ${clock(t.goal_reached_at)} (was ${clock(previousGoal)}) · ` : "";
  box.appendChild(el("p", { class: "diff-counts" }, goal + counts));
  const ul = el("ul", { class: "diff-items" });
  const what = (x) => `${x.automaton} ${x.command || "(automatic)"}: ${x.from} → ${x.to}`;
  for (const x of d.moved || []) ul.appendChild(item("moved", `${what(x)}, ${clock(x.time_before)} → ${clock(x.time_after)}`));
  for (const x of d.added || []) ul.appendChild(item("added", `${what(x)} at ${clock(x.time_after)}`));
  for (const x of d.dropped || []) ul.appendChild(item("dropped", `${what(x)}, was at ${clock(x.time_before)}`));
  if (ul.childNodes.length) box.appendChild(ul);
  return box;

  function item(kind, text) {
    const li = el("li", { class: `diff-${kind}` });
    li.append(el("span", { class: "diff-kind" }, kind), document.createTextNode(` ${text}`));
    return li;
  }
}

// What the planner's search among plans did (controllability.search: plans_cut, stopped): "" when
// there was none.
function searchText(search, plan) {
  if (!search) return "";
  const n = search.plans_cut || 0;
  const plans = `${n} plan${n === 1 ? "" : "s"}`;
  const parts = [];
  if (!plan) parts.push(`No plan is robust: the planner set aside ${plans} that some outcome would break` +
    (search.proven ? " and found none left." : "."));
  else if (n > 0) parts.push(`The planner set aside ${plans} that some outcome would break.`);
  if (search.stopped) parts.push(`It stopped looking (${search.stopped})${plan ? ": this plan is not robust" : ""}.`);
  return parts.join(" ");
}

// The plan's flexibility (contract section 13): whether it is robust, and to what, and each
// transition's window (earliest and latest time over every schedule the network allows). Without
// a plan (no network), only what the search among plans did, if anything (null: nothing to say).
export function flexibilityBlock(t) {
  const c = t.controllability || {};
  const net = t.network || {};
  const contingent = (net.links || []).some((l) => l.kind === "contingent");
  let robust;
  if (!t.network && !c.note) {
    robust = searchText(c.search, false);
    if (!robust) return null;
  } else if (c.note) robust = `No flexible plan: ${c.note}.`;
  else if (!contingent) robust = "Every duration is the plan's own: any time within the windows below keeps the plan valid.";
  else if (c.strong) robust = "Robust to every outcome of the uncertain durations with fixed times (strongly controllable).";
  else if (c.dynamic) robust = "Robust to every outcome of the uncertain durations when the next steps wait for what happened (dynamically controllable, not with fixed times).";
  else robust = "Not robust: some outcomes of the uncertain durations break it.";
  if (c.success_probability) robust += ` Chance of success: ${Math.round(c.success_probability.value * 1000) / 10} %` +
    (c.success_probability.samples ? ` (${c.success_probability.samples} draws).` : " (exact).");
  if (t.network && c.search) robust += ` ${searchText(c.search, true)}`;
  robust = robust.trim();
  const box = el("details", { class: "flexibility" });
  box.appendChild(el("summary", {}, "Flexibility"));
  box.appendChild(el("p", { class: "robustness" }, robust));
  const points = new Map((net.points || []).map((p) => [p.id, p]));
  const list = el("ul", { class: "windows", "aria-label": "Windows" });
  for (const w of t.slack || []) {
    const p = points.get(w.point);
    if (!p || !p.automaton) continue;
    const what = `${p.automaton} ${p.command || `${p.from} → ${p.to}`}${p.kind === "contingent" ? " (uncertain)" : ""}`;
    const latest = w.latest === null ? "open" : seconds(w.latest);
    list.appendChild(el("li", { "data-point": String(w.point) }, `${what}: ${seconds(w.earliest)} – ${latest}`));
  }
  box.appendChild(list);
  return box;
}

// What the LLM read in a fault reported in words (a /replan answer's `report`): its restatement,
// then the facts the replan took from it.
function reportBlock(r) {
  const box = el("div", { class: "report", role: "note", "aria-label": "The report, as understood" });
  box.appendChild(el("p", { class: "report-restatement" }, `Understood: “${r.restatement || r.command}”`));
  const facts = el("ul", { class: "report-facts" });
  for (const b of r.blocked || []) facts.appendChild(el("li", {}, `${b.automaton}: ${b.from} → ${b.to} blocked`));
  for (const [a, o] of Object.entries(r.observed || {}))
    facts.appendChild(el("li", {}, `${a} observed in ${o.location}` + (typeof o.since === "number" ? ` since ${clock(o.since)}` : "")));
  if (facts.children.length) box.appendChild(facts);
  return box;
}

// Draws `data` (a /plan answer) into `into`. ctx: {domainInfo, followUp(command), execution?,
// serverRun? ({domain}: the plan may be run on the server, serverexec.js)}
// (execution: execute.js's context; without it the plan cannot be executed from this turn).
export function renderAnswer(into, data, ctx) {
  const t = data.trajectory || {};
  const words = t.state_plan_summary || data.state_plan_summary || [];
  const ex = t.explanation || data.explanation;
  const warnings = [...(data.warnings || []), ...(t.warnings || [])];
  const summary = el("div", { class: `summary status-${t.status}` });
  summary.appendChild(el("span", { class: "badge" }, t.status || "?"));
  summary.appendChild(document.createTextNode(verdict(t)));
  into.appendChild(summary);
  if (t.stats) {
    const s = t.stats;
    into.appendChild(el("div", { class: "stats" },
      `solved in ${seconds((s.solve_ms || 0) / 1000)}` + (t.horizon !== undefined ? ` · ${t.horizon} events` : "") +
      (s.parts ? ` · ${s.parts} independent parts` : "") +
      (typeof t.now === "number" ? ` · replanned from ${clock(t.now)}` : "")));
  }
  if (t.report) into.appendChild(reportBlock(t.report));
  if (warnings.length) {
    const w = el("ul", { class: "warnings", "aria-label": "Warnings" });
    for (const x of warnings) w.appendChild(el("li", {}, (x.path ? `${x.path}: ` : "") + x.message));
    into.appendChild(w);
  }
  const conflictPointers = new Set((ex?.conflicts || []).flatMap((c) => c.constraints || []));
  const body = el("div", { class: "answer-body" });
  if (words.length) body.appendChild(wordsList(words, conflictPointers));
  if (ex && t.status === "infeasible") body.appendChild(explanationBlock(ex, words, ctx.followUp));
  if (body.childNodes.length) into.appendChild(body);
  const canRun = !!ctx.execution && executable(t);
  let api = null;
  if (t.timelines && Object.keys(t.timelines).length) {
    const chart = el("div", { class: "chart" });
    into.appendChild(chart);
    api = renderTimeline(chart, t, data.state_plan, ctx.domainInfo, { history: t.now, diff: t.diff,
      previousGoal: data.previous_goal, executable: canRun });
    // Hovering a sentence of the plan in words lights up its bracket.
    for (const li of into.querySelectorAll(".plan-words li[data-pointer]")) {
      const on = (v) => () => {
        for (const b of chart.querySelectorAll(`.bracket[data-pointer="${CSS.escape(li.dataset.pointer)}"]`)) b.classList.toggle("lit", v);
      };
      li.addEventListener("mouseenter", on(true));
      li.addEventListener("mouseleave", on(false));
    }
  }
  if (api && canRun) attachExecution(into, t, api, ctx.execution);
  if (canRun && ctx.serverRun && data.state_plan) into.appendChild(serverRunBlock(data, ctx.serverRun));
  if (t.diff) into.appendChild(diffBlock(t, data.previous_goal));
  const flex = t.network || t.controllability ? flexibilityBlock(t) : null;
  if (flex) {
    into.appendChild(flex);
    // Hovering a window in the list lights up its band on the timeline.
    for (const li of flex.querySelectorAll(".windows li[data-point]")) {
      const band = () => into.querySelector(`.chart g.window[data-point="${CSS.escape(li.dataset.point)}"]`);
      li.addEventListener("mouseenter", () => band()?.classList.add("lit"));
      li.addEventListener("mouseleave", () => band()?.classList.remove("lit"));
    }
  }
  const stamp = new Date().toISOString().replace(/[:.]/g, "-").slice(0, 19);
  into.appendChild(exportsBar(data.trajectory, data.state_plan, stamp));
  if (data.reasoning) into.appendChild(details("Reasoning", data.reasoning, "reasoning"));
  if (data.state_plan) into.appendChild(details("State plan", JSON.stringify(data.state_plan, null, 2), "state-plan"));
}

// A turn the server remembers but this browser has no whole answer for (GET /sessions/{id}):
// its verdict, reasoning and state plan, without a chart.
export function renderRemembered(into, turn) {
  const s = turn.trajectory_summary || {};
  const line = el("div", { class: `summary status-${s.status}` });
  line.appendChild(el("span", { class: "badge" }, s.status || "answered"));
  line.appendChild(document.createTextNode(verdict(s)));
  into.appendChild(line);
  into.appendChild(el("p", { class: "note" }, "Kept by the server without its timeline; send the command again to redraw it."));
  if (turn.reasoning) into.appendChild(details("Reasoning", turn.reasoning, "reasoning"));
  if (turn.state_plan) {
    into.appendChild(exportsBar(null, turn.state_plan, "restored"));
    into.appendChild(details("State plan", JSON.stringify(turn.state_plan, null, 2), "state-plan"));
  }
}
