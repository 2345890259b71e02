#!/usr/bin/env python3
"""IPC temporal domains through ctburton (issue 32 item 6): per domain, the first N instances
imported with `ctburton domain import-pddl` (yes/no, the first error, seconds), then solved with
`ctburton solve` under a time limit (status, makespan, seconds to the answer).

The competition files are public data written by others and are not committed: pass the folder
that holds them (e.g. a checkout of potassco/pddl-instances), laid out as
<root>/ipc-YEAR/domains/<domain>/domain.pddl and instances/instance-K.pddl.

  python3 bench/pddl_ipc.py /tmp/ipc --limit 30 --instances 3 --out bench/results/pddl_ipc
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

from common import BIN

DOMAINS = [  # (label, folder under the root)
    ("driverlog", "ipc-2014/domains/driver-log-temporal-satisficing"),
    ("floortile", "ipc-2014/domains/floor-tile-temporal-satisficing"),
    ("matchcellar", "ipc-2014/domains/match-cellar-temporal-satisficing"),
    ("turnandopen", "ipc-2014/domains/turn-and-open-temporal-satisficing"),
    ("parking", "ipc-2014/domains/parking-temporal-satisficing"),
    ("satellite", "ipc-2014/domains/satellite-temporal-satisficing"),
    ("storage", "ipc-2014/domains/storage-temporal-satisficing"),
    ("elevators", "ipc-2011/domains/elevator-temporal-satisficing"),
    ("sokoban", "ipc-2011/domains/sokoban-temporal-satisficing"),
    ("pegsol", "ipc-2011/domains/peg-solitaire-temporal-satisficing"),
    ("crewplanning", "ipc-2011/domains/crew-planning-temporal-satisficing"),
    ("openstacks", "ipc-2011/domains/openstacks-temporal-satisficing"),
    ("mapanalyser", "ipc-2014/domains/map-analyzer-temporal-satisficing"),
    ("rtam", "ipc-2014/domains/road-traffic-accident-management-temporal-satisficing"),
    ("tms", "ipc-2014/domains/temporal-machine-shop-temporal-satisficing"),
    ("rovers", "ipc-2002/domains/rovers-time-automatic"),
    ("tpp", "ipc-2006/domains/tpp-metric-time"),
]


def domain_file(folder, k):
    per = os.path.join(folder, "domains", "domain-%d.pddl" % k)
    return per if os.path.exists(per) else os.path.join(folder, "domain.pddl")


def run(cmd, timeout):
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr, time.time() - t0
    except subprocess.TimeoutExpired:
        return None, "", "timeout", time.time() - t0


def one(folder, k, limit, tmp):
    dom, prob = domain_file(folder, k), os.path.join(folder, "instances", "instance-%d.pddl" % k)
    d_out, p_out = os.path.join(tmp, "d.json"), os.path.join(tmp, "p.json")
    rc, out, err, secs = run([BIN, "domain", "import-pddl", dom, prob, "-o", d_out,
                              "--state-plan-out", p_out], 120)
    r = {"instance": k, "imported": rc == 0, "import_s": round(secs, 3)}
    if rc != 0:
        r["error"] = (err.strip().splitlines() or ["?"])[0][:300]
        return r
    r["summary"] = out.strip()
    plan_out = os.path.join(tmp, "plan.pddl")
    if os.path.exists(plan_out):
        os.remove(plan_out)
    # `solve --pddl DOMAIN PROBLEM` imports again and solves with no JSON file between (the
    # imported models of the larger instances exceed what a file read used to allow), with the
    # largest horizon (200 events: two per action).
    rc, out, err, secs = run([BIN, "solve", "--pddl", dom, prob,
                              "--time-limit-ms", str(limit * 1000), "--pddl-plan", plan_out],
                             limit + 120)
    r["solve_s"] = round(secs, 2)
    if os.path.exists(plan_out):  # the plan written as PDDL 2.1 (docs/pddl.md)
        with open(plan_out) as f:
            r["pddl_plan_actions"] = sum(1 for line in f if line.strip() and not line.startswith(";"))
    try:
        t = json.loads(out)
        r["status"] = t.get("status")
        r["makespan"] = (t.get("objective") or {}).get("value")
        r["verified"] = t.get("verified")
        r["first_plan_ms"] = (t.get("stats") or {}).get("first_solution_ms")
        r["found_by"] = (t.get("stats") or {}).get("found_by")
    except ValueError:
        r["status"] = "error"
        r["error"] = " ".join(err.strip().splitlines()[:2] or ["?"])[:300]
    return r


def main():
    global BIN
    ap = argparse.ArgumentParser()
    ap.add_argument("root")
    ap.add_argument("--limit", type=int, default=30, help="seconds per solve")
    ap.add_argument("--instances", type=int, default=3)
    ap.add_argument("--no-solve", action="store_true")
    ap.add_argument("--solve-instances", type=int, default=None,
                    help="solve only the first K instances of each domain (import the rest)")
    ap.add_argument("--out", default=None, help="write OUT.json and OUT.md")
    ap.add_argument("--bin", default=None, help="the ctburton binary (default: build/)")
    a = ap.parse_args()
    BIN = a.bin or BIN
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, sub in DOMAINS:
            folder = os.path.join(a.root, sub)
            for k in range(1, a.instances + 1):
                solve = not a.no_solve and (a.solve_instances is None or k <= a.solve_instances)
                r = one(folder, k, a.limit, tmp) if solve else one_import(folder, k, tmp)
                r["domain"] = label
                rows.append(r)
                print(json.dumps(r), flush=True)
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    if a.out:
        json.dump({"uptime": uptime, "rows": rows}, open(a.out + ".json", "w"), indent=1)
        write_md(a, rows, uptime)


def one_import(folder, k, tmp):
    dom, prob = domain_file(folder, k), os.path.join(folder, "instances", "instance-%d.pddl" % k)
    rc, out, err, secs = run([BIN, "domain", "import-pddl", dom, prob, "-o",
                              os.path.join(tmp, "d.json"), "--state-plan-out",
                              os.path.join(tmp, "p.json")], 120)
    r = {"instance": k, "imported": rc == 0, "import_s": round(secs, 3)}
    if rc == 0:
        r["summary"] = out.strip()
    else:
        r["error"] = (err.strip().splitlines() or ["?"])[0][:300]
    return r


def write_md(a, rows, uptime):
    doms = [d for d, _ in DOMAINS]
    imported = [d for d in doms if all(r["imported"] for r in rows if r["domain"] == d)]
    lines = ["# IPC temporal domains through ctburton (bench/pddl_ipc.py)", "",
             "Command: `python3 bench/pddl_ipc.py ROOT --limit %d --instances %d%s%s`" %
             (a.limit, a.instances, " --no-solve" if a.no_solve else "",
              " --solve-instances %d" % a.solve_instances if a.solve_instances else ""),
             "", "`uptime` at the end: `%s`" % uptime, "",
             "Domains whose first %d instances all import: %d of %d." %
             (a.instances, len(imported), len(doms)), "",
             "| domain | inst | imported | import s | status | makespan | verified | first plan s | solve s | note |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        note = r.get("error", r.get("summary", "")).replace("|", "/")
        if "pddl_plan_actions" in r:
            note = "PDDL plan of %d actions written; %s" % (r["pddl_plan_actions"], note)
        first = r.get("first_plan_ms")
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["domain"], r["instance"], "yes" if r["imported"] else "no", r["import_s"],
            r.get("status", ""), r.get("makespan", ""), r.get("verified", ""),
            round(first / 1000, 3) if isinstance(first, (int, float)) and first >= 0 else "",
            r.get("solve_s", ""), note))
    open(a.out + ".md", "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
