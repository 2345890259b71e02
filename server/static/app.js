// The ctburton chat page: POST /plan with the session, show reasoning, state plan and the
// trajectory as a timeline chart (one row per automaton, a coloured segment per location,
// markers at commands).
"use strict";
const $ = (id) => document.getElementById(id);
let session = null;

function colour(name) {
  let h = 0;
  for (const c of name) h = (h * 31 + c.charCodeAt(0)) % 360;
  return `hsl(${h}, 55%, 45%)`;
}

function el(tag, attrs, text) {
  const e = document.createElementNS("http://www.w3.org/2000/svg", tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

// Draws the trajectory's timelines; returns the <svg>.
function chart(t) {
  const names = Object.keys(t.timelines);
  const end = Math.max(1, t.goal_reached_at || 0);
  const left = 110, width = 900, row = 34, top = 20;
  const svg = el("svg", { class: "timeline", width: left + width + 20, height: top + row * names.length + 30 });
  const x = (time) => left + (time / end) * width;
  names.forEach((name, i) => {
    const y = top + i * row;
    svg.appendChild(el("text", { x: 4, y: y + 18, class: "rowlabel" }, name));
    for (const seg of t.timelines[name]) {
      const w = Math.max(2, x(seg.end) - x(seg.start));
      const r = el("rect", { x: x(seg.start), y: y + 4, width: w, height: row - 10, fill: colour(seg.location),
                             class: "segment", "data-automaton": name, "data-location": seg.location });
      r.appendChild(el("title", {}, `${name}: ${seg.location} ${seg.start}–${seg.end} s`));
      svg.appendChild(r);
      if (w > 60) svg.appendChild(el("text", { x: x(seg.start) + 4, y: y + 20, class: "seglabel" }, seg.location));
    }
    for (const tr of t.transitions.filter((tr) => tr.automaton === name && tr.command)) {
      const m = el("path", { d: `M ${x(tr.time)} ${y + 2} l -5 -7 h 10 z`, fill: "#1d2330", class: "command" });
      m.appendChild(el("title", {}, `${tr.command} at ${tr.time} s`));
      svg.appendChild(m);
    }
  });
  const yAxis = top + row * names.length + 14;
  for (let k = 0; k <= 4; k++) {
    const time = Math.round((end * k) / 4);
    svg.appendChild(el("text", { x: x(time) - 10, y: yAxis }, `${time} s`));
  }
  return svg;
}

function addTurn(command) {
  const turn = document.createElement("div");
  turn.className = "turn";
  const u = document.createElement("div");
  u.className = "user";
  u.textContent = command;
  turn.appendChild(u);
  $("log").appendChild(turn);
  return turn;
}

function details(summary, text) {
  const d = document.createElement("details");
  const s = document.createElement("summary");
  s.textContent = summary;
  const pre = document.createElement("pre");
  pre.textContent = text;
  d.append(s, pre);
  return d;
}

async function plan(ev) {
  ev.preventDefault();
  const command = $("command").value.trim();
  if (!command) return;
  const turn = addTurn(command);
  $("send").disabled = true;
  const body = { domain: $("domain").value, command, prompting: $("prompting").value };
  if (session) body.session = session;
  try {
    const res = await fetch("/plan", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
    const data = await res.json();
    if (!res.ok) {
      const e = document.createElement("div");
      e.className = "error";
      const d = data.error || {};
      e.textContent = `${res.status} ${d.code}: ${d.message}` + (d.details ? "\n" + d.details.map((x) => `${x.path}: ${x.message}`).join("\n") : "");
      turn.appendChild(e);
      return;
    }
    session = data.session;
    $("session-label").textContent = `session ${session.slice(0, 8)}`;
    const t = data.trajectory;
    const s = document.createElement("div");
    s.className = "summary";
    s.textContent = `${t.status}${t.verified ? ", verified" : ""}: ${t.objective.kind} ${JSON.stringify(t.objective.value)}` +
                    (t.goal_reached_at !== undefined ? `, goal at ${t.goal_reached_at} s` : "");
    turn.appendChild(s);
    if (data.reasoning) turn.appendChild(details("Reasoning", data.reasoning));
    turn.appendChild(details("State plan", JSON.stringify(data.state_plan, null, 2)));
    if (t.timelines) turn.appendChild(chart(t));
    $("command").value = "";
  } catch (err) {
    const e = document.createElement("div");
    e.className = "error";
    e.textContent = String(err);
    turn.appendChild(e);
  } finally {
    $("send").disabled = false;
  }
}

async function init() {
  const res = await fetch("/domains");
  const data = await res.json();
  for (const d of data.domains) {
    const o = document.createElement("option");
    o.value = d.name;
    o.textContent = d.name;
    $("domain").appendChild(o);
  }
  $("ask").addEventListener("submit", plan);
  $("new-session").addEventListener("click", () => { session = null; $("session-label").textContent = ""; });
  $("domain").addEventListener("change", () => { session = null; $("session-label").textContent = ""; });
}
init();
