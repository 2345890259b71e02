// End-to-end, the team panel (issue 22) and a fault reported in words (issue 21): the real `ctburton serve` with a loopback mock LLM (a
// small HTTP server here that answers drafts with the recorded draft and commands with a state
// plan for the drone team), the page in Debian's headless Chromium. A user opens the panel and
// sees the diagram, pastes a team with an error and sees it marked at its place, fixes it, saves
// it, sees its diagram, plans with it in the chat, and drafts a team from words. Screenshots
// (desktop and phone width) go to OUTPUT_DIR.
//   node domains_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { spawn } from "node:child_process";
import { mkdirSync, openSync, readFileSync, rmSync } from "node:fs";
import http from "node:http";
import net from "node:net";
import { chromium } from "playwright-core";

const [bin, src, out] = process.argv.slice(2);
mkdirSync(out, { recursive: true });
let passed = 0, failed = 0;
const check = (name, ok, detail = "") => {
  if (ok) { passed++; console.log(`ok   ${name}`); } else { failed++; console.log(`FAIL ${name} ${detail}`); }
};
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const freePort = () => new Promise((resolve) => {
  const s = net.createServer();
  s.listen(0, "127.0.0.1", () => { const p = s.address().port; s.close(() => resolve(p)); });
});

const drones = JSON.parse(readFileSync(`${src}/config/templates/drones.json`, "utf8"));
const draftAnswer = readFileSync(`${src}/tests/recordings/draft/good.txt`, "utf8");
const plan = {
  initial_state: { drone1: "inHangar", drone2: "inHangar", hangarDoor: "closed" },
  end_state: { maintenance_constraint: "true", goal_constraint: "drone1l[i+1]==atA /\\ drone2l[i+1]==atB" },
  constraints: { episodes: {}, temporal: {}, event: {} },
};

// What the mock reads in a fault reported in words (issue 21): drone 2 cannot fly to B.
const report = { blocked: [{ automaton: "drone2", from: "airborne", to: "flyingToB" }],
                 restatement: "Drone 2 cannot fly to B." };

// The mock LLM: OpenAI chat completions on loopback.
const prompts = [];
const llm = http.createServer((req, res) => {
  let body = "";
  req.on("data", (c) => { body += c; });
  req.on("end", () => {
    const msgs = JSON.parse(body).messages || [];
    const text = msgs.map((m) => m.content).join("\n");
    prompts.push(text);
    const content = /Describe|Description of the team/.test(text) ? draftAnswer
      : /operator reports in words/.test(text) ? JSON.stringify(report) : JSON.stringify(plan);
    res.setHeader("Content-Type", "application/json");
    res.end(JSON.stringify({ id: "mock", object: "chat.completion", model: "mock",
      choices: [{ index: 0, finish_reason: "stop", message: { role: "assistant", content } }] }));
  });
});
const llmPort = await freePort();
await new Promise((r) => llm.listen(llmPort, "127.0.0.1", r));

const port = await freePort();
const env = { ...process.env, CTB_CONFIG_DIR: `${src}/config`, CTB_PROMPTS_DIR: `${src}/prompts`,
              CTB_LLM_BASE_URL: `http://127.0.0.1:${llmPort}/v1`, CTB_LLM_MODEL: "mock" };
for (const k of ["CTB_LLM_REPLAY", "CTB_LLM_API_KEY"]) delete env[k];
const dataDir = `/tmp/ctb-browser-domains-${process.pid}`;
rmSync(dataDir, { recursive: true, force: true });
const serverLog = openSync(`${out}/browser-domains-server.log`, "w");
const server = spawn(bin, ["serve", "--port", String(port), "--data-dir", dataDir],
                     { cwd: src, env, stdio: ["ignore", "ignore", serverLog] });
const base = `http://127.0.0.1:${port}`;
for (let i = 0; i < 200; i++) {
  try { if ((await fetch(`${base}/healthz`)).ok) break; } catch {}
  await sleep(50);
}

const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"],
});
const scriptErrors = [];
const refused = [];
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  const page = await context.newPage();
  page.on("pageerror", (e) => scriptErrors.push(String(e)));
  page.on("response", (r) => { if (r.status() >= 400 && !/\/sessions\//.test(r.url())) refused.push(`${r.status()} ${r.url()}`); });
  await page.goto(base);
  await page.waitForSelector("body[data-ready='1']");

  // The panel shows the selected domain's diagram.
  await page.click("#team-toggle");
  check("the Team button opens the panel", await page.isVisible("#team"));
  check("the button says it is expanded", (await page.getAttribute("#team-toggle", "aria-expanded")) === "true");
  await page.waitForFunction(() => document.getElementById("team-diagram").naturalWidth > 0);
  const shipped = await page.inputValue("#domain");
  check("the diagram of the selected domain is drawn",
        (await page.getAttribute("#team-diagram", "src")) === `/domains/${shipped}/diagram`);
  check("a shipped domain says how to change it", /shipped/.test(await page.textContent("#team-source")));

  // A new team pasted with an error: refused, and the error is marked at its place.
  await page.click("#team-new");
  const bad = structuredClone(drones);
  bad.automata[0].transitions[1].guard = "{self}l[i]==nowhere";
  await page.fill("#team-editor", JSON.stringify(bad));
  await page.click("#team-save");
  await page.waitForSelector(".team-error");
  const errors = await page.locator(".team-error").allTextContents();
  check("the error names its pointer and the instance",
        errors.some((e) => e.includes("/automata/0/transitions/1/guard") && e.includes("drone1")), JSON.stringify(errors));
  check("the editor is marked invalid", (await page.getAttribute("#team-editor", "aria-invalid")) === "true");
  const selected = await page.evaluate(() => {
    const ed = document.getElementById("team-editor");
    return ed.value.slice(ed.selectionStart, ed.selectionEnd);
  });
  check("the error's place is selected in the text", selected.includes("nowhere"), selected);
  check("nothing was stored", (await (await fetch(`${base}/domains/drones`)).status) === 404);
  await page.screenshot({ path: `${out}/domains-error.png`, fullPage: false });

  // Fixed and saved: selected in the page, its diagram drawn.
  await page.fill("#team-editor", JSON.stringify(drones));
  await page.click("#team-save");
  await page.waitForFunction(() => /saved drones/.test(document.getElementById("team-status").textContent));
  check("the fixed team is saved", (await (await fetch(`${base}/domains/drones`)).status) === 200);
  check("the page selects the new team", (await page.inputValue("#domain")) === "drones");
  await page.waitForFunction(() => {
    const img = document.getElementById("team-diagram");
    return /drones\/diagram$/.test(img.src) && img.complete && img.naturalWidth > 0;
  });
  check("the errors are gone", (await page.locator(".team-error").count()) === 0);
  check("the team says it is stored", /stored through the API, version 1/.test(await page.textContent("#team-source")));
  await page.screenshot({ path: `${out}/domains-saved.png`, fullPage: true });

  // Planning with it in the chat.
  await page.selectOption("#prompting", "direct");
  await page.fill("#command", "drone 1 to A and drone 2 to B");
  await page.press("#command", "Enter");
  const turn = page.locator(".turn").last();
  await turn.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  const summary = await turn.locator(".summary").textContent().catch(() => "");
  check("the plan for the new team is optimal", /optimal/.test(summary), summary);
  const rows = await turn.locator("svg.timeline .rowlabel").allTextContents();
  check("its chart has a row per drone and the door",
        ["drone1", "drone2", "hangarDoor"].every((r) => rows.includes(r)), JSON.stringify(rows));
  check("the prompt described the new team", prompts.some((p) => p.includes("hangarDoor") && p.includes("drone 1 to A")));

  // Executing it, a fault reported in words from drone 2's row: the LLM reads it into a blocked
  // move, the replan says what it understood, and drone 2 can no longer reach B.
  const replans = [];
  page.on("request", (r) => { if (r.method() === "POST" && r.url().endsWith("/replan")) replans.push(JSON.parse(r.postData())); });
  await turn.locator(".exec-toggle").click();
  await sleep(300);
  await turn.locator(".exec-toggle").click();
  await turn.locator('svg.timeline .rowpick[data-automaton="drone2"]').click();
  const box = turn.locator(".fault-box");
  check("with an LLM, the report box offers words", await box.locator(".fault-words").isVisible());
  await box.locator(".fault-words").fill("drone 2's flight to B failed");
  await page.screenshot({ path: `${out}/domains-fault-words.png` });
  await box.locator(".fault-tell").click();
  const replanned = page.locator(".turn.replan-turn").last();
  await replanned.locator(".summary, .error").first().waitFor({ timeout: 120000 });
  check("the replan sent the words as command", replans.length === 1 && replans[0].command === "drone 2's flight to B failed" &&
        typeof replans[0].now === "number", JSON.stringify(replans));
  check("the LLM was asked with the report", prompts.some((p) => /operator reports in words/.test(p) && p.includes("drone 2's flight to B failed")));
  const understood = await replanned.locator(".report").textContent().catch(() => "");
  check("the replanned turn says what was understood", /Drone 2 cannot fly to B/.test(understood) &&
        /drone2: airborne → flyingToB blocked/.test(understood), understood);
  check("without that move drone 2 cannot reach B", /infeasible/.test(await replanned.locator(".summary").textContent()));
  await replanned.scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${out}/domains-replanned-words.png` });

  // A draft from words: into the editor, with what the LLM understood and left open.
  await page.click("#team-drafting summary");
  await page.fill("#team-description", "two drones that take off in 5 s and fly to A or B in 20 s");
  await page.click("#team-draft");
  await page.waitForSelector("#team-draft-answer:not([hidden])");
  check("the draft is in the editor", (await page.inputValue("#team-editor")).includes("\"hangar_drones\""));
  check("the restatement is shown", (await page.textContent("#team-restatement")).length > 10);
  check("the open questions are listed", (await page.locator("#team-questions li").count()) > 0);
  check("a draft is not stored", (await (await fetch(`${base}/domains/hangar_drones`)).status) === 404);
  await page.screenshot({ path: `${out}/domains-draft.png`, fullPage: true });

  // Phone width: the panel fits.
  const phone = await browser.newContext({ viewport: { width: 390, height: 844 } });
  const p2 = await phone.newPage();
  p2.on("pageerror", (e) => scriptErrors.push(String(e)));
  await p2.goto(base);
  await p2.waitForSelector("body[data-ready='1']");
  await p2.selectOption("#domain", "drones");
  await p2.click("#team-toggle");
  await p2.waitForFunction(() => document.getElementById("team-diagram").naturalWidth > 0);
  await p2.click("#team-edit summary");
  const overflow = await p2.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  check("no sideways scrolling at phone width", overflow <= 0, `${overflow}px`);
  await p2.screenshot({ path: `${out}/domains-phone.png`, fullPage: true });
  // ... and so does the report box with its words row, over a plan being executed.
  await p2.fill("#command", "drone 1 to A and drone 2 to B");
  await p2.press("#command", "Enter");
  const phoneTurn = p2.locator(".turn").last();
  await phoneTurn.locator(".summary").waitFor({ timeout: 120000 });
  await phoneTurn.locator(".exec-toggle").click();
  await sleep(300);
  await phoneTurn.locator(".exec-toggle").click();
  await phoneTurn.locator('svg.timeline .rowpick[data-automaton="drone2"]').click();
  const phoneBox = phoneTurn.locator(".fault-box");
  const wordsBox = await phoneBox.locator(".fault-words-row").boundingBox();
  const boxBox = await phoneBox.boundingBox();
  check("at phone width the words row fits in the report box, inside the screen",
        wordsBox && boxBox && wordsBox.x >= boxBox.x && wordsBox.x + wordsBox.width <= boxBox.x + boxBox.width + 1 &&
        boxBox.x >= 0 && boxBox.x + boxBox.width <= 390, JSON.stringify({ wordsBox, boxBox }));
  await phoneBox.scrollIntoViewIfNeeded();
  await p2.screenshot({ path: `${out}/domains-fault-words-phone.png` });

  check("no script errors", scriptErrors.length === 0, scriptErrors.join("; "));
  check("the only refused request is the bad team's",
        refused.length === 1 && /400 .*\/domains$/.test(refused[0]), JSON.stringify(refused));
} catch (e) {
  failed++;
  console.log(`FAIL the test stopped: ${e.stack || e}`);
} finally {
  await browser.close();
  server.kill("SIGTERM");
  llm.close();
  rmSync(dataDir, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
