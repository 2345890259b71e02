#!/usr/bin/env python3
"""Coupled problems, where nothing splits (issue 9), and the infeasible requests it lists.

    python3 bench/coupled.py [--time-limit-ms 60000] [--quick] [--first-plan-ms N] [--out bench/results]

Generates the problems from the shipped domains (tools/gen_domains.py, bench/gen_scaled.py), runs
`build/client/ctburton solve` under /usr/bin/time on each and writes bench/results/coupled.{md,json}:
status, objective, `bound` (when the time limit ends the search first), time to the first plan,
end-to-end time, solver runs and peak memory of the process tree. --quick runs the small ones
(what CI can afford; tests/cli/coupled_test.sh runs them and checks every answer).
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
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_domains  # noqa: E402
import gen_scaled  # noqa: E402


def load(path):
    with open(path) as f:
        return json.load(f)


def presentation_coupled(n):
    """n copies of test prompt 1, plus an episode that needs every projector on together."""
    plan = gen_scaled.presentation_plan(n)
    if n == 1:
        plan["constraints"]["episodes"]["ProjectorOnLong"] = {
            "accepting_constraint": "projl[i]==projOn", "state_constraint": "projl[i]==projOn",
            "lower_bound": 600, "upper_bound": 3600}
        return plan
    together = " /\\ ".join(f"proj{k}l[i]==projOn" for k in range(1, n + 1))
    plan["constraints"]["episodes"]["AllProjectorsOn"] = {
        "accepting_constraint": together, "state_constraint": together,
        "lower_bound": 60, "upper_bound": 1800}
    return plan


def problems(tmp, quick):
    out = []

    def add(label, domain, plan, objective, size="small"):
        if quick and size != "small":
            return
        path = os.path.join(tmp, f"p{len(out)}.json")
        with open(path, "w") as f:
            json.dump(plan, f)
        out.append((label, domain, path, objective))

    def domain_file(name, dom):
        path = os.path.join(tmp, name + ".json")
        with open(path, "w") as f:
            json.dump(dom, f)
        return path

    ex = os.path.join(ROOT, "config", "examples")
    add("presentation 1x, test prompt 1", "presentation", load(f"{ex}/presentation/test1_cot.json"),
        "makespan")
    add("presentation 1x, test prompt 1 + projector on 600-3600 s", "presentation",
        presentation_coupled(1), "makespan")
    for n, objective, size in ((2, "cost", "small"), (4, "cost", "large"), (8, "makespan", "large")):
        dom = gen_domains.presentation(n)
        dom["name"] = f"presentation_x{n}"
        add(f"presentation {n}x, all projectors on together", domain_file(f"pres{n}", dom),
            presentation_coupled(n), objective, size)
    for n, objectives, size in ((3, ("makespan",), "large"), (4, ("makespan", "cost"), "large"),
                                (6, ("makespan",), "large"), (8, ("makespan",), "large")):
        dom = gen_domains.search_rescue(n)
        dom["name"] = f"search_rescue_r{n}"
        d = domain_file(f"rescue{n}", dom)
        for objective in objectives:
            add(f"search_rescue, {n} robots", d, gen_scaled.rescue_plan(n), objective, size)
    # The thesis benchmark (independent copies of test prompt 1): nothing may get slower here.
    for n, size in ((1, "small"), (4, "large"), (16, "large")):
        dom = gen_domains.presentation(n)
        dom["name"] = f"presentation_x{n}"
        add(f"thesis copies {n}x (independent), test prompt 1 each", domain_file(f"copies{n}", dom),
            gen_scaled.presentation_plan(n), "cost", size)
    # Infeasible requests.
    add("infeasible: deadline below the warm-up", "presentation",
        load(os.path.join(ROOT, "tests", "data", "deadline_infeasible.json")), "cost")
    add("infeasible: thesis direct answer to test prompt 2", "presentation",
        load(f"{ex}/presentation/test2_direct.json"), "cost")
    shut = load(f"{ex}/search_rescue/test2.json")
    shut["end_state"]["maintenance_constraint"] = "door1l[i]==closed /\\ door2l[i]==closed"
    shut.setdefault("constraints", {}).setdefault("temporal", {})["RescueWithin30"] = {
        "accepting_event1_constraint": "robot1l[i+1]==outside",
        "accepting_event2_constraint": "robot1l[i+1]==rescuedPerson1",
        "lower_bound": 0, "upper_bound": 30}
    add("infeasible: doors kept shut plus a deadline", "search_rescue", shut, "cost")
    return out


def run(label, domain, plan, objective, limit_ms, first_plan_ms=None):
    cmd = ["/usr/bin/time", "-f", "%M", BIN, "solve", "--domain", domain, plan, "--objective",
           objective, "--time-limit-ms", str(limit_ms)]
    if first_plan_ms is not None:  # the first-plan engine's budget (0: off, as before issue 18)
        cmd += ["--first-plan-ms", str(first_plan_ms)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 120)
    mem = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "-1"
    row = {"problem": label, "objective_kind": objective,
           "peak_mb": round(int(mem) / 1024, 1) if mem.isdigit() else None}
    if p.returncode != 0:
        row.update(status="error", error=p.stderr.strip()[-300:])
        return row
    t = json.loads(p.stdout)
    s = t["stats"]
    row.update(status=t["status"], objective=t["objective"]["value"], bound=t.get("bound"),
               verified=t["verified"], first_solution_ms=s.get("first_solution_ms"),
               solve_ms=s.get("solve_ms"), solver_runs=s.get("solver_runs"),
               solver=s.get("solver"), found_by=s.get("found_by"), proved_by=s.get("proved_by"))
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--first-plan-ms", type=int, default=None,
                    help="passed to ctburton solve (0 turns the first-plan engine off)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, domain, plan, objective in problems(tmp, a.quick):
            r = run(label, domain, plan, objective, a.time_limit_ms, a.first_plan_ms)
            print(json.dumps(r), flush=True)
            rows.append(r)
    if a.quick:
        bad = [r for r in rows if r["status"] == "error" or
               (r["status"] in ("optimal", "feasible") and not r.get("verified"))]
        sys.exit(1 if bad else 0)
    os.makedirs(a.out, exist_ok=True)
    cmd = "python3 bench/coupled.py " + " ".join(sys.argv[1:])
    with open(os.path.join(a.out, "coupled.json"), "w") as f:
        json.dump({"command": cmd, "rows": rows}, f, indent=1)
    with open(os.path.join(a.out, "coupled.md"), "w") as f:
        f.write("# Coupled problems and infeasible requests (issue 9)\n\n")
        f.write(f"Made by `{cmd}` on {os.cpu_count()} cores, {platform.platform()}; time limit "
                f"{a.time_limit_ms} ms per solve. Seconds end to end (`stats.solve_ms`); "
                f"`first` is the first verified plan.\n\n")
        f.write("| problem | objective | status | value | bound | first | total | runs | solver | "
                "found by | proved by | peak MB |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            def sec(v):
                return "—" if v is None or v < 0 else f"{v / 1000:.2f}"
            f.write(f"| {r['problem']} | {r['objective_kind']} | {r['status']} | "
                    f"{json.dumps(r.get('objective'))} | {json.dumps(r.get('bound'))} | "
                    f"{sec(r.get('first_solution_ms'))} | {sec(r.get('solve_ms'))} | "
                    f"{r.get('solver_runs', '')} | {r.get('solver', '')} | "
                    f"{r.get('found_by') or '—'} | {r.get('proved_by') or '—'} | {r.get('peak_mb')} |\n")


if __name__ == "__main__":
    main()
