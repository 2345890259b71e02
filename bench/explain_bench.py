#!/usr/bin/env python3
"""Times the explanations of infeasible state plans (issue 10) and the static checks.

Usage: python3 bench/explain_bench.py [--build build] [--max-horizon 16] [--out bench/results/explain.md]

For each infeasible example, `ctburton solve` is run once; the answer's `stats.solve_ms` is the
solver's own infeasibility proof (issue 9's business), `explanation.stats.ms` the explanation
(static analysis, deletion filter, relaxations and their checks), `solver_calls` how many solves
the explanation made. The static checks are timed by the Analyze tests of planner_tests (each
test loads its state plan and runs every check).
"""
import argparse
import json
import os
import platform
import subprocess
import tempfile
import time

CASES = [
    ("presentation", "tests/data/deadline_infeasible.json", "deadline below the warm-up (shipped)"),
    ("presentation", "config/examples/presentation/test2_direct.json", "thesis direct answer, test prompt 2"),
    ("presentation", "tests/data/explain/deadline_boot.json", "deadline below the boot time"),
    ("presentation", "tests/data/explain/change_not_allowed.json", "a change no transition allows"),
    ("search_rescue", "tests/data/explain/unreachable.json", "an unreachable location"),
    ("presentation", "tests/data/explain/overlap.json", "two episodes that overlap impossibly"),
    ("presentation", "tests/data/explain/maintenance_blocks.json", "maintenance blocks the only route"),
    ("presentation", "tests/data/explain/three_together.json", "three constraints, only together"),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build")
    ap.add_argument("--max-horizon", type=int, default=16)
    ap.add_argument("--out", default="bench/results/explain.md")
    a = ap.parse_args()
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.chdir(src)
    exe = os.path.join(a.build, "client", "ctburton")
    rows = []
    for dom, f, what in CASES:
        t0 = time.time()
        out = subprocess.run([exe, "solve", "--domain", dom, f, "--max-horizon", str(a.max_horizon),
                              "--time-limit-ms", "120000"], capture_output=True, text=True)
        wall = time.time() - t0
        t = json.loads(out.stdout)
        ex = t.get("explanation", {})
        conflict = ex.get("conflicts", [{}])[0].get("constraints", []) if ex.get("conflicts") else []
        relax = [r["text"] for r in ex.get("relaxations", [])]
        rows.append((what, f, t["status"], t["stats"]["solve_ms"], ex.get("stats", {}).get("ms"),
                     ex.get("stats", {}).get("solver_calls"), ex.get("status"), conflict, relax, wall))
    with tempfile.TemporaryDirectory() as tmp:
        js = os.path.join(tmp, "analyze.json")
        subprocess.run([os.path.join(a.build, "tests", "planner_tests"), "--gtest_filter=Analyze.*",
                        "--gtest_output=json:" + js], capture_output=True, env=dict(os.environ, CTB_CONFIG_DIR=os.path.join(src, "config")))
        static = json.load(open(js))["testsuites"][0]["testsuite"]
    load = os.getloadavg()
    mzn = subprocess.run(["minizinc", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    lines = [
        "# Explanations of infeasible state plans (issue 10)",
        "",
        f"Made by `python3 bench/explain_bench.py --max-horizon {a.max_horizon}` on {os.cpu_count()} cores, "
        f"{platform.platform()}; {mzn}. Load average while it ran: {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} "
        "(other engineers' builds and tests share the two cores; times on an idle machine are several times lower).",
        "",
        "`solve` is `stats.solve_ms`: the solver's own proof that the plan is infeasible (before any "
        "explanation; issue 9 makes it faster). `explain` is `explanation.stats.ms`: static analysis, the "
        "deletion filter and the relaxations with every check, `calls` the solver runs it made. "
        "Times in ms.",
        "",
        "| case | status | solve | explain | calls | explanation | conflict | relaxations |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for what, f, st, solve_ms, ex_ms, calls, exst, conflict, relax, wall in rows:
        lines.append(f"| {what} (`{f}`) | {st} | {solve_ms} | {ex_ms} | {calls} | {exst} | "
                     f"{', '.join('`' + c + '`' for c in conflict)} | {'; '.join(relax)} |")
    lines += ["", "Static checks alone (each Analyze test of `planner_tests`: load the state plan, run every check):", "",
              "| test | ms |", "|---|---|"]
    for s in static:
        lines.append(f"| {s['name']} | {s['time']} |")
    open(a.out, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
