#!/usr/bin/env python3
"""New coupled families nobody tuned for (issue 18): search and rescue teams written from the
template config/templates/search_rescue_team.json (expanded by `ctburton domain expand`), with

  assign  free assignment: every person rescued by some robot, robots of three speeds
          (robot k's timed moves take 1, 2 or 3 times as long);
  assign_eq  the same with robots of one speed (interchangeable: bench/symmetry.py);
  door    a shared resource as a state constraint: at most one robot opening door 1 or door 2
          at a time, robot k rescues person k;
  due     deadlines: robot k rescues person k within a bound a little above its fastest route;
  all     the three together;
  cost    issue 29 item 2, under `cost` and `cost_then_makespan`: every person rescued by some
          robot, robots of three speeds and three running costs (the fast ones dear: robot k's
          moves cost 3, 2 or 1 each, its timed moves take 1, 2 or 3 times as long) and persons at
          three distances (the last leg to person p costs 1, 2 or 3 times the robot's rate);
  cost_spare  the same with one robot more than there are persons (who stays out, who opens).

    python3 bench/families.py [--sizes 2,4,8,16] [--time-limit-ms 30000] [--before OLD_BINARY]
                              [--binary BINARY] [--out bench/results] [--name families]

Runs `ctburton solve` on each (makespan; the cost families under cost and cost_then_makespan),
and with --before the same problems with another binary (e.g. one built before a change), and
writes bench/results/<name>.{md,json}: status, objective, the bound of a feasible answer, time to
the first verified plan, end-to-end time, which engine found and proved it.
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import BIN, ROOT  # noqa: E402

TEMPLATE = os.path.join(ROOT, "config", "templates", "search_rescue_team.json")
FAMILIES = ("assign", "assign_eq", "door", "due", "all")
COST_FAMILIES = ("cost", "cost_spare")
OBJECTIVES = {"cost": ("cost", "cost_then_makespan"), "cost_spare": ("cost", "cost_then_makespan")}
# Beyond these sizes the goal or the pairwise door constraint is longer than the 8192 characters
# a state-plan expression may have (contract section 8): the state plan cannot say it.
MAX_ROBOTS = {"assign": 8, "assign_eq": 8, "door": 8, "due": 64, "all": 8, "cost": 8,
              "cost_spare": 8}


def running_cost(k):
    """Robot k's cost per move in the cost families: the fast robots (speed factor 1) dearest."""
    return 4 - (1 + (k - 1) % 3)


def distance(p):
    """How far person p is carried in the cost families: the last leg's multiplier."""
    return 1 + (p - 1) % 3


def expand(binary, n, speeds, path, costs=False):
    """The team of n robots; with speeds, robot k's timed transitions scaled by 1, 2 or 3; with
    costs, robot k's transitions cost running_cost(k) each, its last leg to person p times
    distance(p)."""
    p = subprocess.run([binary, "domain", "expand", TEMPLATE, "--set", f"N={n}"],
                       capture_output=True, text=True, check=True)
    dom = json.loads(p.stdout)
    dom["name"] = f"rescue_team_{n}"
    if speeds:
        for a in dom["automata"]:
            if not a["name"].startswith("robot"):
                continue
            factor = 1 + (int(a["name"][5:]) - 1) % 3
            for t in a["transitions"]:
                if "duration" in t:
                    t["duration"] = [v * factor if v is not None else None for v in t["duration"]]
    if costs:
        for a in dom["automata"]:
            if not a["name"].startswith("robot"):
                continue
            rate = running_cost(int(a["name"][5:]))
            for t in a["transitions"]:
                person = t["to"].startswith("rescuedPerson")
                t["cost"] = rate * (distance(int(t["to"][len("rescuedPerson"):])) if person else 1)
    with open(path, "w") as f:
        json.dump(dom, f)


def persons(n, family):
    return n - 1 if family == "cost_spare" else n


def plan(n, family):
    init = {f"robot{k}": "outside" for k in range(1, n + 1)}
    init.update({"door1": "closed", "door2": "closed", "door3": "open"})
    robots = range(1, n + 1)
    if family in COST_FAMILIES:
        goal = " /\\ ".join("(" + " \\/ ".join(f"robot{k}l[i+1]==rescuedPerson{p}" for k in robots) + ")"
                            for p in range(1, persons(n, family) + 1))
    elif family in ("assign", "assign_eq", "all"):
        goal = " /\\ ".join("(" + " \\/ ".join(f"robot{k}l[i+1]==rescuedPerson{p}" for k in robots) + ")"
                            for p in robots)
    else:
        goal = " /\\ ".join(f"robot{k}l[i+1]==rescuedPerson{k}" for k in robots)
    maintenance = "true"
    if family in ("door", "all"):
        pairs = [f"not (robot{a}l[i]==door{d}Opening /\\ robot{b}l[i]==door{d}Opening)"
                 for d in (1, 2) for a in robots for b in robots if a < b]
        maintenance = " /\\ ".join(pairs) if pairs else "true"
    temporal = {}
    if family in ("due", "all"):
        for k in robots:
            # The fastest rescue through door 1 takes 11 s (door 2: 13 s); slower robots get more.
            factor = 1 + (k - 1) % 3 if family == "all" else 1
            temporal[f"Robot{k}Within"] = {
                "accepting_event1_constraint": f"robot{k}l[i]==outside /\\ robot{k}l[i+1]!=outside",
                "accepting_event2_constraint": f"robot{k}l[i+1]==rescuedPerson{k}" if family == "due"
                else " \\/ ".join(f"robot{k}l[i+1]==rescuedPerson{p}" for p in robots),
                "lower_bound": 0, "upper_bound": 14 * factor + 2 * k}
    return {"initial_state": init,
            "end_state": {"maintenance_constraint": maintenance, "goal_constraint": goal},
            "constraints": {"episodes": {}, "temporal": temporal, "event": {}}}


def run(binary, domain, plan_path, limit_ms, objective="makespan"):
    cmd = [binary, "solve", "--domain", domain, plan_path, "--objective", objective,
           "--time-limit-ms", str(limit_ms)]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 60)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if p.returncode != 0:
        return {"status": "error", "error": p.stderr.strip()[-300:]}
    t = json.loads(p.stdout)
    s = t["stats"]
    value = t["objective"]["value"]
    if isinstance(value, dict):
        value = f"{value['cost']}, {value['makespan']}"
    bound = t.get("bound")
    if isinstance(bound, dict):
        bound = f"{bound['cost']}, {bound['makespan']}"
    return {"status": t["status"], "objective": value, "bound": bound, "verified": t["verified"],
            "first_s": None if s.get("first_solution_ms") in (None, -1) else round(s["first_solution_ms"] / 1000, 2),
            "total_s": round(s["solve_ms"] / 1000, 2), "found_by": s.get("found_by"),
            "proved_by": s.get("proved_by")}


def cell(r, key):
    v = r.get(key)
    return "—" if v is None else str(v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="2,4,8,16")
    ap.add_argument("--families", default=",".join(FAMILIES),
                    help="any of " + ", ".join(FAMILIES + COST_FAMILIES))
    ap.add_argument("--time-limit-ms", type=int, default=30000)
    ap.add_argument("--binary", default=BIN, help="the ctburton binary measured (default build/)")
    ap.add_argument("--before", help="another ctburton binary to run on the same problems")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--name", default="families", help="the results' file name, without .md/.json")
    a = ap.parse_args()
    sizes = [int(x) for x in a.sizes.split(",")]
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for family in a.families.split(","):
            for n in sizes:
                if n > MAX_ROBOTS[family]:
                    continue
                dom = os.path.join(tmp, f"{family}{n}_domain.json")
                expand(a.binary, n, family in ("assign", "all") + COST_FAMILIES, dom,
                       costs=family in COST_FAMILIES)
                path = os.path.join(tmp, f"{family}{n}.json")
                with open(path, "w") as f:
                    json.dump(plan(n, family), f)
                for objective in OBJECTIVES.get(family, ("makespan",)):
                    row = {"family": family, "robots": n, "persons": persons(n, family),
                           "objective": objective,
                           "now": run(a.binary, dom, path, a.time_limit_ms, objective)}
                    if a.before:
                        row["before"] = run(a.before, dom, path, a.time_limit_ms, objective)
                    print(json.dumps(row), flush=True)
                    rows.append(row)
    load = os.getloadavg()
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, a.name + ".json"), "w") as f:
        json.dump(rows, f, indent=1)
    cmd = "python3 bench/families.py " + " ".join(sys.argv[1:])
    lines = ["# New coupled families (issues 18 and 29): problems nobody tuned for", "",
             f"Made by `{cmd}` on {os.cpu_count()} cores, {platform.platform()}; time limit "
             f"{a.time_limit_ms} ms per solve. Load average (1 / 5 / 15 min) at "
             f"the start {load_before[0]:.1f} / {load_before[1]:.1f} / {load_before[2]:.1f}, at the "
             f"end {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f}. Seconds; `first`: the first verified "
             "plan; `total`: the answer (`stats.solve_ms`); `bound`: a feasible answer's bound "
             "(cost, or cost and makespan).", "",
             "Families (bench/families.py), objective makespan: `assign` free assignment of robots to "
             "persons, robots of three speeds (`assign_eq`: one speed); `door` at most one robot "
             "opening each door at a time (a state constraint); `due` a deadline per rescue; `all` "
             "the three together. Under `cost` and `cost_then_makespan`: `cost` every person rescued "
             "by some robot, robots of three speeds and running costs, persons at three distances; "
             "`cost_spare` the same with one robot more than persons.", ""]
    head = "| family | robots | objective | status | value | bound | first | total | found by | proved by |"
    if a.before:
        head += " before: status | before: value | before: bound | before: first | before: total |"
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        x = r["now"]
        line = (f"| {r['family']} | {r['robots']} | {r.get('objective', 'makespan')} | {x['status']} | "
                f"{cell(x, 'objective')} | {cell(x, 'bound')} | "
                f"{cell(x, 'first_s')} | {cell(x, 'total_s')} | {cell(x, 'found_by')} | {cell(x, 'proved_by')} |")
        if a.before:
            b = r["before"]
            line += (f" {b['status']} | {cell(b, 'objective')} | {cell(b, 'bound')} | "
                     f"{cell(b, 'first_s')} | {cell(b, 'total_s')} |")
        lines.append(line)
    with open(os.path.join(a.out, a.name + ".md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    bad = [r for r in rows if r["now"]["status"] in ("error", "timeout") or
           (r["now"]["status"] in ("optimal", "feasible") and not r["now"].get("verified"))]
    if bad:
        print(f"{len(bad)} problem(s) failed", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
