// What the browser tests share: counted checks, a free loopback port, the real `ctburton serve`
// started and waited for, and Debian's headless Chromium.
import { spawn } from "node:child_process";
import { mkdirSync, openSync } from "node:fs";
import net from "node:net";
import { chromium } from "playwright-core";

let passed = 0, failed = 0;

export function check(name, ok, detail = "") {
  if (ok) { passed++; console.log(`ok   ${name}`); } else { failed++; console.log(`FAIL ${name} ${detail}`); }
}

// A failure that stopped the test (an exception).
export function stopped(e) {
  failed++;
  console.log(`FAIL the test stopped: ${e?.stack || e}`);
}

// Prints the count and exits 1 when a check failed.
export function finish() {
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

export const freePort = () => new Promise((resolve) => {
  const s = net.createServer();
  s.listen(0, "127.0.0.1", () => { const p = s.address().port; s.close(() => resolve(p)); });
});

// `ctburton serve` on a free port with the repository's config and prompts, no LLM unless `env`
// names one; its log in OUT/LOG. Resolves once /healthz answers: {server, base}.
export async function startServer(bin, src, out, { args = [], env = {}, log = "server.log" } = {}) {
  mkdirSync(out, { recursive: true });
  const port = await freePort();
  const full = { ...process.env, CTB_CONFIG_DIR: `${src}/config`, CTB_PROMPTS_DIR: `${src}/prompts` };
  for (const k of ["CTB_LLM_BASE_URL", "CTB_LLM_REPLAY", "CTB_LLM_API_KEY"]) delete full[k];
  Object.assign(full, env);
  const server = spawn(bin, ["serve", "--port", String(port), ...args],
                       { cwd: src, env: full, stdio: ["ignore", "ignore", openSync(`${out}/${log}`, "w")] });
  const base = `http://127.0.0.1:${port}`;
  for (let i = 0; i < 200; i++) {
    try { if ((await fetch(`${base}/healthz`)).ok) break; } catch {}
    await sleep(50);
  }
  return { server, base };
}

export const launchBrowser = () => chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
