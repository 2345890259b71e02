#!/usr/bin/env python3
"""Replanning a 4-robot coupled search_rescue plan end to end (issue 21: target < 2 s).

    python3 bench/replan.py [--robots 4] [--repeat 3] [--out bench/results] [--bin PATH]
                            [--baseline OLD.json]

Generates the domain and the state plan (tools/gen_domains.py, bench/gen_scaled.py: robot k
rescues person k), solves it once with `ctburton solve --objective makespan`, then times
`ctburton replan` (the whole process: load, checks, bounds, solve, verify, diff) on departures
along that plan: nothing departs, a robot's next move blocked, a robot found back where it was, a
transition that did not happen, keep min_change, and now = 0. Writes bench/results/replan.{md,json}
with the median of --repeat runs, the status, objective, solver runs, which engine found and
proved the answer, and the load average. --bin times another build's ctburton (e.g. main's, for a
before/after); --baseline adds the medians of an earlier run's replan.json as a "before" column.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "client", "ctburton")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_domains  # noqa: E402
import gen_scaled  # noqa: E402


def run(args):
    t0 = time.monotonic()
    p = subprocess.run([BIN] + args, capture_output=True, text=True, timeout=600)
    ms = round((time.monotonic() - t0) * 1000)
    if p.returncode != 0:
        return ms, {"status": "error", "error": p.stderr.strip()[-300:]}
    return ms, json.loads(p.stdout)


def scenarios(plan, n):
    ts = plan["transitions"]
    goal = plan["goal_reached_at"]
    mid = sorted({t["time"] for t in ts})[len({t["time"] for t in ts}) // 2]
    out = [("nothing departs, now = %s" % mid, {"now": mid}, "none"),
           ("now = 0, nothing happened", {"now": 0}, "none")]
    # the first robot still outside at mid cannot go the way the plan sends it (another door)
    for r in range(1, n + 1):
        dep = next((t for t in ts if t["automaton"] == f"robot{r}" and t["from"] == "outside"), None)
        if dep and dep["time"] >= mid:
            out.append(("robot%d %s -> %s blocked at %s" % (r, dep["from"], dep["to"], mid),
                        {"now": mid, "blocked": [{k: dep[k] for k in ("automaton", "from", "to")}]},
                        "none"))
            break
    else:
        dep = next(t for t in ts if t["automaton"] == "robot1" and t["from"] == "outside")
        out.append(("robot1 %s -> %s blocked at 0" % (dep["from"], dep["to"]),
                    {"now": 0, "blocked": [{k: dep[k] for k in ("automaton", "from", "to")}]}, "none"))
    # robot n's last transition before mid did not happen (it is late)
    before = [t for t in ts if t["time"] < mid]
    late = next((t for t in reversed(before) if t["automaton"] == f"robot{n}"), None)
    if late:
        ex = [{k: t[k] for k in ("time", "automaton", "from", "to")} for t in before if t is not late]
        out.append(("robot%d's %s -> %s did not happen by %s" % (n, late["from"], late["to"], mid),
                    {"now": mid, "executed": ex}, "none"))
    # robot 2 found back outside
    out.append(("robot2 found outside at %s" % mid,
                {"now": mid, "observed": {"robot2": {"location": "outside", "since": mid}}}, "none"))
    out.append(("nothing departs, now = %s, keep min_change" % mid, {"now": mid}, "min_change"))
    return out, goal


def main():
    global BIN
    ap = argparse.ArgumentParser()
    ap.add_argument("--robots", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--bin", default=BIN, help="the ctburton binary to time")
    ap.add_argument("--baseline", help="an earlier replan.json: its medians as a 'before' column")
    a = ap.parse_args()
    BIN = a.bin
    n = a.robots
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        dom = gen_domains.search_rescue(n)
        dom["name"] = f"search_rescue_r{n}"
        dpath, spath, ppath = (os.path.join(tmp, x) for x in ("d.json", "sp.json", "plan.json"))
        json.dump(dom, open(dpath, "w"))
        json.dump(gen_scaled.rescue_plan(n), open(spath, "w"))
        ms, plan = run(["solve", "--domain", dpath, spath, "--objective", "makespan",
                        "--time-limit-ms", str(a.time_limit_ms)])
        json.dump(plan, open(ppath, "w"))
        rows.append({"case": "solve from scratch (the plan)", "ms": [ms], "status": plan["status"],
                     "objective": plan["objective"]["value"], "solver_runs": plan["stats"]["solver_runs"]})
        print(json.dumps(rows[-1]), flush=True)
        cases, goal = scenarios(plan, n)
        for label, fields, keep in cases:
            rpath = os.path.join(tmp, "req.json")
            json.dump(fields, open(rpath, "w"))
            times, ans = [], None
            for _ in range(a.repeat):
                ms, ans = run(["replan", "--domain", dpath, spath, "--trajectory", ppath, "--request",
                               rpath, "--objective", "makespan", "--keep", keep,
                               "--time-limit-ms", str(a.time_limit_ms)])
                times.append(ms)
            row = {"case": label, "ms": times, "median_ms": statistics.median(times),
                   "status": ans.get("status"), "objective": ans.get("objective", {}).get("value"),
                   "solver_runs": ans.get("stats", {}).get("solver_runs"),
                   "history_events": ans.get("stats", {}).get("history_events"),
                   "found_by": ans.get("stats", {}).get("found_by"),
                   "proved_by": ans.get("stats", {}).get("proved_by"),
                   "verified": ans.get("verified")}
            if "diff" in ans:
                row["diff"] = {k: len(v) for k, v in ans["diff"].items()}
            rows.append(row)
            print(json.dumps(row), flush=True)
    load = os.getloadavg()
    os.makedirs(a.out, exist_ok=True)
    cmd = "python3 bench/replan.py " + " ".join(sys.argv[1:])
    before = load_baseline(a.baseline)
    json.dump({"command": cmd, "binary": a.bin, "robots": n, "loadavg": load, "rows": rows,
               "baseline": before},
              open(os.path.join(a.out, "replan.json"), "w"), indent=1)
    with open(os.path.join(a.out, "replan.md"), "w") as f:
        f.write(f"# Replanning search_rescue with {n} robots (issue 21)\n\n")
        f.write(f"Command: `{cmd}` ({os.path.relpath(a.bin, ROOT)}, RelWithDebInfo). Each replan is "
                "the whole `ctburton replan` process (load, checks, bounds, solve, verify, diff); "
                f"median of {a.repeat} runs. Load average (1, 5, 15 min) at the end: "
                f"{load[0]:.1f}, {load[1]:.1f}, {load[2]:.1f} on {os.cpu_count()} cores.\n\n")
        if before:
            f.write(f"Before: the medians of `{before['command']}` ({before['binary']}; load at its end "
                    f"{before['loadavg'][0]:.1f}).\n\n")
        f.write("| case | median ms |" + (" before ms |" if before else "") + " runs (ms) | status | "
                "makespan | solver runs | found by | proved by | history events | diff |\n")
        f.write("| --- " * (10 + bool(before)) + "|\n")
        for r in rows:
            old = before["medians"].get(r["case"], "") if before else None
            f.write(f"| {r['case']} | {r.get('median_ms', r['ms'][0])} |" +
                    (f" {old} |" if before else "") +
                    f" {', '.join(map(str, r['ms']))} | {r['status']} | {r['objective']} | "
                    f"{r.get('solver_runs')} | {r.get('found_by', '')} | {r.get('proved_by', '')} | "
                    f"{r.get('history_events', '')} | {r.get('diff', '')} |\n")


def load_baseline(path):
    """The medians of an earlier run (its replan.json), by case."""
    if not path:
        return None
    old = json.load(open(path))
    return {"command": old.get("command"), "binary": old.get("binary", "build/client/ctburton"),
            "loadavg": old.get("loadavg"),
            "medians": {r["case"]: r.get("median_ms", r["ms"][0]) for r in old["rows"]}}


if __name__ == "__main__":
    main()
