#!/usr/bin/env python3
"""Impossible requests, end to end (issue 20): how long `ctburton solve` takes to prove each one
infeasible and to explain it, and whether each relaxation it proposes works.

Usage:
  python3 bench/impossible.py [--exe build/client/ctburton] [--label after] [--routes]
                              [--before bench/results/impossible_before.json]
                              [--out bench/results/impossible]

For each case one `ctburton solve --max-horizon 32 --time-limit-ms 60000` is run (a fresh process,
as a user would): `prove` is the answer's `stats.solve_ms` (static analysis or solver), `explain`
the explanation's own `stats.ms`, `wall` the whole command (loading, proof, explanation,
restatement). Then every relaxation of the explanation is applied to the state plan and solved
again (`works`: how many of them give a plan). `--before` adds the columns of an earlier run (the
same script with the binary of main before the change) to the table.
"""
import argparse
import copy
import json
import os
import platform
import subprocess
import tempfile
import time

CASES = [
    ("presentation", "config/examples/presentation/impossible_off_within59.json",
     "off within 59 s of leaving projOn (cool-down 60 s)"),
    ("presentation", "config/examples/presentation/impossible_on1800_off1500.json",
     "on for exactly 1800 s, off within 1500 s of warming up"),
    ("search_rescue", "config/examples/search_rescue/impossible_door_shut_deadline.json",
     "door 1 kept shut, person 1 rescued within 12 s"),
    ("presentation", "tests/data/deadline_infeasible.json", "deadline below the warm-up"),
    ("presentation", "config/examples/presentation/test2_direct.json", "thesis direct answer, prompt 2"),
    ("presentation", "tests/data/explain/deadline_boot.json", "deadline below the boot time"),
    ("presentation", "tests/data/explain/change_not_allowed.json", "a change no transition allows"),
    ("search_rescue", "tests/data/explain/unreachable.json", "an unreachable location"),
    ("presentation", "tests/data/explain/overlap.json", "two episodes that overlap impossibly"),
    ("presentation", "tests/data/explain/maintenance_blocks.json", "maintenance blocks the only route"),
    ("presentation", "tests/data/explain/three_together.json", "three constraints, only together"),
    # Beyond the time network (it refutes the projector deadline below 45 s; 75 s are needed):
    # the solver must prove it.
    ("presentation", "tests/data/explain/three_together_60.json",
     "three constraints, only together, projector within 60 s"),
]


def drop(sp, pointer):
    t = pointer.strip("/").split("/")
    if t[0] == "end_state":
        sp["end_state"][t[1]] = "true"
        return
    group = sp["constraints"][t[1]]
    group.pop(t[2], None)
    if t[1] == "event":
        return
    kinds = ("start", "end") if t[1] == "episodes" else ("event1", "event2")
    events = sp["constraints"].get("event", {})
    for name in list(events):
        events[name] = [e for e in events[name] if e not in (t[2] + "." + k for k in kinds)]
        if len(events[name]) < 2:
            del events[name]


def apply(sp, changes):
    sp = copy.deepcopy(sp)
    for c in changes:
        if c["value"] is None:
            drop(sp, c["pointer"])
        else:
            t = c["pointer"].strip("/").split("/")
            sp["constraints"][t[1]][t[2]][t[3]] = c["value"]
    return sp


def solve(exe, dom, path, extra=()):
    t0 = time.time()
    out = subprocess.run([exe, "solve", "--domain", dom, path, "--max-horizon", "32",
                          "--time-limit-ms", "60000", *extra], capture_output=True, text=True)
    wall = int((time.time() - t0) * 1000)
    try:
        return json.loads(out.stdout), wall
    except json.JSONDecodeError:
        return {"status": "error", "error": out.stderr.strip()[:200]}, wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default="build/client/ctburton")
    ap.add_argument("--label", default="after")
    ap.add_argument("--before")
    ap.add_argument("--out", default="bench/results/impossible")
    ap.add_argument("--no-check", action="store_true", help="do not solve the relaxations")
    ap.add_argument("--routes", action="store_true",
                    help="time each solver route on the cases static analysis leaves to a solver")
    a = ap.parse_args()
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.chdir(src)
    rows = []
    for dom, f, what in CASES:
        t, wall = solve(a.exe, dom, f)
        ex = t.get("explanation", {})
        conflict = ex["conflicts"][0]["constraints"] if ex.get("conflicts") else []
        relax = ex.get("relaxations", [])
        works = None
        if not a.no_check and relax:
            works = 0
            sp = json.load(open(f))
            for r in relax:
                with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
                    json.dump(apply(sp, r["changes"]), tmp)
                rt, _ = solve(a.exe, dom, tmp.name)
                os.unlink(tmp.name)
                works += rt.get("status") in ("optimal", "feasible")
        rows.append({"case": what, "file": f, "status": t.get("status"),
                     "infeasible_for": t.get("infeasible_for"),
                     "prove_ms": t.get("stats", {}).get("solve_ms"), "solver": t.get("stats", {}).get("solver"),
                     "explain_ms": ex.get("stats", {}).get("ms"),
                     "explain_calls": ex.get("stats", {}).get("solver_calls"),
                     "conflict_by": ex.get("stats", {}).get("conflict_by"),
                     "conflict_ms": ex.get("stats", {}).get("conflict_ms"),
                     "explanation": ex.get("status"), "conflict": conflict,
                     "relaxations": [r["text"] for r in relax], "relaxations_work": works,
                     "wall_ms": wall})
    routes = []
    if a.routes:
        for r, (dom, f, what) in zip(rows, CASES):
            if r["infeasible_for"] == "any_horizon":
                continue
            for extra in (["--search", "g_first"], ["--search", "portfolio"],
                          ["--search", "portfolio", "--portfolio", "3"], ["--search", "z3"]):
                t, wall = solve(a.exe, dom, f, extra)
                routes.append({"case": what, "route": " ".join(extra), "status": t.get("status"),
                               "prove_ms": t.get("stats", {}).get("solve_ms")})
    before = {}
    if a.before:
        for r in json.load(open(a.before))["rows"]:
            before[r["file"]] = r
    load = os.getloadavg()
    doc = {"label": a.label, "machine": platform.platform(), "cores": os.cpu_count(),
           "load": [round(x, 1) for x in load], "rows": rows, "routes": routes}
    with open(a.out + ".json", "w") as fh:
        json.dump(doc, fh, indent=1)
    lines = [
        "# Impossible requests: proof and explanation times (issue 20)",
        "",
        f"Made by `python3 bench/impossible.py{' --before ' + a.before if a.before else ''}` "
        f"on {os.cpu_count()} cores, {platform.platform()}. Load average at the end: "
        f"{load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (other engineers' builds and tests share the "
        "cores). Each case is one `ctburton solve --max-horizon 32 --time-limit-ms 60000` process.",
        "",
        "`prove`: the answer's `stats.solve_ms` (static analysis or the solver); `explain`: the "
        "explanation's `stats.ms`; `wall`: the whole command, both included. `works`: how many of "
        "the proposed relaxations, applied and solved again, give a plan. `conflict by`: what "
        "found the conflict (`stats.conflict_by`) and when (`stats.conflict_ms`; the rest of "
        "`explain` is the relaxations). Times in ms.",
        "",
    ]
    head = ("| case | status | infeasible_for | prove | explain | conflict by | wall | works "
            "| conflict |")
    sep = "|---|---|---|---|---|---|---|---|---|"
    if before:
        head = "| case | before: status | before: prove | before: explain | before: wall " + head[6:]
        sep = "|---|---|---|---|---" + sep[4:]
    lines += [head, sep]
    for r in rows:
        rel = r["relaxations_work"]
        works = "-" if rel is None else f"{rel}/{len(r['relaxations'])}"
        cells = [f"{r['case']} (`{r['file']}`)"]
        if before:
            b = before.get(r["file"], {})
            cells += [str(b.get("status")), str(b.get("prove_ms")), str(b.get("explain_ms")), str(b.get("wall_ms"))]
        by = f"{r.get('conflict_by')} ({r.get('conflict_ms')})" if r.get("conflict_by") else "-"
        cells += [str(r["status"]), str(r["infeasible_for"]), str(r["prove_ms"]), str(r["explain_ms"]),
                  by, str(r["wall_ms"]), works, ", ".join(f"`{p}`" for p in r["conflict"])]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "Relaxations proposed:", ""]
    for r in rows:
        lines.append(f"- {r['case']}: " + ("; ".join(r["relaxations"]) or "none"))
    if routes:
        lines += ["", "Solver routes on the cases static analysis leaves to a solver (`--routes`; "
                  "`prove` = `stats.solve_ms` of the whole solve, explanation included in neither):", "",
                  "| case | route | status | prove |", "|---|---|---|---|"]
        for r in routes:
            lines.append(f"| {r['case']} | `{r['route']}` | {r['status']} | {r['prove_ms']} |")
    with open(a.out + ".md", "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
