#!/usr/bin/env python3
"""Planning and executing with uncertain durations (issue 26, docs/uncertainty.md).

For each state plan of config/uncertain/ (the presentation team with an uncertain boot and
warm-up) and the same state plan on the shipped presentation domain (fixed durations):
  - the solve's wall time (median of --repeat runs), status, objective and controllability;
  - N simulated executions (`ctburton execute --sample`) dispatched dynamically and at fixed
    times, their success and violation counts, and the time they took.

Usage: python3 bench/uncertainty.py [--runs 10000] [--repeat 5] [--out bench/results/uncertainty]
Writes OUT.json and OUT.md (with the command and the load average).
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time

from common import BIN, ROOT

PLANS = ["on_within_60", "on_ten_then_off", "together_within_5"]
UNCERTAIN = os.path.join(ROOT, "config", "uncertain", "presentation.json")


def solve(domain, plan, repeat):
    times, answer = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = subprocess.run([BIN, "solve", "--domain", domain, plan], capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        answer = json.loads(out.stdout)
    c = answer.get("controllability", {})
    return {"ms": round(1000 * statistics.median(times), 1), "status": answer["status"],
            "objective": answer["objective"]["value"], "strong": c.get("strong"),
            "dynamic": c.get("dynamic")}


def sample(plan, dispatch, runs, extra=()):
    t0 = time.perf_counter()
    out = subprocess.run([BIN, "execute", "--domain", UNCERTAIN, plan, "--sample", "distribution",
                          "--runs", str(runs), "--seed", "1", "--dispatch", dispatch, *extra],
                         capture_output=True, text=True)
    secs = time.perf_counter() - t0
    if out.returncode not in (0, 5):
        return {"error": out.stderr.strip()[:200]}
    totals = json.loads(out.stdout.strip().splitlines()[-1])
    totals["seconds"] = round(secs, 2)
    return totals


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=10000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "uncertainty"))
    a = ap.parse_args()
    rows = []
    for name in PLANS:
        plan = os.path.join(ROOT, "config", "uncertain", name + ".json")
        row = {"plan": name,
               "fixed_durations": solve("presentation", plan, a.repeat),
               "uncertain": solve(UNCERTAIN, plan, a.repeat)}
        if row["uncertain"]["status"] == "unknown":  # not controllable: the optimistic plan
            row["dynamic"] = sample(plan, "dynamic", a.runs, ["--controllability", "none"])
            row["fixed"] = sample(plan, "fixed", a.runs, ["--controllability", "none"])
        else:
            row["dynamic"] = sample(plan, "dynamic", a.runs)
            row["fixed"] = sample(plan, "fixed", a.runs)
        rows.append(row)
        print(json.dumps(row), flush=True)
    load = os.getloadavg()
    meta = {"command": "python3 bench/uncertainty.py " + " ".join(sys.argv[1:]),
            "machine": f"{platform.machine()}, {os.cpu_count()} cores",
            "load_average": [round(x, 2) for x in load]}
    json.dump({"meta": meta, "rows": rows}, open(a.out + ".json", "w"), indent=1)
    with open(a.out + ".md", "w") as f:
        f.write("# Planning and executing with uncertain durations\n\n")
        f.write(f"`{meta['command']}` on {meta['machine']}, load average {meta['load_average']} "
                "(1, 5, 15 min) at the end. Solve times: median wall time of the whole "
                "`ctburton solve` process. Executions: nature draws the warm-up from its "
                "distribution (normal around 30 s in [20, 40]) and the boot uniformly in "
                "[10, 20]; `dynamic` dispatch reacts, `fixed` starts everything at the plan's "
                "times. A plan that is not controllable is executed with "
                "`--controllability none` (its optimistic plan).\n\n")
        f.write("| state plan | fixed durations: solve | uncertain: solve | status, worst case | "
                "strong / dynamic | dynamic dispatch | fixed times |\n")
        f.write("| --- | ---: | ---: | --- | --- | --- | --- |\n")
        for r in rows:
            u, x = r["uncertain"], r["fixed_durations"]
            def fmt(s):
                if "error" in s:
                    return s["error"]
                return (f"{s['succeeded']}/{s['runs']} succeed, {s['violated']} violated "
                        f"({s['seconds']} s)")
            f.write(f"| {r['plan']} | {x['ms']} ms ({x['status']} {x['objective']}) | {u['ms']} ms | "
                    f"{u['status']}, {u['objective']} | {u['strong']} / {u['dynamic']} | "
                    f"{fmt(r['dynamic'])} | {fmt(r['fixed'])} |\n")


if __name__ == "__main__":
    main()
