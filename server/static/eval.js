// "How well does the model translate?" (contract section 15): runs the shipped suite through the
// configured model (POST /eval, streamed) and shows a table per domain: each command's verdict,
// why, and the rates.
import { postStream } from "./sse.js";

const $ = (id) => document.getElementById(id);
const VERDICTS = ["equivalent", "not_equivalent", "unparsed", "invalid", "unknown"];

function el(tag, attrs = {}, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

function cut(s, n) { return s.length > n ? `${s.slice(0, n - 1)}…` : s; }

function rate(count, n) { return `${count} (${n ? Math.round((100 * count) / n) : 0} %)`; }

// One table per domain, rows in suite order; returns the row of each item.
function tables(suite) {
  const box = $("eval-tables");
  box.replaceChildren();
  const byDomain = new Map();
  suite.forEach((item, i) => {
    if (!byDomain.has(item.domain)) {
      const table = el("table", { class: "eval-table", "data-domain": item.domain });
      table.appendChild(el("caption", {}, item.domain));
      const head = el("tr");
      for (const h of ["#", "command", "verdict", "why", "ms"]) head.appendChild(el("th", { scope: "col" }, h));
      table.appendChild(el("thead")).appendChild(head);
      table.appendChild(el("tbody"));
      table.appendChild(el("tfoot")).appendChild(el("tr")).appendChild(el("td", { colspan: 5, class: "eval-total" }));
      box.appendChild(table);
      byDomain.set(item.domain, { table, items: [] });
    }
    const row = el("tr", { "data-item": i });
    row.appendChild(el("td", {}, String(i)));
    const cmd = el("td", { title: item.command }, cut(item.command, 90));
    row.appendChild(cmd);
    row.appendChild(el("td", { class: "eval-verdict" }, "…"));
    row.appendChild(el("td", { class: "eval-why" }));
    row.appendChild(el("td", { class: "eval-ms" }));
    byDomain.get(item.domain).table.querySelector("tbody").appendChild(row);
    byDomain.get(item.domain).items.push(i);
  });
  return byDomain;
}

function totals(byDomain, lines) {
  for (const [, { table, items }] of byDomain) {
    const mine = items.map((i) => lines[i]).filter(Boolean);
    const count = (v) => mine.filter((l) => l.verdict === v).length;
    table.querySelector(".eval-total").textContent = `${mine.length} of ${items.length} items: ` +
      VERDICTS.map((v) => `${v.replace("_", " ")} ${rate(count(v), mine.length)}`).join(", ");
  }
}

async function run() {
  const button = $("eval-run"), status = $("eval-status");
  button.disabled = true;
  status.textContent = "loading the suite…";
  try {
    const res = await fetch("/eval/suite");
    if (!res.ok) { status.textContent = `no suite (${res.status})`; return; }
    const suite = await res.json();
    const byDomain = tables(suite);
    const lines = [];
    status.textContent = `measuring ${suite.length} commands…`;
    const prompting = $("prompting")?.value || "cot";
    const r = await postStream("/eval", { suite, prompting }, {
      onEvent: (name, data) => {
        if (name !== "item") return;
        lines[data.item] = data;
        const row = document.querySelector(`#eval-tables tr[data-item="${data.item}"]`);
        if (!row) return;
        row.dataset.verdict = data.verdict;
        row.querySelector(".eval-verdict").textContent = data.verdict.replace("_", " ");
        row.querySelector(".eval-why").textContent = data.why || "";
        row.querySelector(".eval-ms").textContent = String(data.ms);
        totals(byDomain, lines);
      },
    });
    if (r.status !== 200) {
      status.textContent = `failed: ${r.data?.error?.message || r.data?.message || r.status}`;
      return;
    }
    const t = r.data.totals;
    status.textContent = `done (${prompting}): ` + VERDICTS.map((v) => `${v.replace("_", " ")} ${rate(t[v], t.items)}`).join(", ");
  } catch (e) {
    status.textContent = `failed: ${e.message}`;
  } finally {
    button.disabled = false;
  }
}

export function initEval() {
  $("eval-run").addEventListener("click", run);
}
