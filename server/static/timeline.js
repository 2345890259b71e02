// The trajectory as a timeline (hand-written SVG, no library): one row per automaton with a
// coloured segment per location, each automaton's commanded transitions as labelled markers on
// a row of their own, episodes and temporal constraints as brackets with their bounds and the
// achieved value, the goal as a dashed line, round ticks (m:ss or h:mm:ss) with gridlines, a
// legend, hover and tap cards, zoom and pan. It is drawn for the width of its container and
// redrawn when that changes, so it never makes the page scroll sideways. Where the answer has
// `slack` (contract section 13), each transition's window (when it may happen without breaking
// the plan) is a translucent band under its automaton's row and commands, one lane per window,
// with the transition's planned time marked in it; an open window fades out at the chart's right
// edge.
//
//   renderTimeline(container, trajectory, statePlan, domain, opts) -> {wrap, legend, table,
//     stage, redraw, setNow(t), setPick(fn)}
// `statePlan` gives the bounds (may be null); `domain` (GET /domains/{name}) gives each
// automaton's locations in order, so a location keeps its colour from plan to plan (may be null).
// opts (all optional), for execution (execute.js) and replanned answers: `history`, the time up
// to which the plan is history (a replan's `now`): that part is drawn hatched and marked;
// `diff`, the answer's diff against the previous plan: added and moved commands are marked, and
// the previous plan's dropped and moved commands are drawn hollow at their old times;
// `previousGoal`, the previous plan's goal time, drawn as a faint line. setNow(t) moves the "now"
// line (null hides it); setPick(fn) makes a click or tap on a row (segment, command, or the
// row's name, which then takes the keyboard focus) call fn(automaton, data, anchor) instead of
// opening a card (null: cards again); anchor is {x, y} in the page.

const SVG = "http://www.w3.org/2000/svg";

// 20 colours that stay apart from each other (Tableau 20, reordered so neighbours differ).
const PALETTE = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#b07aa1", "#76b7b2", "#edc948",
  "#9c755f", "#ff9da7", "#499894", "#86bcb6", "#d37295", "#a0cbe8", "#8cd17d", "#b6992d",
  "#ffbe7d", "#79706e", "#f1ce63", "#d4a6c8", "#bab0ac"];

function svgEl(tag, attrs = {}, text) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

function htmlEl(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

// Seconds as m:ss, or h:mm:ss from an hour on; fractions kept to a tenth.
export function clock(t, longForm = false) {
  const neg = t < 0;
  t = Math.abs(t);
  const whole = Math.floor(t + 1e-9);
  const frac = t - whole > 1e-6 ? (Math.round((t - whole) * 10) / 10).toString().slice(1) : "";
  const h = Math.floor(whole / 3600), m = Math.floor((whole % 3600) / 60), s = whole % 60;
  const pad = (n) => String(n).padStart(2, "0");
  const body = h > 0 || longForm ? `${h}:${pad(m)}:${pad(s)}` : `${m}:${pad(s)}`;
  return (neg ? "-" : "") + body + frac;
}

export function seconds(t) {
  return `${Number.isInteger(t) ? t : Math.round(t * 100) / 100} s`;
}

// A tick step giving about `count` ticks over `span` seconds, from round values.
function tickStep(span, count) {
  const steps = [1, 2, 5, 10, 15, 30, 60, 120, 300, 600, 900, 1200, 1800, 3600, 7200, 10800,
    21600, 43200, 86400];
  const raw = span / Math.max(1, count);
  if (raw < 1) {
    for (const s of [0.1, 0.2, 0.5]) if (s >= raw) return s;
    return 1;
  }
  for (const s of steps) if (s >= raw) return s;
  return Math.ceil(raw / 86400) * 86400;
}

// Black or white text, whichever contrasts more with the fill (WCAG relative luminance).
function textOn(hex) {
  const c = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16) / 255)
    .map((v) => (v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4));
  const l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
  return (l + 0.05) / 0.05 > 1.05 / (l + 0.05) ? "#111" : "#fff";
}

let measureCtx = null;
function textWidth(text, px = 11, weight = "normal") {
  measureCtx = measureCtx || document.createElement("canvas").getContext("2d");
  measureCtx.font = `${weight} ${px}px system-ui, sans-serif`;
  return measureCtx.measureText(text).width;
}

// Colour per (automaton, location): the location's index in the domain, else first appearance.
function colours(t, domain) {
  const out = {};
  for (const [name, segs] of Object.entries(t.timelines || {})) {
    const known = domain?.automata?.find((a) => a.name === name)?.locations || [];
    const order = [...known];
    for (const s of segs) if (!order.includes(s.location)) order.push(s.location);
    out[name] = {};
    order.forEach((loc, i) => { out[name][loc] = PALETTE[i % PALETTE.length]; });
  }
  return out;
}

// The command (if any) that moved `automaton` into the segment starting at `start`.
function enteringCommand(t, automaton, seg) {
  const tr = (t.transitions || []).find((x) => x.automaton === automaton && x.to === seg.location &&
                                               Math.abs(x.time - seg.start) < 1e-9);
  return tr ? tr.command || "(automatic)" : seg.start === 0 ? "(initial)" : "";
}

function bound(v) { return v === null || v === undefined ? "∞" : v; }

// Episodes and temporal constraints with what the plan achieved: [{kind, name, from, to, lo, hi,
// achieved, label}].
export function constraintBrackets(t, sp) {
  const out = [];
  const spc = sp?.constraints || {};
  for (const [name, e] of Object.entries(t.episodes || {})) {
    const c = spc.episodes?.[name] || {};
    const achieved = e.end - e.start;
    out.push({ kind: "episode", name, from: e.start, to: e.end, lo: c.lower_bound, hi: c.upper_bound,
      achieved, label: `${name} lasts [${bound(c.lower_bound)}, ${bound(c.upper_bound)}] s: ${seconds(achieved)}` });
  }
  for (const [name, e] of Object.entries(t.temporal || {})) {
    const c = spc.temporal?.[name] || {};
    const achieved = Math.abs(e.event2 - e.event1);
    // An order (contract section 15: actions as its events, or "ordered") has a lower bound of 0
    // unless it says otherwise; an ordered one is drawn as an arrow from event 1 to event 2.
    const order = c.event1 !== undefined || c.event2 !== undefined || c.ordered === true;
    const lo = c.lower_bound ?? (order ? 0 : undefined);
    out.push({ kind: "temporal", name, from: Math.min(e.event1, e.event2), to: Math.max(e.event1, e.event2),
      lo, hi: c.upper_bound, achieved, event1: e.event1, event2: e.event2, ordered: c.ordered === true,
      label: `${name} within [${bound(lo)}, ${bound(c.upper_bound)}] s: ${seconds(achieved)}` });
  }
  return out;
}

// The state plan's action events (contract section 15) that a command marker is: names of the
// actions of `automaton` given by this command (or by its from/to).
export function actionsOf(sp, tr) {
  const acts = sp?.constraints?.actions || {};
  return Object.entries(acts).filter(([, a]) => a.automaton === tr.automaton &&
    (a.command === undefined || a.command === tr.command) &&
    (a.from === undefined || a.from === tr.from) && (a.to === undefined || a.to === tr.to))
    .map(([n]) => n);
}

// Each transition's window (the answer's `slack` over `network.points`): [{tr, point,
// contingent, earliest, latest}] in the points' order, latest null when open. Windows of a single
// instant are left out. A point is the first transition not yet matched of its automaton with its
// from and to (an automaton's points follow its transitions in order); an unmatched one is skipped.
export function windowsOf(t) {
  const points = new Map((t.network?.points || []).map((p) => [p.id, p]));
  const trs = t.transitions || [];
  const used = new Set();
  const out = [];
  for (const w of [...(t.slack || [])].sort((a, b) => a.point - b.point)) {
    const p = points.get(w.point);
    if (!p?.automaton || typeof w.earliest !== "number") continue;
    const i = trs.findIndex((tr, k) => !used.has(k) && tr.automaton === p.automaton && tr.from === p.from && tr.to === p.to);
    if (i < 0) continue;
    used.add(i);
    const latest = typeof w.latest === "number" ? w.latest : null;
    if (latest !== null && latest - w.earliest < 1e-9) continue;
    out.push({ tr: trs[i], point: w.point, contingent: p.kind === "contingent", earliest: w.earliest, latest });
  }
  return out;
}

const num = (v) => String(Number.isInteger(v) ? v : Math.round(v * 100) / 100);

// "robot1 outside → goingToDoor1: any time 0–2 s"; a contingent point says that nature picks it.
export function windowText(w) {
  const span = w.latest === null ? `from ${num(w.earliest)} s on` : `${num(w.earliest)}–${num(w.latest)} s`;
  const what = `${w.tr.automaton} ${w.tr.from} → ${w.tr.to}`;
  return w.contingent ? `${what} (uncertain): nature picks it, any time ${span}` : `${what}: any time ${span}`;
}

// Greedy lanes: items sorted by x0 go to the first lane whose last item ended before them.
function lanes(items) {
  const ends = [];
  for (const it of [...items].sort((a, b) => a.x0 - b.x0)) {
    let k = ends.findIndex((e) => e <= it.x0);
    if (k < 0) { k = ends.length; ends.push(0); }
    ends[k] = it.x1;
    it.lane = k;
  }
  return Math.max(1, ends.length);
}

// The diff's marks: "added" or "moved" per new command ("automaton|from|to|time"), and the
// previous plan's moved and dropped commands as ghosts at their old times.
function diffMarks(diff) {
  const marks = new Map();
  const ghosts = [];
  for (const kind of ["added", "moved"])
    for (const d of diff?.[kind] || []) marks.set(`${d.automaton}|${d.from}|${d.to}|${d.time_after}`, { kind, before: d.time_before });
  for (const kind of ["moved", "dropped"])
    for (const d of diff?.[kind] || [])
      if (d.command && typeof d.time_before === "number") ghosts.push({ ...d, kind, time: d.time_before });
  return { marks, ghosts };
}

export function renderTimeline(container, t, sp, domain, opts = {}) {
  const names = Object.keys(t.timelines || {});
  const colour = colours(t, domain);
  let lastEnd = 0;
  for (const segs of Object.values(t.timelines || {})) for (const s of segs) lastEnd = Math.max(lastEnd, s.end);
  const goal = typeof t.goal_reached_at === "number" ? t.goal_reached_at : null;
  const history = typeof opts.history === "number" ? opts.history : null;
  const prevGoal = typeof opts.previousGoal === "number" && opts.previousGoal !== goal ? opts.previousGoal : null;
  const { marks: diffMark, ghosts } = diffMarks(opts.diff);
  const full = Math.max(1, goal ?? 0, lastEnd, prevGoal ?? 0, ...ghosts.map((g) => g.time));
  const brackets = constraintBrackets(t, sp);
  const longForm = full >= 3600;
  // Windows per automaton, in lanes fixed in time (so zooming does not reshuffle them); windows
  // that only touch keep apart.
  const windows = windowsOf(t);
  const winRows = Object.fromEntries(names.map((name) => {
    const items = windows.filter((w) => w.tr.automaton === name)
      .map((w) => ({ w, x0: w.earliest, x1: w.latest === null ? Infinity : w.latest + 1e-6 }));
    return [name, { items, lanes: items.length ? lanes(items) : 0 }];
  }));

  const wrap = htmlEl("div", { class: "timeline-wrap" });
  const tools = htmlEl("div", { class: "timeline-tools", role: "toolbar", "aria-label": "Timeline zoom" });
  const zoomOut = htmlEl("button", { type: "button", "aria-label": "Zoom out" }, "−");
  const zoomIn = htmlEl("button", { type: "button", "aria-label": "Zoom in" }, "+");
  const fit = htmlEl("button", { type: "button", "aria-label": "Show the whole plan" }, "Fit");
  const range = htmlEl("span", { class: "timeline-range", "aria-live": "polite" });
  tools.append(zoomOut, zoomIn, fit, range);
  const stage = htmlEl("div", {
    class: "timeline-stage", tabindex: "0", role: "region",
    "aria-label": "Timeline. Arrow keys pan, plus and minus zoom, 0 shows the whole plan.",
  });
  // The card repeats what "Timeline as a table" says; screen readers read the table instead.
  const card = htmlEl("div", { class: "timeline-card", "aria-hidden": "true", hidden: "" });
  stage.appendChild(card);
  wrap.append(tools, stage);

  // The legend: per automaton, the locations the plan visits, in colour order.
  const legend = htmlEl("div", { class: "legend", "aria-label": "Legend" });
  for (const name of names) {
    const group = htmlEl("div", { class: "legend-group" });
    group.appendChild(htmlEl("span", { class: "legend-automaton" }, name));
    const visited = [...new Set(t.timelines[name].map((s) => s.location))]
      .sort((a, b) => Object.keys(colour[name]).indexOf(a) - Object.keys(colour[name]).indexOf(b));
    for (const loc of visited) {
      const item = htmlEl("span", { class: "legend-item", "data-automaton": name, "data-location": loc });
      const sw = htmlEl("span", { class: "swatch", "aria-hidden": "true" });
      sw.style.background = colour[name][loc];
      item.append(sw, document.createTextNode(loc));
      group.appendChild(item);
    }
    legend.appendChild(group);
  }
  const marks = htmlEl("div", { class: "legend-group legend-marks", "aria-hidden": "true" });
  marks.innerHTML = '<span class="legend-item"><svg width="12" height="12"><path d="M6 1 L11 6 L6 11 L1 6 Z" fill="#1d2330"/></svg>command</span>' +
    '<span class="legend-item"><svg width="16" height="12"><line x1="8" y1="0" x2="8" y2="12" stroke="#b3261e" stroke-width="2" stroke-dasharray="3 2"/></svg>goal</span>' +
    '<span class="legend-item"><svg width="22" height="12"><path d="M1 10 V4 H21 V10" fill="none" stroke="#3b4a6b" stroke-width="1.5"/></svg>constraint: bounds and achieved</span>';
  const spc = sp?.constraints || {};
  if (windows.length)
    marks.innerHTML += '<span class="legend-item legend-window"><svg width="22" height="12"><rect x="1" y="3" width="20" height="6" class="window-band"/><rect x="1" y="3" width="1.5" height="6" class="window-edge"/></svg>window: when it may happen</span>';
  if (windows.some((w) => w.contingent))
    marks.innerHTML += '<span class="legend-item legend-window contingent"><svg width="22" height="12"><rect x="1" y="3" width="20" height="6" class="window-band"/><rect x="1" y="3" width="1.5" height="6" class="window-edge"/></svg>uncertain: nature picks when</span>';
  if (Object.keys(spc.actions || {}).length)
    marks.innerHTML += '<span class="legend-item"><svg width="12" height="12"><path d="M6 1 L11 6 L6 11 L1 6 Z" fill="#1d2330" stroke="#b35c00" stroke-width="2"/></svg>a named action</span>';
  if (Object.values(spc.temporal || {}).some((c) => c.ordered === true))
    marks.innerHTML += '<span class="legend-item"><svg width="22" height="12"><path d="M1 6 H20 M15 2 L20 6 L15 10" fill="none" stroke="#3b4a6b" stroke-width="1.5"/></svg>first, then</span>';
  if (history !== null || opts.executable)
    marks.innerHTML += '<span class="legend-item"><svg width="16" height="12"><rect width="16" height="12" fill="#e9ebf0"/><path d="M0 12 L12 0 M4 12 L16 0 M-4 4 L4 -4 M12 16 L20 8" stroke="#5a6378" stroke-width="1.2"/></svg>executed</span>' +
      '<span class="legend-item"><svg width="10" height="12"><line x1="5" y1="0" x2="5" y2="12" stroke="#1f5fbf" stroke-width="2"/></svg>now</span>';
  if (ghosts.length || prevGoal !== null)
    marks.innerHTML += '<span class="legend-item"><svg width="12" height="12"><path d="M6 1 L11 6 L6 11 L1 6 Z" fill="#fff" stroke="#6b7386" stroke-width="1.2"/></svg>previous plan (moved or dropped)</span>' +
      '<span class="legend-item"><svg width="12" height="12"><path d="M6 1 L11 6 L6 11 L1 6 Z" fill="#1b6e3a"/></svg>new command</span>' +
      '<span class="legend-item"><svg width="12" height="12"><path d="M6 1 L11 6 L6 11 L1 6 Z" fill="#8a5300"/></svg>moved command</span>';
  legend.appendChild(marks);
  wrap.appendChild(legend);

  // The same facts as a table, for screen readers and keyboard users.
  const table = htmlEl("details", { class: "timeline-table" });
  table.appendChild(htmlEl("summary", {}, "Timeline as a table"));
  const tbl = htmlEl("table");
  tbl.innerHTML = "<thead><tr><th scope=col>automaton</th><th scope=col>location</th><th scope=col>start</th>" +
    "<th scope=col>end</th><th scope=col>duration</th><th scope=col>entered by</th></tr></thead>";
  const tb = htmlEl("tbody");
  for (const name of names) for (const s of t.timelines[name]) {
    const tr = htmlEl("tr");
    for (const v of [name, s.location, clock(s.start, longForm), clock(s.end, longForm), seconds(s.end - s.start),
      enteringCommand(t, name, s)]) tr.appendChild(htmlEl("td", {}, String(v)));
    tb.appendChild(tr);
  }
  tbl.appendChild(tb);
  table.appendChild(tbl);
  wrap.appendChild(table);
  container.appendChild(wrap);

  let view = [0, full];
  let pinned = null;  // the element whose card was opened by a tap or click
  let svg = null;
  let geom = { labelW: 0, plotW: 1 };
  let nowT = null;    // the moving "now" of an execution (setNow)
  let pick = null;    // setPick's callback
  let nowEls = null;  // the shading, line and label drawn by the last draw(), moved by setNow

  function showCard(lines, x, y) {
    card.replaceChildren();
    for (const [i, l] of lines.entries()) card.appendChild(htmlEl(i ? "div" : "strong", {}, l));
    card.hidden = false;
    const w = stage.clientWidth;
    card.style.left = `${Math.max(4, Math.min(x + 12, w - card.offsetWidth - 4))}px`;
    card.style.top = `${Math.max(4, y + 14)}px`;
  }
  function hideCard() { card.hidden = true; pinned = null; }

  function cardFor(node) {
    const d = node.dataset;
    if (d.kind === "segment") {
      const s = { location: d.location, start: +d.start, end: +d.end };
      const cmd = enteringCommand(t, d.automaton, s);
      return [`${d.automaton}: ${d.location}`, `start ${clock(s.start, longForm)} (${seconds(s.start)})`,
        `end ${clock(s.end, longForm)} (${seconds(s.end)})`, `duration ${seconds(s.end - s.start)}`,
        cmd ? `entered by ${cmd}` : ""].filter(Boolean);
    }
    if (d.kind === "command")
      return [`${d.automaton}: ${d.command}`, `at ${clock(+d.time, longForm)} (${seconds(+d.time)})`,
        `${d.from} → ${d.to}`, `event ${d.event}`,
        d.diff === "added" ? "new in this plan" : d.diff === "moved" ? `moved from ${clock(+d.before, longForm)}` : ""].filter(Boolean);
    if (d.kind === "ghost")
      return [`${d.automaton}: ${d.command}`, d.diff === "dropped"
        ? `dropped: the previous plan had it at ${clock(+d.time, longForm)}`
        : `moved: ${clock(+d.time, longForm)} → ${clock(+d.after, longForm)}`, `${d.from} → ${d.to}`];
    if (d.kind === "previous-goal") return ["the previous plan's goal", `at ${clock(prevGoal, longForm)} (${seconds(prevGoal)})`];
    if (d.kind === "bracket") {
      const b = brackets[+d.index];
      return [b.label, `${b.kind === "episode" ? "from" : "between"} ${clock(b.from, longForm)} and ${clock(b.to, longForm)}`,
        b.kind === "temporal" ? `event 1 at ${seconds(b.event1)}, event 2 at ${seconds(b.event2)}` : ""].filter(Boolean);
    }
    if (d.kind === "window") {
      const w = windows.find((x) => x.point === +d.point);
      if (!w) return null;
      return [`${w.tr.automaton}: ${w.tr.from} → ${w.tr.to}`, w.tr.command ? `command ${w.tr.command}` : "",
        windowText(w).replace(/^.*?: /, ""),
        `planned at ${clock(w.tr.time, longForm)} (${seconds(w.tr.time)})`].filter(Boolean);
    }
    if (d.kind === "goal") return ["goal reached", `at ${clock(goal, longForm)} (${seconds(goal)})`];
    return null;
  }

  // A previous plan's command: a hollow diamond at its old time, its label struck through when it
  // was dropped; a moved one is joined by a dashed line to where it went.
  function ghostMark(it, ly, r, rowH, laneY) {
    const g = it.tr;
    const el = svgEl("g", { class: `ghost ghost-${g.kind}`, "data-kind": "ghost", "data-automaton": r.name,
      "data-command": g.command, "data-time": g.time, "data-from": g.from, "data-to": g.to, "data-diff": g.kind });
    if (g.kind === "moved") {
      el.dataset.after = g.time_after;
      const to = r.cmd.items.find((o) => !o.tr.ghost && o.tr.from === g.from && o.tr.to === g.to && o.tr.time === g.time_after);
      if (to) el.appendChild(svgEl("path", { d: `M ${it.px} ${ly} L ${to.px} ${laneY(to)}`, class: "ghost-link" }));
    }
    el.appendChild(svgEl("path", { d: `M ${it.px} ${ly - 5} l 5 5 l -5 5 l -5 -5 z`, class: "ghost-mark" }));
    if (g.kind === "dropped")
      el.appendChild(svgEl("text", { x: it.left ? it.x0 + 2 : it.px + 7, y: ly + 4, class: "command-label ghost-label" }, g.command));
    return el;
  }

  // The executed part (hatched, over the rows) and the "now" line with its label on the axis.
  function drawNow(s, plot, gm) {
    const end = nowT ?? history;
    if (end === null) return null;
    const shade = svgEl("rect", { x: gm.x(0), y: gm.top - 4, height: Math.max(0, gm.bandY - gm.top), class: "past",
      fill: `url(#hatch-${uid})`, "pointer-events": "none" });
    plot.appendChild(shade);
    const line = svgEl("line", { y1: gm.top - 6, y2: gm.axisY - 2, class: nowT === null ? "now-line history-line" : "now-line" });
    const bg = svgEl("rect", { y: gm.axisY, height: gm.font + 4, rx: 3, class: "now-label-bg" });
    const label = svgEl("text", { y: gm.axisY + gm.font, class: "now-label" });
    s.append(line, bg, label);
    const els = { shade, line, bg, label, gm };
    placeNow(els, end);
    return els;
  }

  function placeNow(els, end) {
    const { gm } = els;
    const px = gm.x(end);
    const inView = px >= gm.labelW - 1 && px <= gm.labelW + gm.plotW + 1;
    els.shade.setAttribute("width", Math.max(0, px - gm.x(0)));
    els.line.setAttribute("x1", px);
    els.line.setAttribute("x2", px);
    const text = nowT === null ? `replanned at ${clock(end, longForm)}` : `now ${clock(Math.floor(end), longForm)}`;
    els.label.textContent = text;
    const w = textWidth(text, gm.font, "600") + 8;
    const lx = Math.max(gm.labelW, Math.min(px - w / 2, gm.width - w - 2));
    els.bg.setAttribute("x", lx);
    els.bg.setAttribute("width", w);
    els.label.setAttribute("x", lx + 4);
    for (const e of [els.line, els.bg, els.label]) e.setAttribute("visibility", inView ? "visible" : "hidden");
  }

  function draw() {
    const width = Math.max(240, stage.clientWidth || container.clientWidth || 600);
    const small = width < 520;
    const font = small ? 10 : 11;
    const hasCommands = (t.transitions || []).some((tr) => tr.command) || ghosts.length > 0;
    const labelW = Math.min(small ? 64 : 120, Math.max(36, textWidth(hasCommands ? "commands" : "", font - 1) + 10,
      textWidth(windows.length ? "windows" : "", font - 1) + 10,
      ...names.map((n) => textWidth(n, font, "600") + 10)));
    const right = 8, top = 20, pad = 8;  // pad: inside the plot, so marks at its ends stay whole
    const plotW = width - labelW - right;
    geom = { labelW: labelW + pad, plotW: plotW - 2 * pad };
    const [v0, v1] = view;
    const x = (time) => labelW + pad + ((time - v0) / (v1 - v0)) * (plotW - 2 * pad);
    const clipX = (px) => Math.max(labelW, Math.min(labelW + plotW, px));
    const rowH = small ? 22 : 26;

    // Command markers per automaton, their labels stacked in lanes so none overlap.
    const cmdRows = names.map((name) => {
      const own = (t.transitions || []).filter((tr) => tr.automaton === name && tr.command);
      // A moved command's ghost has no label of its own: its new marker has it.
      const items = [...own, ...ghosts.filter((g) => g.automaton === name).map((g) => ({ ...g, ghost: true }))]
        .map((tr) => {
          const px = x(tr.time);
          const w = tr.ghost && tr.kind === "moved" ? 0 : textWidth(tr.command, font - 1) + 4;
          // The label goes right of its marker, or left of it where the plot ends.
          const left = px + 8 + w > labelW + plotW;
          return { tr, px, left, x0: left ? px - 8 - w : px - 5, x1: left ? px + 5 : px + 8 + w };
        }).filter((it) => it.px >= labelW - 6 && it.px <= labelW + plotW + 6);
      const n = items.length ? lanes(items) : 0;
      return { items, height: n ? 8 + n * (font + 4) : 0 };
    });
    const bItems = brackets.map((b, i) => {
      const x0 = clipX(x(b.from)), x1 = clipX(x(b.to));
      const w = textWidth(b.label, font) * 1.05 + 10;  // SVG text runs a little wider than canvas'
      return { b, i, bx0: x0, bx1: x1, x0: Math.min(x0, labelW + plotW - w), x1: Math.max(x1, Math.min(x0, labelW + plotW - w) + w) };
    });
    const bLanes = bItems.length ? lanes(bItems) : 0;
    const bandH = bLanes ? 10 + bLanes * (font + 16) : 0;

    let y = top;
    const winLane = small ? 5 : 6, winGap = 2;
    const layout = names.map((name, i) => {
      const win = winRows[name];
      const winH = win.lanes * (winLane + winGap);
      const cmdY = y + rowH + 2;
      const r = { name, y, cmdY, cmd: cmdRows[i], win, winY: cmdY + Math.max(0, cmdRows[i].height - 2), winH };
      y += rowH + 2 + cmdRows[i].height + winH + 6;
      return r;
    });
    const bandY = y;
    const axisY = bandY + bandH + 4;
    const height = axisY + 18;

    // Text is measured at these sizes, so the CSS draws it at them.
    const s = svgEl("svg", { class: "timeline", width, height, viewBox: `0 0 ${width} ${height}`, role: "img",
      style: `--fs: ${font}px; --fs-small: ${font - 1}px`,
      "aria-label": `Timeline of ${names.length} automata up to ${clock(full, longForm)}` +
        (goal !== null ? `, goal reached at ${clock(goal, longForm)}` : "") });
    const defs = svgEl("defs");
    const clip = svgEl("clipPath", { id: `clip-${uid}` });
    clip.appendChild(svgEl("rect", { x: labelW, y: 0, width: plotW, height }));
    defs.appendChild(clip);
    const hatch = svgEl("pattern", { id: `hatch-${uid}`, width: 6, height: 6, patternUnits: "userSpaceOnUse",
      patternTransform: "rotate(45)" });
    hatch.appendChild(svgEl("rect", { width: 6, height: 6, class: "past-wash" }));
    hatch.appendChild(svgEl("line", { x1: 0, y1: 0, x2: 0, y2: 6, class: "past-hatch" }));
    defs.appendChild(hatch);
    // An open window fades out towards the chart's right edge.
    for (const kind of ["", "contingent"]) {
      const fade = svgEl("linearGradient", { id: `fade-${kind}${uid}`, class: `window-fade ${kind}`.trim(), x1: 0, x2: 1, y1: 0, y2: 0 });
      for (const [offset, opacity] of [[0, 1], [0.6, 1], [1, 0]])
        fade.appendChild(svgEl("stop", { offset, "stop-opacity": opacity }));
      defs.appendChild(fade);
    }
    s.appendChild(defs);

    // Gridlines and ticks.
    const step = tickStep(v1 - v0, Math.max(2, Math.floor(plotW / (small ? 64 : 90))));
    const grid = svgEl("g", { class: "grid" });
    for (let k = Math.ceil(v0 / step - 1e-9); k * step <= v1 + 1e-9; k++) {
      const time = Math.round(k * step * 1000) / 1000;
      const px = x(time);
      grid.appendChild(svgEl("line", { x1: px, x2: px, y1: top - 4, y2: axisY - 2, class: "gridline" }));
      const label = clock(time, longForm);
      const w = textWidth(label, font);
      const tx = Math.max(labelW, Math.min(px - w / 2, width - w - 2));
      grid.appendChild(svgEl("text", { x: tx, y: axisY + 10, class: "tick" }, label));
    }
    s.appendChild(grid);

    const plot = svgEl("g", { "clip-path": `url(#clip-${uid})` });
    for (const r of layout) {
      const label = svgEl("text", { x: 4, y: r.y + rowH / 2 + 4, class: "rowlabel" }, r.name);
      if (pick) {
        // In execution, a row's name is a button (keyboard users reach the row through it).
        const g = svgEl("g", { class: "rowpick", tabindex: "0", role: "button", "data-kind": "row",
          "data-automaton": r.name, "aria-label": `${r.name}: report what went wrong` });
        g.append(svgEl("rect", { x: 1, y: r.y + 1, width: labelW - 3, height: rowH - 2, rx: 3, class: "rowpick-box" }), label);
        s.appendChild(g);
      } else s.appendChild(label);
      if (r.cmd.height) s.appendChild(svgEl("text", { x: 4, y: r.cmdY + 12, class: "cmdlabel" }, "commands"));
      if (r.winH >= font + 4) s.appendChild(svgEl("text", { x: 4, y: r.winY + font, class: "cmdlabel" }, "windows"));
      for (const seg of t.timelines[r.name]) {
        const x0 = x(seg.start), x1 = x(seg.end);
        if (x1 < labelW - 2 || x0 > labelW + plotW + 2) continue;
        const fill = colour[r.name][seg.location];
        const w = Math.max(2, x1 - x0);
        const rect = svgEl("rect", { x: x0, y: r.y, width: w, height: rowH, fill, class: "segment",
          "data-kind": "segment", "data-automaton": r.name, "data-location": seg.location,
          "data-start": seg.start, "data-end": seg.end });
        plot.appendChild(rect);
        const vx0 = clipX(x0), vx1 = clipX(x1);
        const lw = textWidth(seg.location, font);
        if (vx1 - vx0 > lw + 8)
          plot.appendChild(svgEl("text", { x: vx0 + 4, y: r.y + rowH / 2 + 4, class: "seglabel",
            fill: textOn(fill), "pointer-events": "none" }, seg.location));
      }
      // Windows, under the row's commands.
      for (const { w, lane } of r.win.items) {
        const x0 = x(w.earliest);
        const open = w.latest === null;
        const x1 = open ? labelW + plotW : x(w.latest);
        if (x1 < labelW || x0 > labelW + plotW) continue;
        const wy = r.winY + lane * (winLane + winGap);
        const g = svgEl("g", { class: `window${w.contingent ? " contingent" : ""}${open ? " open" : ""}`,
          "data-kind": "window", "data-automaton": r.name, "data-point": w.point, "data-from": w.tr.from,
          "data-to": w.tr.to, "data-time": w.tr.time, "data-earliest": w.earliest });
        if (w.tr.command) g.dataset.command = w.tr.command;
        if (open) g.dataset.open = "true"; else g.dataset.latest = w.latest;
        if (w.contingent) g.dataset.contingent = "true";
        const band = svgEl("rect", { x: x0, y: wy, width: Math.max(1, x1 - x0), height: winLane, class: "window-band" });
        if (open) band.style.fill = `url(#fade-${w.contingent ? "contingent" : ""}${uid})`;
        g.appendChild(band);
        g.appendChild(svgEl("rect", { x: x0, y: wy, width: 1.5, height: winLane, class: "window-edge" }));
        if (!open) g.appendChild(svgEl("rect", { x: x1 - 1.5, y: wy, width: 1.5, height: winLane, class: "window-edge" }));
        g.appendChild(svgEl("rect", { x: x(w.tr.time) - 1, y: wy - 1, width: 2, height: winLane + 2, class: "window-at" }));
        g.appendChild(svgEl("title", {}, windowText(w)));
        plot.appendChild(g);
      }
      const laneY = (it) => r.cmdY + 6 + it.lane * (font + 4);
      for (const it of r.cmd.items) {
        const ly = laneY(it);
        if (it.tr.ghost) {
          plot.appendChild(ghostMark(it, ly, r, rowH, laneY));
          continue;
        }
        const mark = diffMark.get(`${r.name}|${it.tr.from}|${it.tr.to}|${it.tr.time}`);
        const g = svgEl("g", { class: `command${mark ? ` diff-${mark.kind}` : ""}`, "data-kind": "command", "data-automaton": r.name,
          "data-command": it.tr.command, "data-time": it.tr.time, "data-from": it.tr.from,
          "data-to": it.tr.to, "data-event": it.tr.event });
        if (mark) { g.dataset.diff = mark.kind; if (mark.before !== undefined) g.dataset.before = mark.before; }
        g.appendChild(svgEl("line", { x1: it.px, x2: it.px, y1: r.y + rowH, y2: ly, class: "command-stem" }));
        g.appendChild(svgEl("path", { d: `M ${it.px} ${ly - 5} l 5 5 l -5 5 l -5 -5 z`, class: "command-mark" }));
        g.appendChild(svgEl("text", { x: it.left ? it.x0 + 2 : it.px + 7, y: ly + 4, class: "command-label" }, it.tr.command));
        const acts = actionsOf(sp, { ...it.tr, automaton: r.name });
        if (acts.length) {
          g.classList.add("action-event");
          g.dataset.action = acts.join(" ");
          g.appendChild(svgEl("title", {}, `action ${acts.join(", ")}`));
        }
        plot.appendChild(g);
      }
    }
    // Constraint brackets under the rows.
    for (const it of bItems) {
      const by = bandY + 8 + it.lane * (font + 16);
      const g = svgEl("g", { class: `bracket ${it.b.kind}`, "data-kind": "bracket", "data-index": it.i,
        "data-name": it.b.name, "data-constraint": it.b.kind, "data-pointer":
          `/constraints/${it.b.kind === "episode" ? "episodes" : "temporal"}/${it.b.name}` });
      const x0 = it.bx0, x1 = Math.max(it.bx1, it.bx0 + 2), yb = by + font + 10;
      if (it.b.ordered) {
        // "First event 1, then event 2": an arrow towards event 2.
        g.classList.add("ordered");
        g.dataset.ordered = "true";
        // At least 16 px long, so that an order met at one moment still reads as an arrow.
        const right = it.b.event2 >= it.b.event1;
        const a0 = right ? x0 : Math.min(x0, x1 - 16), a1 = right ? Math.max(x1, x0 + 16) : x1;
        const tip = right ? a1 : a0, back = right ? -6 : 6;
        g.appendChild(svgEl("path", { d: `M ${a0} ${yb - 3} H ${a1}`, class: "bracket-line" }));
        g.appendChild(svgEl("path", { d: `M ${tip + back} ${yb - 7} L ${tip} ${yb - 3} L ${tip + back} ${yb + 1}`,
          class: "bracket-line arrow-head" }));
      } else {
        g.appendChild(svgEl("path", { d: `M ${x0} ${yb} V ${yb - 6} H ${x1} V ${yb}`, class: "bracket-line" }));
      }
      g.appendChild(svgEl("rect", { x: x0, y: by, width: Math.max(12, x1 - x0), height: font + 12, class: "hit" }));
      g.appendChild(svgEl("text", { x: it.x0 + 2, y: by + font, class: "bracket-label" }, it.b.label));
      s.appendChild(g);
    }
    // The goal.
    if (goal !== null && x(goal) >= labelW - 1 && x(goal) <= labelW + plotW + 1) {
      const gx = x(goal);
      const g = svgEl("g", { class: "goal", "data-kind": "goal" });
      g.appendChild(svgEl("line", { x1: gx, x2: gx, y1: top - 6, y2: axisY - 2, class: "goal-line" }));
      g.appendChild(svgEl("rect", { x: gx - 6, y: top - 6, width: 12, height: axisY - top, class: "hit" }));
      const label = `goal ${clock(goal, longForm)}`;
      const lw = textWidth(label, font, "600") + 2;
      g.appendChild(svgEl("text", { x: Math.max(labelW, Math.min(gx - lw / 2, width - lw - 2)), y: top - 8,
        class: "goal-label" }, label));
      s.appendChild(g);
    }
    // The previous plan's goal, faint, labelled unless the goal's label is in the way.
    if (prevGoal !== null && x(prevGoal) >= labelW - 1 && x(prevGoal) <= labelW + plotW + 1) {
      const px = x(prevGoal);
      const g = svgEl("g", { class: "previous-goal", "data-kind": "previous-goal" });
      g.appendChild(svgEl("line", { x1: px, x2: px, y1: top - 6, y2: axisY - 2, class: "previous-goal-line" }));
      g.appendChild(svgEl("rect", { x: px - 5, y: top - 6, width: 10, height: axisY - top, class: "hit" }));
      const label = `was ${clock(prevGoal, longForm)}`;
      const lw = textWidth(label, font) + 4;
      const left = goal === null || prevGoal < goal;
      const lx = left ? px - lw - 2 : px + 3;
      const goalHalf = goal === null ? 0 : textWidth(`goal ${clock(goal, longForm)}`, font, "600") / 2 + 4;
      const clash = goal !== null && (left ? lx + lw > x(goal) - goalHalf : lx < x(goal) + goalHalf);
      if (!clash && lx >= labelW && lx + lw <= width)
        g.appendChild(svgEl("text", { x: lx, y: top - 8, class: "previous-goal-label" }, label));
      s.appendChild(g);
    }
    s.insertBefore(plot, s.querySelector(".bracket, .goal, .previous-goal"));
    nowEls = drawNow(s, plot, { x, labelW, plotW, width, top, bandY, axisY, font });
    const focused = svg?.querySelector(".rowpick:focus")?.dataset.automaton;
    if (svg) svg.replaceWith(s); else stage.insertBefore(s, card);
    svg = s;
    if (focused) svg.querySelector(`.rowpick[data-automaton="${CSS.escape(focused)}"]`)?.focus();
    const round = (v) => (v1 - v0 >= 10 ? Math.round(v) : v);
    range.textContent = v0 === 0 && v1 === full ? `0:00 – ${clock(full, longForm)}`
      : `${clock(round(v0), longForm)} – ${clock(round(v1), longForm)} of ${clock(full, longForm)}`;
  }

  const uid = Math.random().toString(36).slice(2, 9);
  const clampView = (a, b) => {
    const span = Math.min(full, Math.max(Math.min(full, 2), b - a));
    a = Math.max(0, Math.min(a, full - span));
    return [a, a + span];
  };
  const zoom = (factor, at) => {
    const [a, b] = view;
    const c = at ?? (a + b) / 2;
    view = clampView(c - (c - a) * factor, c + (b - c) * factor);
    hideCard();
    draw();
  };
  const pan = (dt) => { view = clampView(view[0] + dt, view[1] + dt); draw(); };
  zoomIn.addEventListener("click", () => zoom(0.5));
  zoomOut.addEventListener("click", () => zoom(2));
  fit.addEventListener("click", () => { view = [0, full]; hideCard(); draw(); });
  stage.addEventListener("keydown", (e) => {
    const row = e.target.closest?.(".rowpick");
    if (row && pick && (e.key === "Enter" || e.key === " ")) {
      e.preventDefault();
      const box = row.getBoundingClientRect();
      pick(row.dataset.automaton, { ...row.dataset }, { x: box.right, y: box.bottom });
      return;
    }
    const span = view[1] - view[0];
    if (e.key === "ArrowLeft") pan(-span / 5);
    else if (e.key === "ArrowRight") pan(span / 5);
    else if (e.key === "+" || e.key === "=") zoom(0.5);
    else if (e.key === "-") zoom(2);
    else if (e.key === "0") { view = [0, full]; draw(); }
    else if (e.key === "Escape") hideCard();
    else return;
    e.preventDefault();
  });
  stage.addEventListener("wheel", (e) => {
    if (!e.ctrlKey && !e.metaKey) return;  // plain wheel scrolls the page
    e.preventDefault();
    const box = svg.getBoundingClientRect();
    const frac = Math.max(0, Math.min(1, (e.clientX - box.left - geom.labelW) / geom.plotW));
    zoom(e.deltaY > 0 ? 1.25 : 0.8, view[0] + frac * (view[1] - view[0]));
  }, { passive: false });

  // Drag pans (mouse or a horizontal finger); a tap or click opens a card.
  let drag = null;
  stage.addEventListener("pointerdown", (e) => {
    if (e.button !== 0) return;
    drag = { x: e.clientX, view: [...view], moved: false };
  });
  stage.addEventListener("pointermove", (e) => {
    if (drag) {
      const dx = e.clientX - drag.x;
      if (Math.abs(dx) > 4 && view[1] - view[0] < full) {
        drag.moved = true;
        const dt = (-dx / geom.plotW) * (drag.view[1] - drag.view[0]);
        view = clampView(drag.view[0] + dt, drag.view[1] + dt);
        draw();
        return;
      }
    }
    if (e.pointerType !== "mouse" || pinned) return;
    const node = e.target.closest?.("[data-kind]");
    const lines = node && cardFor(node);
    const box = stage.getBoundingClientRect();
    if (lines) showCard(lines, e.clientX - box.left, e.clientY - box.top);
    else card.hidden = true;
  });
  stage.addEventListener("pointerup", (e) => {
    const moved = drag?.moved;
    drag = null;
    if (moved) return;
    if (pick) {
      const row = e.target.closest?.("[data-automaton]");
      if (row && row.dataset.kind !== "ghost") {
        hideCard();
        pick(row.dataset.automaton, { ...row.dataset }, { x: e.clientX, y: e.clientY });
        return;
      }
    }
    const node = e.target.closest?.("[data-kind]");
    const lines = node && cardFor(node);
    const box = stage.getBoundingClientRect();
    if (lines && pinned !== node) {
      showCard(lines, e.clientX - box.left, e.clientY - box.top);
      pinned = node;
    } else hideCard();
  });
  stage.addEventListener("pointerleave", () => { drag = null; if (!pinned) card.hidden = true; });

  draw();
  let lastWidth = stage.clientWidth;
  new ResizeObserver(() => {
    if (stage.clientWidth !== lastWidth) { lastWidth = stage.clientWidth; draw(); }
  }).observe(stage);
  return {
    wrap, legend, table, stage, redraw: draw,
    setNow(time) {
      const was = nowT;
      nowT = time;
      if (nowEls && time !== null && was !== null) placeNow(nowEls, time);
      else draw();
    },
    setPick(fn) {
      if (!!fn === !!pick) { pick = fn; return; }
      pick = fn;
      hideCard();
      draw();
    },
  };
}
