#!/usr/bin/env python3
"""Solver scaling benchmark (issue 3): thesis Table 5.1 and a coupled search-and-rescue run.

    python3 bench/run_bench.py [--quick] [--time-limit-ms N] [--out bench/results]

Runs `build/client/ctburton solve` under /usr/bin/time for each configuration and problem size
and writes bench/results/solve_scaling.{md,json}. Each configuration adds one change to the one
before it; a configuration stops growing N after its first run without a proven optimum.
Peak memory is the largest resident set of the process tree (GNU time's %M: ctburton, minizinc
and fzn-gecode, as reaped).
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "client", "ctburton")
THESIS = {1: ("1,978", "0.404", "—"), 2: ("3,236", "9.818", "—"), 4: ("5,800", "79.142", "not proven"),
          8: ("10,896", "DNF (2 h)", "not proven"), 16: ("—", "—", "—")}
CONFIGS = [
    ("A", "one model, Gecode's default search, no redundant constraints",
     ["--no-decompose", "--search", "default", "--portfolio", "1", "--no-redundant"]),
    ("B", "A + redundant constraints (entry <= event, min time between locations, cost-to-go)",
     ["--no-decompose", "--search", "default", "--portfolio", "1"]),
    ("C", "B + search: state-plan event indices, then transitions in time order, then times",
     ["--no-decompose", "--search", "g_first", "--portfolio", "1"]),
    ("D", "C + two-strategy portfolio (g-first and tc-first on the two cores)",
     ["--no-decompose"]),
    ("E", "D + independent parts solved apart and merged",
     ["--no-reuse"]),
    ("F", "E + identical parts solved once (the default)",
     []),
]


def run(domain, plan, args, limit_ms, objective):
    cmd = ["/usr/bin/time", "-f", "%M", BIN, "solve", "--domain", domain, plan,
           "--time-limit-ms", str(limit_ms), "--objective", objective] + args
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 120)
    mem_kb = int(p.stderr.strip().splitlines()[-1]) if p.stderr.strip() else -1
    if p.returncode != 0:
        return {"status": "error", "error": p.stderr.strip()[-300:], "peak_mb": mem_kb / 1024}
    t = json.loads(p.stdout)
    s = t["stats"]
    return {"status": t["status"], "objective": t["objective"]["value"],
            "variables": s.get("variables"), "compile_ms": s.get("compile_ms"),
            "first_solution_ms": s.get("first_solution_ms"), "solve_ms": s.get("solve_ms"),
            "solver_runs": s.get("solver_runs"), "parts": s.get("parts", 1),
            "peak_mb": round(mem_kb / 1024, 1)}


def fmt_ms(v):
    return "—" if v is None or v < 0 else f"{v / 1000:.2f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="N up to 4, configurations D-F")
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--objective", default="cost")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    probs = tempfile.mkdtemp(prefix="ctb-bench-")
    subprocess.run([sys.executable, os.path.join(ROOT, "bench", "gen_scaled.py"), probs], check=True)
    sizes = [1, 2, 4] if a.quick else [1, 2, 4, 8, 16]
    configs = CONFIGS[3:] if a.quick else CONFIGS
    results = {"scaling": {}, "coupled": {}}
    for key, _, args in configs:
        results["scaling"][key] = {}
        for n in sizes:
            r = run(f"{probs}/presentation_x{n}.json", f"{probs}/presentation_x{n}_plan.json", args,
                    a.time_limit_ms, a.objective)
            results["scaling"][key][n] = r
            print(key, n, r, flush=True)
            if r["status"] != "optimal":
                break
    for n in (2, 3, 4):
        for key in ("D", "F"):
            r = run(f"{probs}/search_rescue_r{n}.json", f"{probs}/search_rescue_r{n}_plan.json",
                    dict((k, g) for k, _, g in CONFIGS)[key], a.time_limit_ms, a.objective)
            results["coupled"].setdefault(n, {})[key] = r
            print("coupled", key, n, r, flush=True)
    os.makedirs(a.out, exist_ok=True)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    mzn = subprocess.run(["minizinc", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    meta = {"command": "python3 bench/run_bench.py " + " ".join(sys.argv[1:]),
            "machine": f"{os.cpu_count()} cores, {cpu}, {platform.platform()}", "minizinc": mzn,
            "time_limit_ms": a.time_limit_ms, "objective": a.objective}
    results["meta"] = meta
    json.dump(results, open(os.path.join(a.out, "solve_scaling.json"), "w"), indent=1)
    L = ["# Solver scaling (issue 3)", "",
         f"Made by `{meta['command']}` on {meta['machine']}; {mzn}; time limit "
         f"{a.time_limit_ms / 1000:.0f} s per solve; objective `{a.objective}`.", "",
         "Problem: the presentation domain with N copies of each automaton, each copy carrying the "
         "thesis' test prompt 1 constraints (chain-of-thought state plan): the thesis' Table 5.1. "
         "Times in seconds, end to end (`ctburton solve`, horizon growth and optimality proof "
         "over every plan with at most 32 events included). `optimum` is the time to a proven "
         "optimum; `—` means not reached within the limit. Variables are those of the last "
         "flattened model (of one part when the problem is split).", "", "Configurations, each adding one change:", ""]
    for key, desc, args in configs:
        L.append(f"- **{key}**: {desc} (`{' '.join(args) or 'defaults'}`)")
    L += ["", "| N | thesis vars | thesis first solution | config | status | vars | compile | first solution | optimum | peak MB | solver runs |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for n in sizes:
        tv, tf, _ = THESIS[n]
        for key, _, _ in configs:
            r = results["scaling"][key].get(n)
            if r is None:
                L.append(f"| {n} | {tv} | {tf} | {key} | not run (no optimum at a smaller N) | | | | | | |")
                continue
            opt = fmt_ms(r.get("solve_ms")) if r["status"] == "optimal" else "—"
            L.append(f"| {n} | {tv} | {tf} | {key} | {r['status']} | {r.get('variables', '—')} | "
                     f"{fmt_ms(r.get('compile_ms'))} | {fmt_ms(r.get('first_solution_ms'))} | {opt} | "
                     f"{r.get('peak_mb')} | {r.get('solver_runs', '—')} |")
    L += ["", "## Coupled: search_rescue with N robots and N persons (robot k rescues person k)", "",
          "The doors couple the robots, so the problem does not split.", "",
          "| robots | config | status | cost | vars | compile | first solution | optimum | peak MB |",
          "|---|---|---|---|---|---|---|---|---|"]
    for n, byk in results["coupled"].items():
        for key, r in byk.items():
            opt = fmt_ms(r.get("solve_ms")) if r["status"] == "optimal" else "—"
            L.append(f"| {n} | {key} | {r['status']} | {r.get('objective')} | {r.get('variables')} | "
                     f"{fmt_ms(r.get('compile_ms'))} | {fmt_ms(r.get('first_solution_ms'))} | {opt} | {r.get('peak_mb')} |")
    open(os.path.join(a.out, "solve_scaling.md"), "w").write("\n".join(L) + "\n")
    print("wrote", os.path.join(a.out, "solve_scaling.md"))


if __name__ == "__main__":
    main()
