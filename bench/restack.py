#!/usr/bin/env python3
"""Re-stacking blocks (issue 29 item 4): random start and goal towers of 4 blocks, 2 and 3 arms.

    python3 bench/restack.py [--bin build/client/ctburton] [--seed 7] [--count 8]
                             [--time-limit-ms 10000] [--out bench/results]

The domain is bench/assembly_proofs.py's `assembly(blocks, arms)` (the shipped assembly domain
generalised); each problem asks for the goal towers with every arm home, objective makespan.
Towers are drawn by `random_config`: blocks in random order, each put on the floor or (p = 0.6)
on top of a random existing tower. The same `count` problems are solved with 2 and with 3 arms.
Writes restack.json and restack.md (status, makespan, bound, first plan and answer seconds, who
found and who proved) under --out.
"""
import argparse
import json
import os
import random
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from assembly_proofs import assembly, plan  # noqa: E402
from common import solve_makespan  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def random_config(blocks, rng):
    order = list(blocks)
    rng.shuffle(order)
    cfg, tops = {}, []
    for b in order:
        if tops and rng.random() < 0.6:
            i = rng.randrange(len(tops))
            cfg[b] = "on" + tops[i]
            tops[i] = b
        else:
            cfg[b] = "onFloor"
            tops.append(b)
    return cfg


def towers(cfg):
    """'C/A/D, B': each tower from its top down."""
    below = {b: loc[2:] for b, loc in cfg.items()}
    above = {v: b for b, v in below.items() if v != "Floor"}
    out = []
    for b in sorted(cfg):
        if below[b] == "Floor":
            t = [b]
            while t[-1] in above:
                t.append(above[t[-1]])
            out.append("/".join(reversed(t)))
    return ", ".join(out)




def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "client", "ctburton"))
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--count", type=int, default=8)
    ap.add_argument("--time-limit-ms", type=int, default=10000)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    rng = random.Random(a.seed)
    problems = []
    for _ in range(a.count):
        start = random_config("ABCD", rng)
        goal = random_config("ABCD", rng)
        while goal == start:
            goal = random_config("ABCD", rng)
        problems.append((start, goal))
    load_before = open("/proc/loadavg").read().split()[:3]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for arms in (2, 3):
            dom = os.path.join(tmp, f"assembly_{arms}.json")
            json.dump(assembly("ABCD", arms), open(dom, "w"))
            for k, (start, goal) in enumerate(problems):
                sp = os.path.join(tmp, "plan.json")
                json.dump(plan(arms, start, goal), open(sp, "w"))
                r = {"problem": k, "arms": arms, "start": towers(start), "goal": towers(goal)}
                r.update(solve_makespan(a.bin, dom, sp, a.time_limit_ms))
                print(json.dumps(r), flush=True)
                rows.append(r)
    load_after = open("/proc/loadavg").read().split()[:3]
    cmd = " ".join(["python3 bench/restack.py"] + sys.argv[1:])
    res = {"command": cmd, "binary": a.bin, "load_before": load_before, "load_after": load_after,
           "rows": rows}
    os.makedirs(a.out, exist_ok=True)
    json.dump(res, open(os.path.join(a.out, "restack.json"), "w"), indent=1)
    proven = sum(r["status"] == "optimal" for r in rows)
    with open(os.path.join(a.out, "restack.md"), "w") as f:
        f.write(f"# Re-stacking 4 blocks with 2 and 3 arms (issue 29 item 4)\n\nCommand: `{cmd}` "
                f"(binary `{a.bin}`); load average {' '.join(load_before)} before, "
                f"{' '.join(load_after)} after, 2 cores. Proven optimal: {proven} of {len(rows)}.\n\n"
                "| # | arms | start (top/.../bottom) | goal | status | makespan | bound | first s | "
                "answer s | found by | proved by |\n|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['problem']} | {r['arms']} | {r['start']} | {r['goal']} | {r['status']} | "
                    f"{r.get('makespan')} | {r.get('bound')} | {r.get('first_s')} | "
                    f"{r.get('answer_s')} | {r.get('found_by') or '—'} | {r.get('proved_by') or '—'} |\n")
    print(f"proven {proven} of {len(rows)}")


if __name__ == "__main__":
    main()
