#!/usr/bin/env python3
"""Times `ctburton network check` (contract section 13, issue 26) on random STNUs of 100, 1,000
and 10,000 points, and writes bench/results/network_check.{md,json}.

The networks look like plans: points on a hidden timeline; each point after the first is linked
from one of the 8 points before it, by a contingent link (20%, [d-w, d+w] around the hidden
duration d, w <= slack/8) or a requirement link (bounds d -/+ slack/2..slack, ub sometimes +inf);
`extra` more requirement links per point (on average) from random points at most 20 before it
(d -/+ slack..3 slack); 1% of points get a deadline from point 0 (its hidden time + 5 slack).
Families: `loose` (slack 40, 2 extra links a point: dynamically controllable), `tight` (slack 2:
mostly not), `sparse` (slack 40, 0.2 extra links a point: closer to a plan's network, chains
of durations with a few cross constraints) and `reactive` (sparse, and the point after each
contingent one must follow it by its hidden gap plus at most 2 s: dynamically but not strongly controllable). A strongly
controllable network is dynamically controllable without Morris's searches; `reactive` is the
family that measures them. Times: the check's own `ms` (parse excluded) and the
process's wall time (reading and parsing the file included).

    python3 bench/network_check.py [--sizes 100,1000,10000] [--seeds 3]
"""
import argparse
import json
import os
import platform
import random
import subprocess
import tempfile
import time

from common import BIN, ROOT


def network(n, seed, slack, extra=2.0, react=False):
    rng = random.Random(seed)
    t = [0]
    for _ in range(1, n):
        t.append(t[-1] + rng.randint(0, 20))
    links, contingent_end = [], set()
    for j in range(1, n):
        i = rng.randint(max(0, j - 8), j - 1)
        d = t[j] - t[i]
        if rng.random() < 0.2 and j not in contingent_end:
            w = rng.randint(0, max(1, min(d // 4, slack // 8)))
            links.append({"from": f"p{i}", "to": f"p{j}", "lb": max(0, d - w), "ub": d + w,
                          "contingent": True})
            contingent_end.add(j)
        else:
            links.append({"from": f"p{i}", "to": f"p{j}", "lb": d - rng.randint(slack // 2, slack),
                          "ub": None if rng.random() < 0.3 else d + rng.randint(slack // 2, slack)})
        for _ in range(int(extra) + (1 if rng.random() < extra - int(extra) else 0)):
            k = rng.randint(max(0, j - 20), j - 1)
            d = t[j] - t[k]
            links.append({"from": f"p{k}", "to": f"p{j}", "lb": d - rng.randint(slack, 3 * slack),
                          "ub": None if rng.random() < 0.5 else d + rng.randint(slack, 3 * slack)})
        if rng.random() < 0.01:
            links.append({"from": "p0", "to": f"p{j}", "lb": 0, "ub": t[j] + 5 * slack})
        if react and j - 1 in contingent_end and j not in contingent_end:
            # the point after a contingent one follows it by its hidden gap d to d + 2 s: a
            # reaction to the outcome, not a schedule
            d = t[j] - t[j - 1]
            links.append({"from": f"p{j - 1}", "to": f"p{j}", "lb": d, "ub": d + 2})
    return {"points": [f"p{i}" for i in range(n)], "links": links}


def run(path):
    t0 = time.perf_counter()
    out = subprocess.run([BIN, "network", "check", path], capture_output=True, text=True,
                         check=True).stdout
    wall = (time.perf_counter() - t0) * 1000
    return json.loads(out), wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="100,1000,10000")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "network_check"))
    args = ap.parse_args()
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(x) for x in args.sizes.split(",")]:
            for family, slack, extra, react in (("loose", 40, 2.0, False), ("tight", 2, 2.0, False),
                                                ("sparse", 40, 0.2, False),
                                                ("reactive", 40, 0.2, True)):
                for seed in range(args.seeds):
                    net = network(n, seed, slack, extra, react)
                    path = os.path.join(tmp, f"n{n}_{family}_{seed}.json")
                    with open(path, "w") as f:
                        json.dump(net, f)
                    answer, wall = run(path)
                    rows.append({"points": n, "links": len(net["links"]), "family": family,
                                 "seed": seed, "consistent": answer["consistent"],
                                 "strong": answer["strong"], "dynamic": answer["dynamic"],
                                 "conflict_links": len(answer.get("conflict", [])),
                                 "check_ms": round(answer["ms"], 2), "wall_ms": round(wall, 1)})
                    print(json.dumps(rows[-1]), flush=True)
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    meta = {"command": "python3 bench/network_check.py --sizes %s --seeds %d" % (args.sizes, args.seeds),
            "machine": "%s, %s, %d cores" % (platform.node(), platform.processor() or platform.machine(),
                                             os.cpu_count()),
            "load_average_before": [round(x, 2) for x in load_before], "uptime_after": uptime}
    with open(args.out + ".json", "w") as f:
        json.dump({"meta": meta, "rows": rows}, f, indent=1)
        f.write("\n")
    with open(args.out + ".md", "w") as f:
        f.write("# `ctburton network check` on random STNUs (issue 26)\n\n")
        f.write("Command: `%s`  \nMachine: %s  \nLoad average before: %s  \nAfter: `%s`\n\n"
                % (meta["command"], meta["machine"], meta["load_average_before"], uptime))
        f.write("check ms: the library's check (consistency, strong, dynamic, conflict); wall ms: "
                "the whole `ctburton` process (reading and parsing the file included).\n\n")
        f.write("| points | links | family | seed | consistent | strong | dynamic | conflict links "
                "| check ms | wall ms |\n|---:|---:|---|---:|---|---|---|---:|---:|---:|\n")
        for r in rows:
            f.write("| %(points)d | %(links)d | %(family)s | %(seed)d | %(consistent)s | %(strong)s "
                    "| %(dynamic)s | %(conflict_links)d | %(check_ms).2f | %(wall_ms).1f |\n" % r)
        for n in sorted({r["points"] for r in rows}):
            worst = max(r["check_ms"] for r in rows if r["points"] == n)
            wall = max(r["wall_ms"] for r in rows if r["points"] == n)
            f.write("\nWorst at %d points: check %.2f ms, wall %.1f ms." % (n, worst, wall))
        f.write("\n")


if __name__ == "__main__":
    main()
