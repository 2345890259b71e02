// End-to-end: the real `ctburton serve` on a free loopback port (no LLM configured, so /plan
// answers the thesis' test prompts from the shipped recordings), the web page in Debian's
// headless Chromium driven by playwright-core. Covers the example chips (each yields a chart whose
// rows, legend and constraint brackets match the answer), Enter and Shift+Enter, live progress
// over SSE before the answer and Stop cancelling the solver, threads and "new dialogue" after a
// failed follow-up, reload, exports, the explanation of an infeasible answer, the phone width,
// and a short accessibility check. Screenshots go to OUTPUT_DIR.
//   node chat_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { spawn } from "node:child_process";
import { mkdirSync, openSync, readFileSync, readdirSync } from "node:fs";
import net from "node:net";
import { chromium } from "playwright-core";

const [bin, src, out] = process.argv.slice(2);
mkdirSync(out, { recursive: true });
let passed = 0, failed = 0;
const check = (name, ok, detail = "") => {
  if (ok) { passed++; console.log(`ok   ${name}`); } else { failed++; console.log(`FAIL ${name} ${detail}`); }
};
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const examples = JSON.parse(readFileSync(`${src}/server/static/examples.json`, "utf8"));
const recorded = JSON.parse(readFileSync(`${src}/tests/recordings/thesis_answers.json`, "utf8"));

const port = await new Promise((resolve) => {
  const s = net.createServer();
  s.listen(0, "127.0.0.1", () => { const p = s.address().port; s.close(() => resolve(p)); });
});
const env = { ...process.env, CTB_CONFIG_DIR: `${src}/config`, CTB_PROMPTS_DIR: `${src}/prompts` };
for (const k of ["CTB_LLM_BASE_URL", "CTB_LLM_REPLAY", "CTB_LLM_API_KEY"]) delete env[k];
const serverLog = openSync(`${out}/browser-server.log`, "w");
const dataDir = `/tmp/ctb-browser-data-${process.pid}`;
const server = spawn(bin, ["serve", "--port", String(port), "--demo", "--data-dir", dataDir], { cwd: src, env, stdio: ["ignore", "ignore", serverLog] });
const base = `http://127.0.0.1:${port}`;
for (let i = 0; i < 200; i++) {
  try { if ((await fetch(`${base}/healthz`)).ok) break; } catch {}
  await sleep(50);
}

// minizinc and fzn-gecode processes below the server (minizinc puts its solver in a process
// group of its own, but it stays a descendant).
function solverProcesses() {
  const parent = new Map(), comm = new Map();
  for (const name of readdirSync("/proc")) {
    if (!/^\d+$/.test(name)) continue;
    let stat;
    try { stat = readFileSync(`/proc/${name}/stat`, "utf8"); } catch { continue; }
    const open = stat.indexOf("("), close = stat.lastIndexOf(")");
    parent.set(+name, +stat.slice(close + 2).split(" ")[1]);
    comm.set(+name, stat.slice(open + 1, close));
  }
  let n = 0;
  for (const [pid, c] of comm) {
    if (c !== "minizinc" && c !== "fzn-gecode") continue;
    for (let p = parent.get(pid); p > 1; p = parent.get(p) ?? 0) if (p === server.pid) { n++; break; }
  }
  return n;
}

// The last answer the page kept (store.js keeps every turn's whole answer).
const lastAnswer = (page) => page.evaluate(() => {
  const list = JSON.parse(localStorage.getItem("ctburton.dialogues.v1") || "[]");
  const turns = list.length ? list[list.length - 1].turns : [];
  return turns.length ? turns[turns.length - 1].answer || null : null;
});

const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
const bad = [];  // failed requests other than the expected GET /sessions/{id} 404
const scriptErrors = [];
async function newPage(width, height) {
  const context = await browser.newContext({ viewport: { width, height }, acceptDownloads: true });
  await context.grantPermissions(["clipboard-read", "clipboard-write"], { origin: base });
  const page = await context.newPage();
  page.on("pageerror", (e) => scriptErrors.push(String(e)));
  page.on("response", (r) => { if (r.status() >= 400 && !/\/sessions\//.test(r.url())) bad.push(`${r.status()} ${r.url()}`); });
  page.on("requestfailed", (r) => { if (!/\/plan$/.test(r.url())) bad.push(`failed ${r.url()}`); });
  await page.goto(base + "/");
  await page.waitForSelector("body[data-ready='1']");
  return page;
}

// Clicks a chip and waits for its turn's answer; returns the turn locator.
async function runChip(page, domain, index) {
  await page.selectOption("#domain", domain);
  const before = await page.locator(".turn").count();
  await page.locator(".chip").nth(index).click();
  const turn = page.locator(".turn").nth(before);
  await turn.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  return turn;
}

try {
  // --- Desktop: first impressions ---
  const page = await newPage(1400, 900);
  check("the page lists the domains", (await page.locator("#domain option").count()) === 3);
  check("the default domain is presentation", (await page.inputValue("#domain")) === "presentation");
  const placeholder = await page.getAttribute("#command", "placeholder");
  check("the placeholder is one of the examples",
        examples.domains.presentation.some((e) => placeholder.includes(e.command)), placeholder);
  const notice = page.locator("#llm-notice");
  const noticeText = await notice.textContent();
  check("no LLM configured: one notice with the three variables", await notice.isVisible() &&
        ["CTB_LLM_BASE_URL", "CTB_LLM_API_KEY", "CTB_LLM_MODEL"].every((v) => noticeText.includes(v)) &&
        (await page.locator("text=No LLM is configured").count()) === 1, noticeText);
  check("every example has recordings in both prompting modes",
        Object.entries(examples.domains).every(([d, list]) => list.every((e) =>
          ["cot", "direct"].every((p) => recorded.some((r) => r.domain === d && r.prompting === p && r.command === e.command)))));
  await page.fill("#command", "abc é");
  check("the counter shows the limit in bytes", (await page.textContent("#counter")) === "6 / 8,000",
        await page.textContent("#counter"));

  // --- Every example chip yields a chart that matches its answer ---
  for (const [domain, list] of Object.entries(examples.domains)) {
    for (let i = 0; i < list.length; i++) {
      const turn = await runChip(page, domain, i);
      const answer = await lastAnswer(page);
      const t = answer?.trajectory;
      const name = `${domain} example ${i + 1}`;
      if (!t?.timelines) { check(`${name} yields a chart`, false, await turn.textContent()); continue; }
      check(`${name} yields a chart`, (await turn.locator("svg.timeline").count()) === 1);
      const rows = await turn.locator("svg.timeline .rowlabel").allTextContents();
      check(`${name}: one row per automaton`, JSON.stringify(rows) === JSON.stringify(Object.keys(t.timelines)), JSON.stringify(rows));
      const legend = await turn.locator(".legend-item[data-location]").evaluateAll(
        (els) => els.map((e) => `${e.dataset.automaton}:${e.dataset.location}`).sort());
      const visited = [...new Set(Object.entries(t.timelines).flatMap(([a, segs]) => segs.map((s) => `${a}:${s.location}`)))].sort();
      check(`${name}: the legend lists the locations visited`, JSON.stringify(legend) === JSON.stringify(visited), JSON.stringify(legend));
      const colours = await turn.locator(".legend-group").evaluateAll((groups) => groups.map((g) =>
        [...g.querySelectorAll(".swatch")].map((s) => s.style.background)));
      check(`${name}: distinct colours within each automaton`, colours.every((c) => new Set(c).size === c.length));
      const commands = (t.transitions || []).filter((x) => x.command).length;
      check(`${name}: a labelled marker per command`,
            (await turn.locator("svg.timeline g.command text.command-label").count()) === commands);
      const sp = answer.state_plan.constraints || {};
      const expected = [
        ...Object.entries(t.episodes || {}).map(([n, e]) =>
          `${n} lasts [${sp.episodes[n].lower_bound}, ${sp.episodes[n].upper_bound ?? "∞"}] s: ${e.end - e.start} s`),
        ...Object.entries(t.temporal || {}).map(([n, e]) =>
          `${n} within [${sp.temporal[n].lower_bound ?? 0}, ${sp.temporal[n].upper_bound ?? "∞"}] s: ${Math.abs(e.event2 - e.event1)} s`),
      ].sort();
      const brackets = (await turn.locator("svg.timeline .bracket-label").allTextContents()).sort();
      check(`${name}: a bracket per episode and temporal constraint, with bounds and achieved value`,
            JSON.stringify(brackets) === JSON.stringify(expected), `${JSON.stringify(brackets)} vs ${JSON.stringify(expected)}`);
      // Orders (contract section 15): an arrow per ordered constraint, each command that is a named
      // action marked with its name.
      for (const [n, c] of Object.entries(sp.temporal || {}).filter(([, c]) => c.ordered === true))
        check(`${name}: ${n} is drawn as an arrow`,
              (await turn.locator(`svg.timeline g.bracket.ordered[data-name="${n}"] path.arrow-head`).count()) === 1);
      for (const [n, a] of Object.entries(sp.actions || {}).filter(([, a]) => a.command)) {
        const fired = (t.transitions || []).filter((x) => x.automaton === a.automaton && x.command === a.command).length;
        const marked = await turn.locator("svg.timeline g.command.action-event").evaluateAll(
          (els, act) => els.filter((e) => e.dataset.action.split(" ").includes(act)).length, n);
        check(`${name}: action ${n} marked on each of its ${fired} command(s)`, marked === fired, `${marked}`);
      }
      const windows = await turn.locator(".flexibility .windows li").count();
      check(`${name}: the flexibility block says it is robust and lists a window per transition`,
            windows === (t.transitions || []).length && windows > 0 &&
            /keeps the plan valid/.test(await turn.locator(".flexibility .robustness").textContent()),
            `${windows} windows for ${(t.transitions || []).length} transitions`);
      // The windows (issue 26 item 4; tests/browser/windows_test.mjs checks where they are drawn).
      const wide = (t.slack || []).filter((w) => w.latest === null || w.latest > w.earliest).map((w) => w.point).sort();
      const bands = await turn.locator("svg.timeline g.window").evaluateAll((els) => els.map((e) => +e.dataset.point).sort());
      check(`${name}: a window band per transition whose window is wider than an instant`,
            JSON.stringify(bands) === JSON.stringify(wide) && (!wide.length ||
              (await turn.locator(".legend-item", { hasText: "window: when it may happen" }).count()) === 1),
            `${JSON.stringify(bands)} vs ${JSON.stringify(wide)}`);
      check(`${name}: the goal marker`, typeof t.goal_reached_at !== "number" ||
            (await turn.locator("svg.timeline .goal-label").textContent()).startsWith("goal "));
      if (domain === "presentation" && i === 0) {
        check("presentation example 1 has its three brackets", brackets.length === 3 &&
              brackets.includes("ProjectorOnWithin60 within [0, 60] s: 30 s"), JSON.stringify(brackets));
        const ticks = await turn.locator("svg.timeline .tick").allTextContents();
        check("round m:ss ticks with gridlines", ticks.length >= 4 && ticks.every((x) => /^\d+:\d\d$/.test(x)) &&
              ticks.every((x) => Number(x.split(":")[1]) % 5 === 0) &&
              (await turn.locator("svg.timeline .gridline").count()) === ticks.length, JSON.stringify(ticks));
        await page.screenshot({ path: `${out}/chat-1400x900.png`, fullPage: false });
        const announced = await page.waitForFunction(() => document.getElementById("announcer").textContent, null, { timeout: 5000 })
          .then((h) => h.jsonValue()).catch(() => "");
        check("screen readers hear the verdict, once (live region)", announced.startsWith("Answer: optimal, verified") &&
              (await page.locator("[aria-live]:not(.timeline-range)").count()) === 1, announced);
        // Hover and tap cards.
        const seg = turn.locator('svg.timeline rect.segment[data-location="projOn"]');
        await seg.hover();
        const card = turn.locator(".timeline-card");
        check("hovering a segment shows its card", await card.isVisible() &&
              /proj: projOn/.test(await card.textContent()) && /duration 1800 s/.test(await card.textContent()),
              await card.textContent());
        await turn.locator("svg.timeline g.command").first().click();
        check("clicking a command marker pins its card", /at 0:00/.test(await card.textContent()), await card.textContent());
        // Zoom and pan.
        const range0 = await turn.locator(".timeline-range").textContent();
        await turn.getByRole("button", { name: "Zoom in" }).click();
        await turn.getByRole("button", { name: "Zoom in" }).click();
        const range1 = await turn.locator(".timeline-range").textContent();
        const box = await turn.locator(".timeline-stage").boundingBox();
        await page.mouse.move(box.x + box.width / 2, box.y + 30);
        await page.mouse.down();
        await page.mouse.move(box.x + box.width / 2 - 200, box.y + 30, { steps: 5 });
        await page.mouse.up();
        const range2 = await turn.locator(".timeline-range").textContent();
        // Two zooms about the middle leave a quarter of the plan: 15:11 to 25:19; dragging left
        // moves the view later.
        const start = (r) => r.split(" – ")[0].split(":").reduce((a, v) => a * 60 + Number(v), 0);
        check("zoom in, then drag to pan", range0 === "0:00 – 40:30" && range1 === "15:11 – 25:19 of 40:30" &&
              /^\d+:\d\d – \d+:\d\d of 40:30$/.test(range2) && start(range2) > start(range1),
              `${range0} | ${range1} | ${range2}`);
        await turn.getByRole("button", { name: "Show the whole plan" }).click();
        // Exports.
        const [csv] = await Promise.all([page.waitForEvent("download"), turn.locator(".export-csv").click()]);
        const lines = readFileSync(await csv.path(), "utf8").trim().split("\n");
        check("transitions as CSV", lines[0] === "time_s,event,automaton,from,to,command" &&
              lines.length === t.transitions.length + 1 && lines[1].split(",").length === 6, lines.slice(0, 2).join(" | "));
        const [json] = await Promise.all([page.waitForEvent("download"), turn.locator(".export-json").click()]);
        const downloaded = JSON.parse(readFileSync(await json.path(), "utf8"));
        check("trajectory as JSON", JSON.stringify(downloaded) === JSON.stringify(t));
        await turn.locator(".copy-plan").click();
        await turn.locator(".copy-note", { hasText: "copied" }).waitFor({ timeout: 5000 });
        const clip = await page.evaluate(() => navigator.clipboard.readText());
        check("copy the state plan", JSON.stringify(JSON.parse(clip)) === JSON.stringify(answer.state_plan));
      }
    }
  }
  check("examples start a thread each", (await page.locator("section.dialogue").count()) ===
        Object.values(examples.domains).flat().length);

  // --- Direct prompting answers offline too (the chain-of-thought default was tested above) ---
  await page.selectOption("#prompting", "direct");
  const direct = await runChip(page, "assembly", 0);
  check("an example in direct mode yields a chart", (await direct.locator("svg.timeline").count()) === 1);
  await page.selectOption("#prompting", "cot");

  // --- The model's eval (contract section 15): the shipped suite replayed, a table per domain ---
  const suite = JSON.parse(readFileSync(`${src}/config/eval/thesis.json`, "utf8"));
  await page.locator("#eval-title").click();
  await page.click("#eval-run");
  await page.waitForFunction(() => /^done/.test(document.getElementById("eval-status").textContent), null,
                             { timeout: 120000 });
  check("eval: a table per domain", (await page.locator("#eval-tables table.eval-table").count()) ===
        new Set(suite.map((x) => x.domain)).size);
  const evalVerdicts = await page.locator("#eval-tables tr[data-item]").evaluateAll((rows) => rows.map((r) => r.dataset.verdict));
  check("eval: every item equivalent from the recordings", evalVerdicts.length === suite.length &&
        evalVerdicts.every((v) => v === "equivalent"), JSON.stringify(evalVerdicts));
  check("eval: each table says its rates", (await page.locator("#eval-tables .eval-total").allTextContents())
        .every((t) => /equivalent \d+ \(100 %\)/.test(t)));
  await page.locator("#eval-title").click();

  // --- Enter sends, Shift+Enter breaks the line; a failed follow-up offers a new dialogue ---
  await runChip(page, "presentation", 0);
  const turns = await page.locator(".turn").count();
  await page.fill("#command", "");
  await page.focus("#command");
  await page.keyboard.type("and keep the computer on");
  await page.keyboard.press("Shift+Enter");
  await page.keyboard.type("too");
  check("Shift+Enter breaks the line", (await page.inputValue("#command")) === "and keep the computer on\ntoo" &&
        (await page.locator(".turn").count()) === turns);
  await page.keyboard.press("Enter");
  const followUp = page.locator(".turn").nth(turns);
  await followUp.locator(".error").waitFor({ timeout: 30000 });
  check("Enter sends", (await followUp.locator(".user").textContent()) === "and keep the computer on\ntoo");
  const err = await followUp.locator(".error").textContent();
  check("a follow-up without an LLM shows the server's error", /503 unavailable/.test(err) && /CTB_LLM_BASE_URL/.test(err), err);
  check("the failed follow-up offers a new dialogue", await followUp.locator("button.retry-new").isVisible());
  const dialogues = await page.locator("section.dialogue").count();
  await followUp.locator("button.retry-new").click();
  await page.locator("section.dialogue").nth(dialogues).locator(".error, .summary").first().waitFor({ timeout: 30000 });
  check("the new dialogue is a thread of its own", (await page.locator("section.dialogue").count()) === dialogues + 1 &&
        /restarted after a failed follow-up/.test(await page.locator("section.dialogue").last().locator(".dialogue-head").textContent()));

  // --- Changing domain says that a new dialogue starts ---
  await runChip(page, "presentation", 0);
  await page.selectOption("#domain", "assembly");
  check("changing domain ends the dialogue visibly", (await page.textContent("#session-label")) === "");
  await page.selectOption("#domain", "presentation");

  // --- Reload keeps the dialogue (GET /sessions/{id}, else this browser's copy) ---
  await runChip(page, "presentation", 1);
  const url = page.url();
  const sessionId = new URL(url).searchParams.get("session");
  await page.reload();
  await page.waitForSelector("body[data-ready='1']");
  check("the session is in the URL and survives a reload", /^[0-9a-f]{32}$/.test(sessionId || "") &&
        (await page.textContent("#session-label")) === `session ${sessionId.slice(0, 8)}` &&
        (await page.locator(".turn").count()) === 1 && (await page.locator(".turn svg.timeline").count()) === 1,
        `${url} ${await page.textContent("#session-label")}`);

  // GET /sessions/{id} (contract section 9): the server's turns, drawn with this browser's whole
  // answers where it has them, else with what the server kept.
  const kept = await lastAnswer(page);
  await page.route(`**/sessions/${sessionId}`, (route) => route.fulfill({
    status: 200, contentType: "application/json",
    body: JSON.stringify({ session: sessionId, domain: "presentation", turns: [
      { command: examples.domains.presentation[1].command, reasoning: kept.reasoning, state_plan: kept.state_plan,
        trajectory_summary: { status: "optimal", objective: kept.trajectory.objective }, at: "2026-01-01T00:00:00Z" },
      { command: "a turn this browser never saw", reasoning: "because", state_plan: { initial_state: {} },
        trajectory_summary: { status: "feasible", verified: true, objective: { kind: "cost", value: 9 } }, at: "2026-01-01T00:01:00Z" },
    ] }),
  }));
  await page.reload();
  await page.waitForSelector("body[data-ready='1']");
  const restored = page.locator(".turn");
  check("turns restored from GET /sessions/{id}", (await restored.count()) === 2 &&
        (await restored.nth(0).locator("svg.timeline").count()) === 1 &&
        (await restored.nth(1).locator("svg.timeline").count()) === 0 &&
        /feasible, verified · cost 9/.test(await restored.nth(1).locator(".summary").textContent()) &&
        /without its timeline/.test(await restored.nth(1).textContent()));
  await page.unroute(`**/sessions/${sessionId}`);

  // --- Live progress before the answer; Stop cancels the solver ---
  // The assembly example by cost: the first-plan engine's plan at once, Gecode's proof of
  // optimality seconds later (by makespan, and search_rescue, the plan meets a bound at once; the
  // neighbourhood rounds do not reach the cost bound here).
  await page.selectOption("#domain", "assembly");
  await page.selectOption("#objective", "cost");
  const n0 = await page.locator(".turn").count();
  await page.locator(".chip").nth(0).click();
  const live = page.locator(".turn").nth(n0);
  await live.locator(".progress .stage[data-stage]").waitFor({ timeout: 30000 });
  check("the stage is shown while it runs", await page.locator("#stop").isVisible() &&
        (await live.locator(".spinner").count()) === 1);
  await live.locator(".progress .solution").first().waitFor({ timeout: 60000 });
  const early = await live.locator(".summary").count();
  check("an improving plan is shown before the final answer", early === 0 &&
        /best so far: cost \d+ · \d+ events/.test(await live.locator(".solution").first().textContent()),
        await live.locator(".progress").textContent());
  // Gecode starts once the first-plan engine and its neighbourhood rounds are done (up to a
  // second after the first plan): wait for it rather than look once.
  let running = solverProcesses();
  for (let i = 0; i < 200 && running === 0; i++) {
    await sleep(50);
    running = solverProcesses();
  }
  check("a solver runs for it", running > 0);
  await page.click("#stop");
  let left = -1;
  for (let i = 0; i < 50; i++) {
    await sleep(100);
    left = solverProcesses();
    if (left === 0) break;
  }
  check("Stop cancels the job: no solver process left", left === 0, `${left} left`);
  check("the turn says it was stopped", /stopped/.test(await live.locator(".progress").textContent()) &&
        (await live.locator(".summary").count()) === 0 && !(await page.locator("#stop").isVisible()));
  await page.selectOption("#objective", "");

  // --- The explanation of an infeasible answer (the shape of contract section 9) ---
  const infeasible = {
    session: "f".repeat(32),
    state_plan: { initial_state: {}, end_state: {}, constraints: { temporal: { OnWithin10: { lower_bound: 0, upper_bound: 10 } } } },
    trajectory: {
      status: "infeasible", verified: false, objective: { kind: "cost", value: null },
      state_plan_summary: [{ pointer: "/initial_state", text: "Everything starts off." },
                           { pointer: "/constraints/temporal/OnWithin10", text: "The projector is on within 10 s." }],
      explanation: {
        conflicts: [{ constraints: ["/constraints/temporal/OnWithin10"], text: "The projector needs 30 s to warm up, more than 10 s." }],
        relaxations: [{ changes: [{ pointer: "/constraints/temporal/OnWithin10/upper_bound", value: 30 }],
                        text: "Allow 30 s for the projector to turn on." }],
      },
    },
  };
  const sent = [];
  await page.route("**/plan", async (route) => {
    sent.push(JSON.parse(route.request().postData()));
    const body = sent.length === 1
      ? `event: stage\ndata: {"stage":"solving"}\n\nevent: done\ndata: ${JSON.stringify(infeasible)}\n\n`
      : `event: error\ndata: {"status":503,"error":{"code":"unavailable","message":"mocked"}}\n\n`;
    await route.fulfill({ status: 200, contentType: "text/event-stream", body });
  });
  await page.click("#new-session");
  await page.fill("#command", "turn the projector on within 10 s");
  await page.keyboard.press("Enter");
  const inf = page.locator(".turn").last();
  await inf.locator(".explanation").waitFor({ timeout: 10000 });
  check("infeasible: the conflict in words, its parts highlighted",
        /warm up/.test(await inf.locator(".conflict p").textContent()) &&
        (await inf.locator(".conflict mark").textContent()) === "The projector is on within 10 s." &&
        (await inf.locator(".plan-words li.in-conflict").count()) === 1);
  check("the plan in words beside the plan", (await inf.locator(".plan-words li").count()) === 2);
  await inf.locator("button.relax").click();
  await page.locator(".turn").last().locator(".error").waitFor({ timeout: 10000 });
  check("a relaxation is sent as a follow-up", sent.length === 2 && sent[1].command === "Allow 30 s for the projector to turn on." &&
        sent[1].session === infeasible.session && sent[1].stream === true, JSON.stringify(sent[1]));
  await page.unroute("**/plan");

  // --- Accessibility: labels, focus order, contrast ---
  const unlabelled = await page.evaluate(() => [...document.querySelectorAll("button, select, textarea, input")]
    .filter((e) => !(e.labels?.length || e.getAttribute("aria-label") || e.textContent.trim()))
    .map((e) => e.outerHTML.slice(0, 80)));
  check("every control has a label", unlabelled.length === 0, JSON.stringify(unlabelled));
  await page.evaluate(() => localStorage.removeItem("ctburton.current.v1"));
  await page.goto(base + "/");
  await page.waitForSelector("body[data-ready='1']");
  await page.evaluate(() => { document.activeElement?.blur(); window.scrollTo(0, 0); });
  const order = [];
  for (let i = 0; i < 16; i++) {
    await page.keyboard.press("Tab");
    order.push(await page.evaluate(() => document.activeElement.id || document.activeElement.className || document.activeElement.tagName));
  }
  const at = (id) => order.indexOf(id);
  check("focus order: skip link, settings, examples, command, send", order[0] === "skip" &&
        at("domain") < at("prompting") && at("prompting") < at("objective") && at("objective") < at("new-session") &&
        at("new-session") < at("chip") && at("chip") < at("command") && at("command") < at("send"), JSON.stringify(order));
  const lowContrast = await page.evaluate(() => {
    const rgb = (s) => (s.match(/[\d.]+/g) || []).slice(0, 4).map(Number);
    const lum = ([r, g, b]) => [r, g, b].map((v) => v / 255).map((v) => (v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4))
      .reduce((a, v, i) => a + v * [0.2126, 0.7152, 0.0722][i], 0);
    const bg = (e) => {
      for (; e; e = e.parentElement) {
        const c = rgb(getComputedStyle(e).backgroundColor);
        if (c.length === 3 || c[3] > 0) return c;
      }
      return [255, 255, 255];
    };
    const bad = [];
    for (const e of document.querySelectorAll("body *")) {
      if (!e.childNodes.length || ![...e.childNodes].some((n) => n.nodeType === 3 && n.textContent.trim())) continue;
      if (!e.getClientRects().length || e.closest("svg")) continue;
      const fg = rgb(getComputedStyle(e).color), b = bg(e);
      const [l1, l2] = [lum(fg), lum(b)].sort((x, y) => y - x);
      const ratio = (l1 + 0.05) / (l2 + 0.05);
      if (ratio < 4.5) bad.push(`${e.tagName}.${e.className} ${ratio.toFixed(2)}`);
    }
    return bad;
  });
  check("text contrast at least 4.5:1", lowContrast.length === 0, JSON.stringify(lowContrast));
  check("the notice can be dismissed and stays dismissed", await (async () => {
    await page.click("#llm-notice-close");
    await page.reload();
    await page.waitForSelector("body[data-ready='1']");
    return !(await page.locator("#llm-notice").isVisible());
  })());

  // --- Phone ---
  for (const [w, h] of [[390, 844], [360, 740]]) {
    const phone = await newPage(w, h);
    await runChip(phone, "presentation", 0);
    const sw = await phone.evaluate(() => document.scrollingElement.scrollWidth);
    check(`at ${w} px nothing scrolls sideways`, sw <= w, `scrollWidth ${sw}`);
    check(`at ${w} px the chart fits`, (await phone.locator("svg.timeline").evaluate((s) => s.getBoundingClientRect().right)) <= w);
    if (w === 390) {
      await phone.locator(".turn .summary").scrollIntoViewIfNeeded();
      await phone.evaluate(() => window.scrollBy(0, -60));
      await phone.screenshot({ path: `${out}/chat-390x844.png`, fullPage: false });
    }
    await phone.locator("svg.timeline rect.segment[data-location=projOn]").click();
    check(`at ${w} px a tap opens a card`, await phone.locator(".timeline-card").isVisible());
    await phone.context().close();
  }
  await page.screenshot({ path: `${out}/chat.png`, fullPage: true });
  console.log(`screenshots: ${out}/chat-1400x900.png ${out}/chat-390x844.png`);
  check("no failed requests (favicon included)", bad.length === 0, bad.join("; "));
  check("no script errors", scriptErrors.length === 0, scriptErrors.join("; "));
} catch (e) {
  check("browser flow", false, String(e.stack || e));
} finally {
  await browser.close();
  server.kill("SIGTERM");
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
