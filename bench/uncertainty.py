#!/usr/bin/env python3
"""Planning and executing with uncertain durations (issue 26, docs/uncertainty.md).

For each state plan of config/uncertain/ (the presentation team with an uncertain boot and
warm-up, the rescue team with uncertain drives) and the same state plan on the shipped domain
(fixed durations):
  - the solve's wall time (median of --repeat runs, each with --time-limit-ms), status,
    objective, controllability and the search among plans (plans cut);
  - N simulated executions (`ctburton execute --sample`) dispatched dynamically and at fixed
    times, their success and violation counts, and the time they took.

Usage: python3 bench/uncertainty.py [--runs 10000] [--repeat 5] [--time-limit-ms 10000]
                                    [--out bench/results/uncertainty]
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

PLANS = [("presentation", "on_within_60"), ("presentation", "on_ten_then_off"),
         ("presentation", "together_within_5"), ("search_rescue", "rescue_at_door1"),
         ("search_rescue", "rescue_open_on_arrival"), ("search_rescue", "rescue_both_at_door1"),
         ("search_rescue", "rescue_arrive_together"), ("assembly", "assembly_a_down_within_6"),
         ("assembly", "assembly_pick_b_on_return"), ("assembly", "assembly_home_in_4_to_5")]
TIME_LIMIT_MS = "10000"


def uncertain(domain):
    return os.path.join(ROOT, "config", "uncertain", domain + ".json")


def solve(domain, plan, repeat):
    times, answer = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = subprocess.run([BIN, "solve", "--time-limit-ms", TIME_LIMIT_MS, "--domain", domain, plan],
                             capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        answer = json.loads(out.stdout)
    c = answer.get("controllability", {})
    search = c.get("search", {})
    return {"ms": round(1000 * statistics.median(times), 1), "status": answer["status"],
            "objective": answer["objective"]["value"], "strong": c.get("strong"),
            "dynamic": c.get("dynamic"), "plans_cut": search.get("plans_cut", 0),
            "proven": search.get("proven", False), "stopped": search.get("stopped")}


def sample(domain, plan, dispatch, runs, extra=()):
    t0 = time.perf_counter()
    out = subprocess.run([BIN, "execute", "--time-limit-ms", TIME_LIMIT_MS, "--domain", uncertain(domain),
                          plan, "--sample", "distribution",
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
    ap.add_argument("--time-limit-ms", default=TIME_LIMIT_MS)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "uncertainty"))
    a = ap.parse_args()
    globals()["TIME_LIMIT_MS"] = str(a.time_limit_ms)
    rows = []
    for domain, name in PLANS:
        plan = os.path.join(ROOT, "config", "uncertain", name + ".json")
        row = {"plan": name, "domain": domain,
               "fixed_durations": solve(domain, plan, a.repeat),
               "uncertain": solve(uncertain(domain), plan, a.repeat)}
        if row["uncertain"]["status"] in ("unknown", "infeasible"):  # the optimistic plan
            row["dynamic"] = sample(domain, plan, "dynamic", a.runs, ["--controllability", "none"])
            row["fixed"] = sample(domain, plan, "fixed", a.runs, ["--controllability", "none"])
        else:
            row["dynamic"] = sample(domain, plan, "dynamic", a.runs)
            row["fixed"] = sample(domain, plan, "fixed", a.runs)
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
                "`ctburton solve` process, time limit " + TIME_LIMIT_MS + " ms. Executions: nature "
                "draws each contingent duration from its distribution (presentation: the warm-up "
                "normal around 30 s in [20, 40], the boot uniform in [10, 20]; rescue: the drives "
                "uniform); `dynamic` dispatch reacts, `fixed` starts everything at the plan's "
                "times. Where no plan of the asked kind is found (unknown) or none exists "
                "(infeasible), the optimistic plan is executed (`--controllability none`). "
                "Search: plans the search among plans cut, and whether it proved that none is "
                "left or stopped.\n\n")
        f.write("| state plan | fixed durations: solve | uncertain: solve | status, worst case | "
                "strong / dynamic | search | dynamic dispatch | fixed times |\n")
        f.write("| --- | ---: | ---: | --- | --- | --- | --- | --- |\n")
        for r in rows:
            u, x = r["uncertain"], r["fixed_durations"]
            def fmt(s):
                if "error" in s:
                    return s["error"]
                return (f"{s['succeeded']}/{s['runs']} succeed, {s['violated']} violated "
                        f"({s['seconds']} s)")
            search = (f"{u['plans_cut']} cut" + (", proven" if u["proven"] else "") +
                      (f", stopped: {u['stopped']}" if u["stopped"] else "")) if u["plans_cut"] else "none"
            f.write(f"| {r['domain']} {r['plan']} | {x['ms']} ms ({x['status']} {x['objective']}) | "
                    f"{u['ms']} ms | {u['status']}, {u['objective']} | {u['strong']} / {u['dynamic']} | "
                    f"{search} | {fmt(r['dynamic'])} | {fmt(r['fixed'])} |\n")


if __name__ == "__main__":
    main()
