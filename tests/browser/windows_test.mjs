// The plan's windows on the timeline and the robustness sentence (issue 26 item 4), end to end:
// the real `ctburton serve --demo` on a free loopback port, the page in Debian's headless
// Chromium. Plans the search_rescue example "Rescue person 1 fast, together" from the shipped
// recordings and checks that every transition whose window (`slack`) is wider than an instant has
// a band on its automaton's row, from its earliest time to its latest (or, open, to the chart's
// right edge), on the timeline's scale within a pixel (read off the location segments), before
// and after zooming; that its tooltip and card say when it may happen; and that the legend names
// windows. Then the uncertain rescue team (config/uncertain/search_rescue.json, stored through
// POST /domains) and "both robots at door 1", solved by the server (the first plan ties nature's
// two arrivals; the search among plans sets it aside): drawn through a mocked /plan, its
// contingent points' bands say "(uncertain)" and the flexibility block says how many plans the
// planner set aside. The same answer with closed windows and a stopped search, and an answer
// without a plan whose search found none, check closed bands and the other sentences.
// Screenshots go to OUTPUT_DIR.
//   node windows_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { readFileSync, rmSync } from "node:fs";
import { check, finish, launchBrowser, startServer, stopped } from "./harness.mjs";

const [bin, src, out] = process.argv.slice(2);
const examples = JSON.parse(readFileSync(`${src}/server/static/examples.json`, "utf8"));
const CHIP = examples.domains.search_rescue.findIndex((e) => /Person 1 as fast as possible/.test(e.command));
const dataDir = `/tmp/ctb-browser-windows-${process.pid}`;
const { server, base } = await startServer(bin, src, out, { args: ["--demo", "--data-dir", dataDir],
  log: "windows-server.log" });
const browser = await launchBrowser();

const lastAnswer = (page) => page.evaluate(() => {
  const list = JSON.parse(localStorage.getItem("ctburton.dialogues.v1") || "[]");
  const turns = list.length ? list[list.length - 1].turns : [];
  return turns.length ? turns[turns.length - 1].answer || null : null;
});

// The windows an answer should draw: {point: {automaton, earliest, latest, contingent}} for the
// points of a transition whose window is wider than an instant.
function expectedWindows(t) {
  const points = new Map((t.network?.points || []).map((p) => [p.id, p]));
  const out = {};
  for (const w of t.slack || []) {
    const p = points.get(w.point);
    if (!p?.automaton) continue;
    if (w.latest === null || w.latest > w.earliest)
      out[w.point] = { automaton: p.automaton, earliest: w.earliest, latest: w.latest, contingent: p.kind === "contingent",
        from: p.from, to: p.to };
  }
  return out;
}

// What the chart drew: its scale read off the location segments (x = a + b * seconds, from the
// segments of the first and the last start), the plot's right edge (its clip), each row's top and
// each window band.
const drawn = (turn) => turn.locator("svg.timeline").evaluate((svg) => {
  const segs = [...svg.querySelectorAll("rect.segment")].map((r) => ({ t: +r.dataset.start, x: +r.getAttribute("x"),
    automaton: r.dataset.automaton, y: +r.getAttribute("y") }));
  const first = segs.reduce((m, s) => (s.t < m.t ? s : m)), last = segs.reduce((m, s) => (s.t > m.t ? s : m));
  const b = (last.x - first.x) / (last.t - first.t), a = first.x - b * first.t;
  const clip = svg.querySelector("clipPath rect");
  const rows = {};
  for (const s of segs) rows[s.automaton] = s.y;
  const bands = [...svg.querySelectorAll("g.window")].map((g) => {
    const band = g.querySelector("rect.window-band"), at = g.querySelector("rect.window-at");
    return { point: +g.dataset.point, automaton: g.dataset.automaton, open: g.dataset.open === "true",
      latest: g.dataset.latest, contingent: g.dataset.contingent === "true", time: +g.dataset.time,
      x: +band.getAttribute("x"), width: +band.getAttribute("width"), y: +band.getAttribute("y"),
      at: +at.getAttribute("x") + 1, title: g.querySelector("title")?.textContent || "",
      fill: getComputedStyle(band).fill };
  });
  return { a, b, left: +clip.getAttribute("x"), right: +clip.getAttribute("x") + +clip.getAttribute("width"), rows, bands };
});

// The bands of `turn` against the windows of `t` that meet the chart's view; `label` names the case.
async function checkBands(turn, t, label) {
  const d = await drawn(turn);
  const px = (s) => d.a + d.b * s;
  const want = Object.fromEntries(Object.entries(expectedWindows(t)).filter(([, w]) =>
    px(w.earliest) <= d.right && (w.latest === null || px(w.latest) >= d.left)));
  const got = Object.fromEntries(d.bands.map((b) => [b.point, b]));
  check(`${label}: a band for each window wider than an instant, and no other`,
        JSON.stringify(Object.keys(got).sort()) === JSON.stringify(Object.keys(want).sort()) && Object.keys(want).length > 0,
        `${JSON.stringify(Object.keys(got))} vs ${JSON.stringify(Object.keys(want))}`);
  const off = [];
  const rowTops = Object.entries(d.rows).sort((x, y) => x[1] - y[1]);
  for (const [point, w] of Object.entries(want)) {
    const b = got[point];
    if (!b) continue;
    const end = w.latest === null ? d.right : px(w.latest);
    const row = rowTops.findIndex(([a]) => a === w.automaton);
    const below = row + 1 < rowTops.length ? rowTops[row + 1][1] : Infinity;
    if (Math.abs(b.x - px(w.earliest)) > 1 || Math.abs(b.x + b.width - end) > 1) off.push(`${point}: x ${b.x}–${b.x + b.width}, want ${px(w.earliest)}–${end}`);
    if (b.automaton !== w.automaton || !(b.y > rowTops[row][1] && b.y < below)) off.push(`${point}: on row ${b.automaton} at y ${b.y}`);
    if ((w.latest === null) !== b.open || (w.latest !== null && +b.latest !== w.latest)) off.push(`${point}: open ${b.open}, latest ${b.latest}`);
    if (Math.abs(b.at - px(b.time)) > 1) off.push(`${point}: planned time marked at ${b.at}, want ${px(b.time)}`);
    if (b.open !== /^url\(/.test(b.fill)) off.push(`${point}: fill ${b.fill}`);
    if (w.contingent !== b.contingent || w.contingent !== /\(uncertain\): nature picks it/.test(b.title)) off.push(`${point}: contingent ${b.contingent}, ${b.title}`);
    const span = w.latest === null ? `from ${w.earliest} s on` : `${w.earliest}–${w.latest} s`;
    if (!b.title.startsWith(`${w.automaton} ${w.from} → ${w.to}`) || !b.title.endsWith(`any time ${span}`)) off.push(`${point}: title ${b.title}`);
  }
  check(`${label}: each band spans its window on the timeline's scale (within a pixel), on its row, its planned time marked, with its tooltip`,
        off.length === 0, off.join("; "));
  return d;
}

// Answers /plan with `answer` (the stream's done event) once.
async function mockPlan(page, answer) {
  await page.route("**/plan", (route) => route.fulfill({ status: 200, contentType: "text/event-stream",
    body: `event: stage\ndata: {"stage":"solving"}\n\nevent: done\ndata: ${JSON.stringify(answer)}\n\n` }), { times: 1 });
  await page.click("#new-session");
  await page.fill("#command", "both robots at door 1");
  await page.keyboard.press("Enter");
  const turn = page.locator(".turn").last();
  await turn.locator(".summary").waitFor({ timeout: 10000 });
  return turn;
}

const scriptErrors = [];
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  page.on("pageerror", (e) => scriptErrors.push(String(e)));
  await page.goto(base + "/");
  await page.waitForSelector("body[data-ready='1']");

  // --- A shipped example: every window is open (nothing bounds the plan's end) ---
  await page.selectOption("#domain", "search_rescue");
  await page.locator(".chip").nth(CHIP).click();
  const turn = page.locator(".turn").first();
  await turn.locator(".summary").waitFor({ timeout: 120000 });
  const answer = await lastAnswer(page);
  const t = answer.trajectory;
  check("the example's answer carries slack and the network's points",
        (t.slack || []).length === (t.transitions || []).length && (t.network?.points || []).length === t.slack.length + 1);
  const d0 = await checkBands(turn, t, "rescue example");
  check("the legend names windows", (await turn.locator(".legend .legend-item").allTextContents())
    .includes("window: when it may happen"));
  check("no point of the example is uncertain: no legend entry for nature's windows",
        (await turn.locator(".legend-window.contingent").count()) === 0);
  const first = d0.bands.find((b) => b.automaton === "robot1" && b.time > 0) || d0.bands[0];
  const firstBand = turn.locator(`svg.timeline g.window[data-point="${first.point}"] rect.window-band`);
  const box = await firstBand.boundingBox();
  await page.mouse.move(box.x + 3, box.y + box.height / 2);
  const card = turn.locator(".timeline-card");
  const cardText = await card.textContent();
  check("hovering a band shows when it may happen and when it is planned", await card.isVisible() &&
        cardText.includes(`${first.automaton}: `) && /any time from \d+ s on/.test(cardText) && /planned at \d:\d\d/.test(cardText),
        cardText);
  await page.screenshot({ path: `${out}/windows-rescue.png` });
  await turn.getByRole("button", { name: "Zoom in" }).click();
  await turn.getByRole("button", { name: "Zoom in" }).click();
  const d1 = await drawn(turn);
  check("zoomed in, the scale changes", d1.b > d0.b * 3, `${d0.b} → ${d1.b}`);
  await checkBands(turn, t, "rescue example, zoomed in");
  await turn.getByRole("button", { name: "Show the whole plan" }).click();
  await turn.locator(".flexibility summary").click();
  const li = turn.locator(`.flexibility .windows li[data-point="${first.point}"]`);
  await li.hover();
  check("hovering a window in the list lights up its band",
        (await turn.locator(`svg.timeline g.window.lit[data-point="${first.point}"]`).count()) === 1);

  // --- Uncertain durations, solved by the server: the search among plans set one aside ---
  const domain = JSON.parse(readFileSync(`${src}/config/uncertain/search_rescue.json`, "utf8"));
  domain.name = "search_rescue_uncertain";
  const stored = await fetch(`${base}/domains`, { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify(domain) });
  check("the uncertain rescue team is stored", stored.status === 201, `${stored.status}`);
  const sp = JSON.parse(readFileSync(`${src}/config/uncertain/rescue_arrive_together.json`, "utf8"));
  delete sp.constraints.temporal.ArriveTogether;  // both robots at door 1, in any order
  const solved = await (await fetch(`${base}/solve`, { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ domain: domain.name, state_plan: sp }) })).json();
  const search = solved.controllability?.search;
  check("the server's plan for both robots at door 1 is dynamic, after the search set plans aside",
        solved.status === "optimal" && solved.controllability.dynamic === true && search?.plans_cut >= 1 && !search.stopped,
        JSON.stringify(solved.controllability));
  await page.reload();
  await page.waitForSelector("body[data-ready='1']");
  await page.selectOption("#domain", domain.name);
  const u = await mockPlan(page, { session: "e".repeat(32), state_plan: sp, trajectory: solved });
  await checkBands(u, solved, "uncertain rescue");
  check("the contingent points' bands are nature's, in the legend too",
        (await u.locator("svg.timeline g.window.contingent").count()) ===
          Object.values(expectedWindows(solved)).filter((w) => w.contingent).length &&
        (await u.locator(".legend-window.contingent").textContent()) === "uncertain: nature picks when");
  const n = search.plans_cut;
  const robust = await u.locator(".flexibility .robustness").textContent();
  check("the robustness sentence says how many plans were set aside",
        robust.endsWith(`The planner set aside ${n} plan${n === 1 ? "" : "s"} that some outcome would break.`) &&
        /^Robust to every outcome/.test(robust), robust);
  await u.locator("svg.timeline").scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${out}/windows-uncertain.png` });

  // --- The same plan with closed windows (nature's arrivals given 3 s more than their earliest,
  //     which holds the plan's own times) and a search that stopped ---
  const closed = structuredClone(solved);
  delete closed.controllability.success_probability;
  const contingentPoints = new Set(solved.network.points.filter((p) => p.kind === "contingent").map((p) => p.id));
  for (const w of closed.slack) if (contingentPoints.has(w.point)) w.latest = w.earliest + 3;
  closed.slack.push({ point: 99, earliest: 5, latest: 5 });  // a point of no transition: ignored
  closed.status = "unknown";
  closed.controllability = { ...closed.controllability, dynamic: false, strong: false,
    search: { plans_cut: 2, ms: 3000, stopped: "time" } };
  const c = await mockPlan(page, { session: "d".repeat(32), state_plan: sp, trajectory: closed });
  await checkBands(c, closed, "closed windows");
  await c.locator("svg.timeline").scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${out}/windows-closed.png` });
  const stoppedText = await c.locator(".flexibility .robustness").textContent();
  check("a stopped search says so: this plan is not robust",
        stoppedText === "Not robust: some outcomes of the uncertain durations break it. The planner set aside 2 plans " +
          "that some outcome would break. It stopped looking (time): this plan is not robust.", stoppedText);

  // --- A single-instant window has no band ---
  const instant = structuredClone(solved);
  for (const w of instant.slack) w.latest = w.earliest;
  const i = await mockPlan(page, { session: "c".repeat(32), state_plan: sp, trajectory: instant });
  check("windows of a single instant draw no band, and the legend does not name windows",
        (await i.locator("svg.timeline g.window").count()) === 0 && (await i.locator(".legend-window").count()) === 0 &&
        (await i.locator("svg.timeline g.command").count()) === instant.transitions.filter((x) => x.command).length);

  // --- No plan: the search found none ---
  const none = { status: "infeasible", verified: false, objective: { kind: "makespan", value: null },
    controllability: { asked: "dynamic", search: { plans_cut: 3, ms: 7000, proven: true } } };
  const nt = await mockPlan(page, { session: "b".repeat(32), state_plan: sp, trajectory: none });
  check("without a plan, the search's sentence alone",
        (await nt.locator(".flexibility .robustness").textContent()) ===
          "No plan is robust: the planner set aside 3 plans that some outcome would break and found none left." &&
        (await nt.locator(".flexibility .windows li").count()) === 0);

  // --- Phone width: the bands fit ---
  const phone = await browser.newPage({ viewport: { width: 390, height: 844 } });
  phone.on("pageerror", (e) => scriptErrors.push(String(e)));
  await phone.goto(base + "/");
  await phone.waitForSelector("body[data-ready='1']");
  await phone.selectOption("#domain", "search_rescue");
  await phone.locator(".chip").nth(CHIP).click();
  const pt = phone.locator(".turn").first();
  await pt.locator(".summary").waitFor({ timeout: 120000 });
  await checkBands(pt, (await lastAnswer(phone)).trajectory, "at 390 px");
  const sw = await phone.evaluate(() => document.scrollingElement.scrollWidth);
  check("at 390 px nothing scrolls sideways", sw <= 390, `scrollWidth ${sw}`);
  await pt.locator("svg.timeline").scrollIntoViewIfNeeded();
  await phone.screenshot({ path: `${out}/windows-390.png` });
  check("no script errors", scriptErrors.length === 0, scriptErrors.join("; "));
} catch (e) {
  stopped(e);
} finally {
  await browser.close();
  server.kill("SIGTERM");
  rmSync(dataDir, { recursive: true, force: true });
}
finish();
