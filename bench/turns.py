#!/usr/bin/env python3
"""Devices that take turns (issue 29 item 1): time to prove the makespan optimum when a
maintenance constraint allows one warm-up at a time.

    python3 bench/turns.py [--bin build/client/ctburton] [--label after] [--sizes 2,3,4,5,6]
                           [--time-limit-ms 10000] [--out bench/results]

Device k goes off -> prep (prep_k s) -> warming (warm_k s) -> on -> ready (tail_k s), started by
its command (tests/planner/turns_problem.h builds the same); the goal is every device ready and
the maintenance constraint excludes every pair of warm-ups. Families, each at every size:
  - `same`: no prep, no tail, warm-ups of 3-7 s;
  - `staggered`: preps of 0-4 s and tails of 0-5 s as well;
  - `due`: `staggered`, and each device on within prep + warm + 2 s of its start command (a
    temporal constraint, as in bench/families.py's `due`);
  - `pairs`: `staggered` devices of which at most two warm at once (every three excluded: two
    machines; its optimum is the best list schedule of every order on two machines).
The optimum is computed here independently: the best order of one machine (every permutation,
each warm-up as early as its release and the previous one allow; its makespan the latest end plus
tail), which a plan can always follow (a device waits off until its turn). Each row: status,
makespan, bound, first plan and answer seconds, who found and who proved it, and whether the value
is the independent optimum. Results go to turns.json under --label (other labels kept) and
turns.md is rewritten from all labels.
"""
import argparse
import itertools
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import solve_makespan  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FAMILIES = ("same", "staggered", "due", "pairs")


def devices(family, n):
    out = []
    for k in range(n):
        warm = 3 + (7 * k) % 5
        prep = 0 if family == "same" else (3 * k) % 5
        tail = 0 if family == "same" else (2 * k + 1) % 6
        out.append((prep, warm, tail))
    return out


def domain(devs):
    autos = []
    for k, (prep, warm, tail) in enumerate(devs, start=1):
        name = f"dev{k}"
        locs, ts = ["off", "warming", "on"], []
        if prep:
            locs.append("prep")
            ts += [{"from": "off", "to": "prep", "guard": f"{name}u[i]==start"},
                   {"from": "prep", "to": "warming", "duration": [prep, prep]}]
        else:
            ts.append({"from": "off", "to": "warming", "guard": f"{name}u[i]==start"})
        ts.append({"from": "warming", "to": "on", "duration": [warm, warm]})
        if tail:
            locs.append("ready")
            ts.append({"from": "on", "to": "ready", "duration": [tail, tail]})
        autos.append({"name": name, "locations": locs, "commands": ["start"], "transitions": ts})
    return {"name": "turns", "description": "devices that warm up one at a time", "automata": autos}


def state_plan(family, devs):
    n = len(devs)
    init = {f"dev{k}": "off" for k in range(1, n + 1)}
    if family == "pairs":
        pairs = [f"not (dev{a}l[i]==warming /\\ dev{b}l[i]==warming /\\ dev{c}l[i]==warming)"
                 for a in range(1, n + 1) for b in range(a + 1, n + 1) for c in range(b + 1, n + 1)]
    else:
        pairs = [f"not (dev{a}l[i]==warming /\\ dev{b}l[i]==warming)"
                 for a in range(1, n + 1) for b in range(a + 1, n + 1)]
    goal = " /\\ ".join(f"dev{k}l[i+1]=={'ready' if t else 'on'}"
                        for k, (_, _, t) in enumerate(devs, start=1))
    temporal = {}
    if family == "due":
        for k, (prep, warm, _) in enumerate(devs, start=1):
            temporal[f"Dev{k}Due"] = {
                "accepting_event1_constraint": f"dev{k}l[i]==off /\\ dev{k}l[i+1]!=off",
                "accepting_event2_constraint": f"dev{k}l[i+1]==on",
                "lower_bound": 0, "upper_bound": prep + warm + 2}
    sp = {"initial_state": init,
          "end_state": {"maintenance_constraint": " /\\ ".join(pairs) or "true",
                        "goal_constraint": goal},
          "objective": "makespan"}
    if temporal:
        sp["constraints"] = {"temporal": temporal}
    return sp


def optimum(devs, machines=1):
    """The best order on this many machines, each warm-up as early as possible on the machine
    free first (every schedule of identical machines is beaten or matched by such a list schedule
    of some order)."""
    best = None
    for order in itertools.permutations(range(len(devs))):
        free, end = [0] * machines, 0
        for j in order:
            prep, warm, tail = devs[j]
            m = min(range(machines), key=lambda k: free[k])
            start = max(prep, free[m])
            free[m] = start + warm
            end = max(end, free[m] + tail)
        best = end if best is None else min(best, end)
    return best




def write_md(path, data):
    with open(path, "w") as f:
        f.write("# Devices that take turns (issue 29 item 1)\n\n`bench/turns.py`: one warm-up at a "
                "time (pairwise exclusions in the maintenance constraint), makespan. `optimum` is "
                "computed by the script (the best order of one machine); `=` says whether the "
                "answer's value is it. Seconds: first verified plan and end of the solve.\n\n")
        for label, run in data.items():
            f.write(f"## {label}\n\nCommand: `{run['command']}` (binary `{run['binary']}`); load "
                    f"average {run['load_before']} before, {run['load_after']} after, 2 cores.\n\n"
                    "| family | devices | optimum | status | makespan | = | bound | first s | "
                    "answer s | found by | proved by |\n|---|---|---|---|---|---|---|---|---|---|---|\n")
            for r in run["rows"]:
                f.write(f"| {r['family']} | {r['n']} | {r['optimum']} | {r['status']} | "
                        f"{r.get('makespan')} | {'yes' if r.get('makespan') == r['optimum'] else 'no'} | "
                        f"{r.get('bound')} | {r.get('first_s')} | {r.get('answer_s')} | "
                        f"{r.get('found_by') or '—'} | {r.get('proved_by') or '—'} |\n")
            f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "client", "ctburton"))
    ap.add_argument("--label", default="after")
    ap.add_argument("--sizes", default="2,3,4,5,6")
    ap.add_argument("--time-limit-ms", type=int, default=10000)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    sizes = [int(x) for x in a.sizes.split(",")]
    load_before = " ".join(open("/proc/loadavg").read().split()[:3])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for family in FAMILIES:
            for n in sizes:
                devs = devices(family, n)
                dom, sp = os.path.join(tmp, "d.json"), os.path.join(tmp, "p.json")
                json.dump(domain(devs), open(dom, "w"))
                json.dump(state_plan(family, devs), open(sp, "w"))
                r = {"family": family, "n": n, "devices": devs,
                     "optimum": optimum(devs, 2 if family == "pairs" else 1)}
                r.update(solve_makespan(a.bin, dom, sp, a.time_limit_ms))
                print(json.dumps(r), flush=True)
                rows.append(r)
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "turns.json")
    data = json.load(open(path)) if os.path.exists(path) else {}
    data[a.label] = {"command": " ".join(["python3 bench/turns.py"] + sys.argv[1:]), "binary": a.bin,
        "load_before": load_before, "load_after": " ".join(open("/proc/loadavg").read().split()[:3]), "rows": rows}
    json.dump(data, open(path, "w"), indent=1)
    write_md(os.path.join(a.out, "turns.md"), data)


if __name__ == "__main__":
    main()
