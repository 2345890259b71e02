#!/usr/bin/env python3
"""Symmetry breaking (issue 18, lever 4): interchangeable automata, detected and ordered in the
Gecode models (planner/analyze/symmetry.h, planner/encode/encode_symmetry.cpp).

    python3 bench/symmetry.py --before OLD_BINARY [--sizes 2,3,4,6,8] [--time-limit-ms 60000]
                              [--out bench/results]

Problems with interchangeable automata:
  assign_eq      bench/families.py: free assignment of N robots of one speed to N persons;
  assign         the same with robots of three speeds (robots of one speed are interchangeable);
  presentation   bench/coupled.py's rows: N units of computer, connection and projector, all
                 projectors on together (units exchanged as a whole);
  search_rescue  test prompt 1 (either robot rescues either person).
Runs `ctburton solve` with this build ("after") and with OLD_BINARY ("before", e.g. main's build
without symmetry breaking), one at a time, with the default options and with the exact engine
alone, and writes bench/results/symmetry.{md,json}: status,
objective, time to the first verified plan, end-to-end time, and the orbits the after build
ordered (read from its --model-out).
"""
import argparse
import json
import os
import platform
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import BIN, ROOT  # noqa: E402
import coupled  # noqa: E402
import families  # noqa: E402


def problems(tmp, sizes):
    out = []

    def write(name, obj):
        path = os.path.join(tmp, name + ".json")
        with open(path, "w") as f:
            json.dump(obj, f)
        return path

    for family in ("assign_eq", "assign"):
        for n in sizes:
            dom = os.path.join(tmp, f"{family}{n}_domain.json")
            families.expand(BIN, n, family == "assign", dom)
            out.append((f"{family}, {n} robots", dom, write(f"{family}{n}", families.plan(n, family)),
                        "makespan"))
    for n, objective in ((2, "cost"), (4, "cost"), (8, "makespan")):
        dom = coupled.gen_domains.presentation(n)
        dom["name"] = f"presentation_x{n}"
        out.append((f"presentation {n}x, all projectors on together", write(f"pres{n}_domain", dom),
                    write(f"pres{n}", coupled.presentation_coupled(n)), objective))
    ex = os.path.join(ROOT, "config", "examples", "search_rescue", "test1.json")
    for objective in ("makespan", "cost"):
        out.append(("search_rescue, test prompt 1", "search_rescue", ex, objective))
    return out


# The two ways each problem is solved: the defaults end to end, and the exact engine alone
# (Gecode's g_first, no first-plan engine, no portfolio), where the ordering acts undiluted.
MODES = {"default": [], "exact": ["--first-plan-ms", "0", "--search", "g_first"]}


def run(binary, domain, plan, objective, limit_ms, mode, model_out=None):
    cmd = [binary, "solve", "--domain", domain, plan, "--objective", objective,
           "--time-limit-ms", str(limit_ms)] + MODES[mode]
    if model_out:
        cmd += ["--model-out", model_out]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 60)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if p.returncode != 0:
        return {"status": "error", "error": p.stderr.strip()[-300:]}
    t = json.loads(p.stdout)
    s = t["stats"]
    first = s.get("first_solution_ms")
    return {"status": t["status"], "objective": t["objective"]["value"], "verified": t["verified"],
            "first_s": None if first in (None, -1) else round(first / 1000, 2),
            "total_s": round(s["solve_ms"] / 1000, 2), "found_by": s.get("found_by"),
            "proved_by": s.get("proved_by"), "runs": s.get("solver_runs")}


def orbits(model_path):
    """The orbits a model orders: 'units x size' per orbit, from its SYM tables."""
    if not os.path.exists(model_path):
        return "—"
    with open(model_path) as f:
        text = f.read()
    found = re.findall(r"array\[1\.\.(\d+), 1\.\.(\d+)\] of int: SYM\d+", text)
    return ", ".join(f"{m}×{r}" for m, r in found) or "none"


def cell(r, key):
    v = r.get(key)
    return "—" if v is None else json.dumps(v) if isinstance(v, dict) else str(v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", required=True, help="a ctburton binary without symmetry breaking")
    ap.add_argument("--sizes", default="2,3,4,6,8")  # 16: a goal past 8192 characters
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    sizes = [int(x) for x in a.sizes.split(",")]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, dom, plan, objective in problems(tmp, sizes):
            model = os.path.join(tmp, "model.mzn")
            for mode in MODES:
                if os.path.exists(model):
                    os.remove(model)
                row = {"problem": label, "objective_kind": objective, "mode": mode,
                       "after": run(BIN, dom, plan, objective, a.time_limit_ms, mode, model),
                       "orbits": orbits(model),
                       "before": run(a.before, dom, plan, objective, a.time_limit_ms, mode)}
                print(json.dumps(row), flush=True)
                rows.append(row)
    load = os.getloadavg()
    cmd = "python3 bench/symmetry.py " + " ".join(sys.argv[1:])
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "symmetry.json"), "w") as f:
        json.dump({"command": cmd, "load": load, "rows": rows}, f, indent=1)
    lines = ["# Symmetry breaking (issue 18, lever 4): interchangeable automata ordered", "",
             f"Made by `{cmd}` on {os.cpu_count()} cores, {platform.platform()}; time limit "
             f"{a.time_limit_ms} ms per solve, one solve at a time. Load average at the end: "
             f"{load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f}. Seconds end to end "
             "(`stats.solve_ms`); `first`: the first verified plan. `orbits`: what the after build "
             "ordered, units × automata per unit (from its `--model-out`).", ""]
    titles = {"default": "## End to end, default options",
              "exact": "## The exact engine alone (`--first-plan-ms 0 --search g_first`)"}
    for mode in MODES:
        lines += [titles[mode], ""] + table([r for r in rows if r["mode"] == mode]) + [""]
    with open(os.path.join(a.out, "symmetry.md"), "w") as f:
        f.write("\n".join(lines))
    bad = [r for r in rows if r["after"]["status"] in ("error", "timeout") or
           (r["after"]["status"] in ("optimal", "feasible") and not r["after"].get("verified"))]
    if bad:
        print(f"{len(bad)} problem(s) failed", file=sys.stderr)
        sys.exit(1)


def table(rows):
    lines = ["| problem | objective | orbits | after: status | value | first | total | proved by "
             "| before: status | value | first | total | proved by |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        x, b = r["after"], r["before"]
        lines.append(f"| {r['problem']} | {r['objective_kind']} | {r['orbits']} | {x['status']} | "
                     f"{cell(x, 'objective')} | {cell(x, 'first_s')} | {cell(x, 'total_s')} | "
                     f"{cell(x, 'proved_by')} | {b['status']} | {cell(b, 'objective')} | "
                     f"{cell(b, 'first_s')} | {cell(b, 'total_s')} | {cell(b, 'proved_by')} |")
    return lines


if __name__ == "__main__":
    main()
