// The page with a server that needs an API key (issue 19): the page asks for the key in a dialog
// when /info answers 401, a wrong key is refused and asked again, the right one loads the domains
// and solves, and the key lives in sessionStorage only (this tab), never in localStorage.
//   node auth_test.mjs CTBURTON_BINARY SOURCE_DIR OUTPUT_DIR
import { writeFileSync } from "node:fs";
import { check, finish, launchBrowser, sleep, startServer } from "./harness.mjs";

const [bin, src, out] = process.argv.slice(2);
const key = "browser-key-0123456789abcdef";
const keyFile = `/tmp/ctb-browser-keys-${process.pid}`;
writeFileSync(keyFile, `${key}\n`);
const { server, base } = await startServer(bin, src, out, {
  args: ["--demo", "--api-keys", keyFile, "--data-dir", `/tmp/ctb-browser-auth-${process.pid}`],
  log: "auth-server.log" });
const browser = await launchBrowser();
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 800 } });
  await page.goto(base);
  const dialog = page.locator("dialog.key-dialog");
  await dialog.waitFor({ state: "visible", timeout: 10000 });
  check("the page asks for a key when the server needs one", await dialog.isVisible());
  await page.screenshot({ path: `${out}/auth-dialog.png` });
  await dialog.locator("input").fill("not-the-key-0123456789");
  await dialog.locator("button[value=ok]").click();
  await sleep(300);
  await dialog.waitFor({ state: "visible", timeout: 10000 });
  check("a wrong key is refused and asked again",
    (await dialog.textContent()).includes("not accepted"));
  await dialog.locator("input").fill(key);
  await dialog.locator("button[value=ok]").click();
  await dialog.waitFor({ state: "detached", timeout: 10000 });
  const stored = await page.evaluate(() => ({ s: sessionStorage.getItem("ctburton.apiKey"),
    l: Object.keys(localStorage).filter((k) => localStorage.getItem(k).includes("browser-key")) }));
  check("the key is kept for this tab only (sessionStorage, not localStorage)",
    stored.s === key && stored.l.length === 0, JSON.stringify(stored));
  const r = await page.evaluate(async () => {
    const res = await fetch("/domains");
    return { status: res.status, body: await res.json() };
  });
  check("requests from the page carry the key", r.status === 200 && r.body.domains.length === 3,
    JSON.stringify(r).slice(0, 200));
  const direct = await fetch(`${base}/domains`);
  check("without the key the server answers 401", direct.status === 401);
} finally {
  await browser.close();
  server.kill("SIGTERM");
}
finish();
