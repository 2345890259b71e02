// End-to-end: the real `ctburton serve` on a free loopback port (no LLM configured, so /plan
// answers the thesis' test prompt 1 from the shipped recordings), the web page in Debian's
// headless Chromium driven by playwright-core: type a command, wait for the chart, check it,
// take a screenshot into the test log folder.
//   node chat_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { spawn } from "node:child_process";
import { mkdirSync } from "node:fs";
import net from "node:net";
import { chromium } from "playwright-core";

const [bin, src, out] = process.argv.slice(2);
const TP1 = "The computer and projector start in the off state, and the connection is disconnected. " +
  "The projector should turn on and stay on for 1800 seconds, following which everything should turn off " +
  "within 600 seconds. In addition, the projector should turn on within 60 seconds.";
let passed = 0, failed = 0;
const check = (name, ok, detail = "") => {
  if (ok) { passed++; console.log(`ok   ${name}`); } else { failed++; console.log(`FAIL ${name} ${detail}`); }
};

const port = await new Promise((resolve) => {
  const s = net.createServer();
  s.listen(0, "127.0.0.1", () => { const p = s.address().port; s.close(() => resolve(p)); });
});
const env = { ...process.env, CTB_CONFIG_DIR: `${src}/config`, CTB_PROMPTS_DIR: `${src}/prompts` };
for (const k of ["CTB_LLM_BASE_URL", "CTB_LLM_REPLAY", "CTB_LLM_API_KEY"]) delete env[k];
const dataDir = `/tmp/ctb-browser-data-${process.pid}`;
const server = spawn(bin, ["serve", "--port", String(port), "--demo", "--data-dir", dataDir], { cwd: src, env, stdio: ["ignore", "ignore", "inherit"] });
const base = `http://127.0.0.1:${port}`;
for (let i = 0; i < 200; i++) {
  try { if ((await fetch(`${base}/healthz`)).ok) break; } catch {}
  await new Promise((r) => setTimeout(r, 50));
}

const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 900 } });
  const consoleErrors = [];
  page.on("pageerror", (e) => consoleErrors.push(String(e)));
  await page.goto(base + "/");
  await page.waitForSelector("#domain option[value=presentation]", { state: "attached" });
  check("the page lists the domains", (await page.locator("#domain option").count()) === 3);
  await page.selectOption("#domain", "presentation");
  await page.fill("#command", TP1);
  await page.click("#send");
  await page.waitForSelector("svg.timeline", { timeout: 90000 });
  const rows = await page.locator("svg.timeline .rowlabel").allTextContents();
  check("one chart row per automaton", JSON.stringify(rows) === JSON.stringify(["comp", "conn", "proj"]), JSON.stringify(rows));
  const locations = await page.locator("svg.timeline rect.segment").evaluateAll(
    (els) => els.map((e) => `${e.dataset.automaton}:${e.dataset.location}`));
  check("segments per location", locations.includes("proj:projOn") && locations.includes("proj:projWarmUp") &&
        locations.includes("conn:connected"), JSON.stringify(locations));
  check("markers at commands", (await page.locator("svg.timeline path.command").count()) >= 3);
  const summary = await page.locator(".turn .summary").first().textContent();
  check("the answer is optimal and verified", /optimal, verified/.test(summary) && /goal at 2430 s/.test(summary), summary);
  check("the reasoning is shown", (await page.locator("details summary", { hasText: "Reasoning" }).count()) === 1);
  check("a session was opened", /session [0-9a-f]{8}/.test(await page.locator("#session-label").textContent()));
  mkdirSync(out, { recursive: true });
  await page.screenshot({ path: `${out}/chat.png`, fullPage: true });
  console.log(`screenshot: ${out}/chat.png`);
  // A follow-up in the same session with no LLM configured and nothing recorded: a clear error.
  await page.fill("#command", "and keep the computer on too");
  await page.click("#send");
  await page.waitForSelector(".turn .error", { timeout: 30000 });
  const err = await page.locator(".turn .error").first().textContent();
  check("a follow-up without an LLM shows the server's error", /503 unavailable/.test(err) && /CTB_LLM_BASE_URL/.test(err), err);
  check("no script errors", consoleErrors.length === 0, consoleErrors.join("; "));
} catch (e) {
  check("browser flow", false, String(e));
} finally {
  await browser.close();
  server.kill("SIGTERM");
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
