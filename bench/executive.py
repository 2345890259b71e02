#!/usr/bin/env python3
"""Executions with injected failures (issue 27): success with and without replanning, and the
time from a decision to replan to the new plan's first commands.

    python3 bench/executive.py [--robots 4] [--runs 100] [--fail 0.2] [--speed 200]
                               [--out bench/results] [--name executive]

Generates the 4-robot search_rescue domain and state plan (tools/gen_domains.py,
bench/gen_scaled.py: robot k rescues person k), starts `ctburton serve` on loopback with a fresh
data directory, and runs --runs executions on the sim adapter with --fail (the chance that each
commanded move fails: the move is then blocked for good), seeds 1..runs, once with replanning
and once with `"replan": false`. Reports per mode: succeeded, failed, replans, and the replanned
events' `ms` (decision to replan -> new plan adopted; its first commands go out in the same step)
at p50/p95/max; with the load average. Writes bench/results/executive.{md,json}.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import BIN, ROOT, free_port, pct  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_domains  # noqa: E402
import gen_scaled  # noqa: E402


def call(base, method, path, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            return r.status, json.load(r)
    except urllib.error.HTTPError as e:
        return e.code, json.load(e)


def run_one(base, dom, sp, speed, fail, seed, replan):
    st, r = call(base, "POST", "/executions", {
        "action_model": dom, "state_plan": sp, "adapter": "sim", "speed": speed,
        "sim": {"fail": fail, "seed": seed}, "replan": replan,
        "options": {"objective": "makespan"}})
    if st != 201:
        raise SystemExit(f"POST /executions: {st} {r}")
    eid = r["execution"]
    t0 = time.monotonic()
    while True:
        _, v = call(base, "GET", f"/executions/{eid}")
        if v["state"] != "running":
            break
        if time.monotonic() - t0 > 300:
            raise SystemExit(f"execution {eid} still running after 300 s")
        time.sleep(0.02)
    ms = [e["data"]["ms"] for e in v["events"] if e["event"] == "replanned"]
    return {"seed": seed, "state": v["state"], "replans": v["replans"], "replan_ms": ms,
            "commands": sum(e["event"] == "dispatched" for e in v["events"]),
            "why": v.get("why", "")}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--robots", type=int, default=4)
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--fail", type=float, default=0.2)
    ap.add_argument("--speed", type=float, default=200)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--name", default="executive", help="the results' file name (without extension)")
    a = ap.parse_args()
    dom = gen_domains.search_rescue(a.robots)
    dom["name"] = f"search_rescue_r{a.robots}"
    sp = gen_scaled.rescue_plan(a.robots)
    data = tempfile.mkdtemp(prefix="ctb-bench-exec-")
    port = free_port()
    server = subprocess.Popen([BIN, "serve", "--port", str(port), "--data-dir", data],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(200):
            try:
                urllib.request.urlopen(base + "/healthz", timeout=1)
                break
            except Exception:
                time.sleep(0.05)
        load0 = os.getloadavg()
        modes = {}
        for replan in (True, False):
            rows = [run_one(base, dom, sp, a.speed, a.fail, s, replan) for s in range(1, a.runs + 1)]
            ms = [x for r in rows for x in r["replan_ms"]]
            modes["on" if replan else "off"] = {
                "runs": len(rows),
                "succeeded": sum(r["state"] == "succeeded" for r in rows),
                "failed": sum(r["state"] == "failed" for r in rows),
                "with_a_failure": sum(r["replans"] > 0 or r["state"] == "failed" for r in rows),
                "replans": sum(r["replans"] for r in rows),
                "replan_ms_p50": pct(ms, 50) if ms else None,
                "replan_ms_p95": pct(ms, 95) if ms else None,
                "replan_ms_max": max(ms) if ms else None,
                "rows": rows,
            }
            m = modes["on" if replan else "off"]
            print(json.dumps({k: v for k, v in m.items() if k != "rows"}), flush=True)
        load1 = os.getloadavg()
    finally:
        server.terminate()
        server.wait(timeout=30)
        shutil.rmtree(data, ignore_errors=True)
    cmd = "python3 bench/executive.py " + " ".join(sys.argv[1:])
    result = {"command": cmd.strip(), "robots": a.robots, "fail": a.fail, "speed": a.speed,
              "load_before": load0, "load_after": load1, "modes": modes}
    os.makedirs(a.out, exist_ok=True)
    json.dump(result, open(os.path.join(a.out, a.name + ".json"), "w"), indent=1)
    on, off = modes["on"], modes["off"]
    md = [f"# Executions with injected failures ({a.robots}-robot search_rescue, sim adapter)", "",
          f"Command: `{cmd.strip()}`  ",
          f"Load average before/after: {load0[0]:.2f} / {load1[0]:.2f} (2 cores)", "",
          f"{a.runs} executions per mode, seeds 1..{a.runs}; each commanded move fails with chance "
          f"{a.fail} (then blocked for good); speed {a.speed} plan s per wall s.", "",
          "| replanning | succeeded | failed | runs that met a failure | replans | replan ms p50 | p95 | max |",
          "|---|---|---|---|---|---|---|---|"]
    for name, m in (("on", on), ("off", off)):
        md.append(f"| {name} | {m['succeeded']} | {m['failed']} | {m['with_a_failure']} | {m['replans']} | "
                  f"{m['replan_ms_p50']} | {m['replan_ms_p95']} | {m['replan_ms_max']} |")
    md += ["", "`replan ms`: from the executive's decision to replan to the new plan adopted (the "
           "replanned event's `ms`, through the core's job gate, the planner and the verifier); the "
           "new plan's first commands are dispatched in the same step. With replanning off, a failed "
           "move ends the execution `failed`. A failed execution with replanning on is one where a "
           "blocked move left no plan (the planner proved it; the execution says why)."]
    open(os.path.join(a.out, a.name + ".md"), "w").write("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
