#!/usr/bin/env python3
"""Gecode vs z3 vs both (issue 9, "a second engine"): a few coupled problems of bench/coupled.py.

    python3 bench/z3_engine.py [--time-limit-ms 60000] [--only LABEL-SUBSTRING]

Runs `build/client/ctburton solve --domain D P --objective O --time-limit-ms T` with
  gecode:     the default (portfolio of g_first and tc_first, two cores)
  g_first:    --search g_first (Gecode, one core)
  z3:         --search z3 (z3 alone, one core)
  portfolio3: --portfolio 3 (g_first, tc_first and z3)
and prints one JSON line per run (status, value, bound, first plan, total, solver).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import coupled  # noqa: E402

CONFIGS = {"gecode": [], "g_first": ["--search", "g_first"], "z3": ["--search", "z3"],
           "portfolio3": ["--portfolio", "3"]}
WANTED = ("presentation 1x, test prompt 1", "presentation 2x", "search_rescue, 3 robots",
          "search_rescue, 4 robots")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--only", default="")
    ap.add_argument("--configs", default=",".join(CONFIGS))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for label, domain, plan, objective in coupled.problems(tmp, False):
            if not any(label.startswith(w) for w in WANTED) or a.only not in label:
                continue
            for name in a.configs.split(","):
                cmd = [coupled.BIN, "solve", "--domain", domain, plan, "--objective", objective,
                       "--time-limit-ms", str(a.time_limit_ms)] + CONFIGS[name]
                p = subprocess.run(cmd, capture_output=True, text=True)
                row = {"problem": label, "objective_kind": objective, "config": name}
                if p.returncode != 0:
                    row.update(status="error", error=p.stderr.strip()[-300:])
                else:
                    t = json.loads(p.stdout)
                    s = t["stats"]
                    row.update(status=t["status"], value=t["objective"]["value"],
                               bound=t.get("bound"), verified=t["verified"],
                               first_ms=s.get("first_solution_ms"), total_ms=s.get("solve_ms"),
                               runs=s.get("solver_runs"), solver=s.get("solver"))
                print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
