// Execution you can watch (issue 21), end to end: the real `ctburton serve --demo` on a free
// loopback port, the page in Debian's headless Chromium (playwright-core). Plans the
// search_rescue example "Rescue person 1 fast, together" from the shipped recordings (robot 1
// alone: goal at 0:11), starts execution and sees the "now" line move with the executed part
// hatched, reports from robot 1's openDoor1 marker that the move failed, and sees the replanned
// future (robot 2 comes to open door 1) drawn against the old one (the diff, the old command
// hollow, the old goal); then, from robot 1's row name with the keyboard, that its arrival
// took 3 s longer, which replans when the late arrival happens, and the execution goes on to
// the goal. Also: the session records both replans, a reload restores them, and at phone
// width (390) the report box and the replanned turn fit. Screenshots go to OUTPUT_DIR.
//   node execute_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { spawn } from "node:child_process";
import { mkdirSync, openSync, readFileSync, rmSync } from "node:fs";
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
const CHIP = examples.domains.search_rescue.findIndex((e) => /Person 1 as fast as possible/.test(e.command));

const port = await new Promise((resolve) => {
  const s = net.createServer();
  s.listen(0, "127.0.0.1", () => { const p = s.address().port; s.close(() => resolve(p)); });
});
const env = { ...process.env, CTB_CONFIG_DIR: `${src}/config`, CTB_PROMPTS_DIR: `${src}/prompts` };
for (const k of ["CTB_LLM_BASE_URL", "CTB_LLM_REPLAY", "CTB_LLM_API_KEY"]) delete env[k];
const dataDir = `/tmp/ctb-browser-execute-${process.pid}`;
const server = spawn(bin, ["serve", "--port", String(port), "--demo", "--data-dir", dataDir],
  { cwd: src, env, stdio: ["ignore", "ignore", openSync(`${out}/execute-server.log`, "w")] });
const base = `http://127.0.0.1:${port}`;
for (let i = 0; i < 200; i++) {
  try { if ((await fetch(`${base}/healthz`)).ok) break; } catch {}
  await sleep(50);
}

const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
const bad = [];
const scriptErrors = [];
async function newPage(width, height) {
  const context = await browser.newContext({ viewport: { width, height } });
  const page = await context.newPage();
  page.on("pageerror", (e) => scriptErrors.push(String(e)));
  page.on("response", (r) => { if (r.status() >= 400 && !/\/sessions\//.test(r.url())) bad.push(`${r.status()} ${r.url()}`); });
  page.replans = [];  // the bodies of POST /replan, in order
  page.on("request", (r) => { if (r.method() === "POST" && r.url().endsWith("/replan")) page.replans.push(JSON.parse(r.postData())); });
  await page.goto(base + "/");
  await page.waitForSelector("body[data-ready='1']");
  return page;
}

// Plans the example and waits for its answer; returns the turn.
async function planExample(page) {
  await page.selectOption("#domain", "search_rescue");
  await page.locator(".chip").nth(CHIP).click();
  const turn = page.locator(".turn").first();
  await turn.locator(".summary").waitFor({ timeout: 120000 });
  return turn;
}

// The answers this browser kept (store.js), last dialogue.
const keptTurns = (page) => page.evaluate(() => {
  const list = JSON.parse(localStorage.getItem("ctburton.dialogues.v1") || "[]");
  return list.length ? list[list.length - 1].turns : [];
});
const pastWidth = (turn) => turn.locator("svg.timeline rect.past").evaluate((r) => +r.getAttribute("width"));
const future = (t) => t.transitions.filter((x) => !x.executed && !x.observed);
const has = (list, a, from, to) => list.some((x) => x.automaton === a && x.from === from && x.to === to);

// Starts the execution at ×1 and stops it within the first second (robot 1 reaches door 1 at
// 0:01): the line moved and the part behind it is hatched. Everything is watched from inside the
// page, frame by frame, and Stop is clicked there on the first frame whose now (plan seconds)
// reaches `stopAt` (0.25 when not given), so that the replan's now (whole seconds) is known and a
// slow machine (long round trips to the browser) changes nothing. Returns the execution's now.
async function startAndStop(page, turn, name, stopAt = null) {
  const toggle = turn.locator(".exec-toggle");
  check(`${name}: the plan has a Start control`, (await toggle.textContent()) === "Start execution");
  const watched = turn.evaluate((t, at) => new Promise((done) => {
    const box = t.querySelector(".exec");
    const line = () => t.querySelector("svg.timeline line.now-line");
    const past = () => t.querySelector("svg.timeline rect.past");
    const seen = () => ({ x: +line().getAttribute("x1"), w: +past().getAttribute("width"), now: +box.dataset.now });
    let first = null;
    const tick = () => {
      const running = +box.dataset.now > 0 && line() && past();
      if (running && first === null) first = seen();
      if (running && first !== null && +box.dataset.now >= at && +box.dataset.now > first.now) {
        const last = seen();
        box.querySelector(".exec-toggle").click();
        done({ first, last });
      } else requestAnimationFrame(tick);
    };
    tick();
  }), stopAt ?? 0.25);
  await toggle.click();
  const { first, last } = await watched;
  check(`${name}: the now line moves across the timeline`, last.x > first.x, `${first.x} -> ${last.x}`);
  check(`${name}: the executed part is drawn hatched behind it`, last.w > first.w && first.w >= 0, `${first.w} -> ${last.w}`);
  check(`${name}: Stop pauses`, (await toggle.textContent()) === "Resume");
  return +(await turn.locator(".exec").getAttribute("data-now"));
}

try {
  // --- Desktop ---
  const page = await newPage(1280, 900);
  const first = await planExample(page);
  const planned = (await keptTurns(page))[0].answer;
  const t0 = planned.trajectory;
  check("the example is planned: robot 1 alone, goal at 0:11", t0.status === "optimal" && t0.goal_reached_at === 11 &&
    has(t0.transitions, "robot1", "atDoor1", "door1Opening") && !t0.transitions.some((x) => x.automaton === "robot2"),
    JSON.stringify(t0.transitions));
  check("the speeds ×1, ×10 and ×60 are offered",
    JSON.stringify(await first.locator(".exec-speed select option").evaluateAll((o) => o.map((x) => x.value))) === '["1","10","60"]');
  const stoppedAt = await startAndStop(page, first, "desktop", 0.6);
  check("it was stopped before robot 1's openDoor1 (0:01)", stoppedAt >= 0.6 && stoppedAt < 1, String(stoppedAt));
  check("what was due is dispatched (the log lists robot 1's goToDoor1)",
    (await first.locator(".exec-log li").allTextContents()).some((s) => /robot1\s+goToDoor1/.test(s)));
  check("every row takes reports once started", (await first.locator("svg.timeline .rowpick").count()) === Object.keys(t0.timelines).length);

  // "This move failed", from robot 1's openDoor1 marker on its row.
  await first.locator('svg.timeline g.command[data-automaton="robot1"][data-command="openDoor1"]').click();
  const box = first.locator(".fault-box");
  check("a click on the row opens the report box", await box.isVisible());
  check("the box names the move", /atDoor1 → door1Opening \(openDoor1\)/.test(await box.textContent()), await box.textContent());
  check("the box takes the keyboard focus", await box.locator(".fault-fail").evaluate((b) => b === document.activeElement));
  await page.screenshot({ path: `${out}/execute-report-1280.png` });
  await box.locator(".fault-fail").click();
  const second = page.locator(".turn.replan-turn").first();
  await second.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  const r1 = page.replans[0];
  check("the report POSTs /replan in the session with the move blocked",
    r1 && r1.session === planned.session && JSON.stringify(r1.blocked) === JSON.stringify([{ automaton: "robot1", from: "atDoor1", to: "door1Opening" }]),
    JSON.stringify(r1));
  check("from now (0:00.6, sent as 1 s) with the history dispatched so far (robot 1's goToDoor1 at 0)",
    r1 && JSON.stringify(r1.executed) === JSON.stringify([{ time: 0, automaton: "robot1", from: "outside", to: "goingToDoor1" }]) &&
    r1.now === 1, JSON.stringify(r1 && { now: r1.now, executed: r1.executed }));
  const kept1 = (await keptTurns(page))[1];
  const t1 = kept1?.answer?.trajectory;
  // By hand: robot 1 arrives at door 1 at 1 and can no longer open it, and nothing else leads it
  // on, so robot 2 leaves at 1, reaches door 1 at 2 and opens it (1 s); robot 1 goes in at 3,
  // takes 4 s to door 3 and 5 s to person 1: goal at 12.
  check("the replan is optimal, verified, and robot 2 comes to open door 1",
    t1 && t1.status === "optimal" && t1.verified && has(future(t1), "robot2", "atDoor1", "door1Opening"), JSON.stringify(t1?.transitions));
  check("the blocked move is not in the replanned future", t1 && !has(future(t1), "robot1", "atDoor1", "door1Opening"));
  check("the goal is where it is by hand (0:12)", t1 && t1.goal_reached_at === 12, `${t1?.goal_reached_at} now ${r1?.now}`);
  check("the replanned turn says what was reported", /Replan at 0:01: robot1: the move atDoor1 → door1Opening \(openDoor1\) failed/
    .test(await second.locator(".user").textContent()), await second.locator(".user").textContent());
  const diffText = await second.locator(".diff").textContent();
  check("the diff against the old plan is shown, robot 1's openDoor1 dropped",
    /dropped/.test(diffText) && /robot1 openDoor1: atDoor1 → door1Opening, was at 0:01/.test(diffText) &&
    /goal 0:12 \(was 0:11\)/.test(diffText), diffText);
  check("the old command is drawn hollow and struck through where it was",
    await second.locator('svg.timeline g.ghost-dropped[data-command="openDoor1"][data-automaton="robot1"] text.ghost-label').count() === 1);
  check("the new commands are marked", await second.locator('svg.timeline g.command.diff-added[data-automaton="robot2"]').count() >= 1);
  check("the old goal is drawn", await second.locator("svg.timeline .previous-goal").count() === 1);
  check("the replanned turn's history is hatched up to its now", await pastWidth(second) > 0);
  check("the first turn's execution hands over", /goes on in the replanned plan below/.test(await first.locator(".exec-status").textContent()) &&
    await first.locator(".exec-toggle").isDisabled());
  check("the replanned execution waits where it stopped", (await second.locator(".exec-toggle").textContent()) === "Resume");
  await second.scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${out}/execute-replanned-1280.png` });

  // "This took longer", from robot 1's row name, with the keyboard: its arrival at door 1 (due at
  // 0:01) comes 3 s late; the replan happens when it comes.
  const rowName = second.locator('svg.timeline .rowpick[data-automaton="robot1"]');
  await rowName.focus();
  await page.keyboard.press("Enter");
  const box2 = second.locator(".fault-box");
  check("Enter on a row's name opens the report box", await box2.isVisible());
  await page.keyboard.press("Escape");
  check("Escape closes it and gives the focus back", !(await box2.count()) &&
    await rowName.evaluate((g) => g === document.activeElement));
  await page.keyboard.press("Enter");
  await box2.locator(".fault-seconds").fill("3");
  check("the box says when the stay ends", /robot1 leaves goingToDoor1 then, not at 0:01/.test(await box2.textContent()), await box2.textContent());
  await box2.locator(".fault-late").click();
  await second.locator(".exec-speed select").selectOption("10");
  await second.locator(".exec-toggle").click();
  const third = page.locator(".turn.replan-turn").nth(1);
  await third.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  const r2 = page.replans[1];
  check("the late arrival replans at its time (0:04), with the blocked move still blocked",
    r2 && r2.now === 4 && r2.blocked.length === 1 && r2.executed.some((e) => e.automaton === "robot1" && e.from === "goingToDoor1" &&
      e.to === "atDoor1" && e.time === 4), JSON.stringify(r2));
  check("every history entry is at or before now", r2 && r2.executed.every((e) => e.time <= r2.now));
  check("the second replanned turn says so", /robot1 left goingToDoor1 3 s late/.test(await third.locator(".user").textContent()));
  const t2 = (await keptTurns(page))[2]?.answer?.trajectory;
  check("the second replan is verified and keeps robot 1 out of door1Opening",
    t2 && t2.verified && (t2.status === "optimal" || t2.status === "feasible") && !has(future(t2), "robot1", "atDoor1", "door1Opening"));
  // The clock ran before the late arrival, so the execution runs on to the goal.
  await third.locator(".exec-toggle", { hasText: "Finished" }).waitFor({ timeout: 60000 });
  check("the execution reaches the goal", /Goal reached at 0:\d\d/.test(await third.locator(".exec-status").textContent()));
  const log = await third.locator(".exec-log li").allTextContents();
  check("its log ends with the goal", log.length > 1 && /goal reached/.test(log.at(-1)), JSON.stringify(log));
  const session = await (await fetch(`${base}/sessions/${planned.session}`)).json();
  check("the session records both replans as turns", JSON.stringify(session.turns?.map((x) => x.command).slice(1)) === '["(replan)","(replan)"]',
    JSON.stringify(session.turns?.map((x) => x.command)));
  await third.screenshot({ path: `${out}/execute-finished-1280.png` });

  await page.reload();
  await page.waitForSelector("body[data-ready='1']");
  check("a reload restores the replanned turns with their charts and labels",
    await page.locator(".turn.replan-turn svg.timeline").count() === 2 &&
    /Replan at .*failed/.test(await page.locator(".turn.replan-turn .user").first().textContent()));
  await page.context().close();

  // --- Phone ---
  const phone = await newPage(390, 844);
  const pturn = await planExample(phone);
  await startAndStop(phone, pturn, "phone");
  await pturn.locator('svg.timeline g.command[data-automaton="robot1"][data-command="openDoor1"] path.command-mark').click();
  const pbox = pturn.locator(".fault-box");
  const fits = await pbox.evaluate((b) => { const r = b.getBoundingClientRect(); return r.left >= 0 && r.right <= 390; });
  check("at 390 px the report box fits", fits);
  await pbox.scrollIntoViewIfNeeded();
  await phone.screenshot({ path: `${out}/execute-report-390.png` });
  await pbox.locator(".fault-fail").click();
  const preplan = phone.locator(".turn.replan-turn").first();
  await preplan.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  check("at 390 px the replanned turn has its chart and diff", await preplan.locator("svg.timeline").count() === 1 &&
    await preplan.locator(".diff").count() === 1);
  const sw = await phone.evaluate(() => document.scrollingElement.scrollWidth);
  check("at 390 px nothing scrolls sideways", sw <= 390, `scrollWidth ${sw}`);
  await preplan.locator(".chart").scrollIntoViewIfNeeded();
  await phone.evaluate(() => window.scrollBy(0, 120));
  await phone.screenshot({ path: `${out}/execute-replanned-390.png` });
  await phone.context().close();

  console.log(`screenshots: ${out}/execute-*.png`);
  check("no failed requests", bad.length === 0, bad.join("; "));
  check("no script errors", scriptErrors.length === 0, scriptErrors.join("; "));
} catch (e) {
  check("browser flow", false, String(e.stack || e));
} finally {
  await browser.close();
  server.kill("SIGTERM");
  await sleep(300);
  rmSync(dataDir, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
