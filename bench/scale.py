#!/usr/bin/env python3
"""Planner speed at scale (issue 18): time to the first verified plan and to the proof.

    python3 bench/scale.py [--bin build/client/ctburton] [--label after] [--time-limit-ms 60000]
                           [--sizes 1,2,4,8,12,16,32,64] [--out bench/results]

Problems: search_rescue with N coupled robots (robot k rescues person k; they share the doors;
bench/gen_scaled.py), makespan, for each N in --sizes; assembly "A to the floor, then B on A"
(config/examples/assembly/test.json) and "reverse a 3-block tower" (A on B on C on the floor to
C on B on A on the floor), makespan. Each runs `ctburton solve` once; the row keeps status,
objective, bound, `first_solution_ms` (first verified plan), `solve_ms` (the answer; the proof
when optimal), `found_by` / `proved_by` and peak memory.

Results go to bench/results/scale.json under --label (rows of other labels are kept), and
bench/results/scale.md is rewritten from every label in the json: run once with --bin pointing at
a build of main, or this build with --first-plan-ms 0 (--label before), and once with this build
(--label after). --domain-dir names the directory the assembly domain is read from (main's own
config for "before").
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_domains  # noqa: E402
import gen_scaled  # noqa: E402


def tower_reverse():
    return {"initial_state": {"arm1": "home", "arm2": "home", "blockA": "onB", "blockB": "onC",
                              "blockC": "onFloor"},
            "end_state": {"maintenance_constraint": "true",
                          "goal_constraint": "arm1[i+1]==home /\\ arm2[i+1]==home /\\ "
                                             "blockA[i+1]==onFloor /\\ blockB[i+1]==onA /\\ "
                                             "blockC[i+1]==onB"},
            "objective": "makespan"}


def problems(tmp, sizes, domain_dir):
    out = []
    for n in sizes:
        dom = gen_domains.search_rescue(n)
        dom["name"] = f"search_rescue_r{n}"
        d = os.path.join(tmp, f"rescue{n}.json")
        p = os.path.join(tmp, f"rescue{n}_plan.json")
        json.dump(dom, open(d, "w"))
        json.dump(gen_scaled.rescue_plan(n), open(p, "w"))
        out.append((f"search_rescue, {n} coupled robots", d, p))
    assembly = os.path.join(domain_dir, "assembly.json")
    out.append(("assembly, A to the floor then B on A", assembly,
                os.path.join(ROOT, "config", "examples", "assembly", "test.json")))
    p = os.path.join(tmp, "tower.json")
    json.dump(tower_reverse(), open(p, "w"))
    out.append(("assembly, reverse a 3-block tower", assembly, p))
    return out


def run(binary, label, domain, plan, limit_ms, first_plan_ms=None):
    cmd = ["/usr/bin/time", "-f", "%M", binary, "solve", "--domain", domain, plan, "--objective",
           "makespan", "--time-limit-ms", str(limit_ms)]
    if first_plan_ms is not None:  # 0: the first-plan engine off (the exact path of main)
        cmd += ["--first-plan-ms", str(first_plan_ms)]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 300)
    wall_ms = round((time.monotonic() - t0) * 1000)
    mem = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "-1"
    row = {"problem": label, "peak_mb": round(int(mem) / 1024, 1) if mem.isdigit() else None,
           "process_ms": wall_ms}
    if p.returncode != 0:
        err = p.stderr.strip()  # the head names the problem, the tail how the run ended
        row.update(status="error", error=err if len(err) <= 600 else err[:300] + " ... " + err[-300:])
        return row
    t = json.loads(p.stdout)
    s = t["stats"]
    row.update(status=t["status"], objective=t["objective"]["value"], bound=t.get("bound"),
               verified=t["verified"], first_solution_ms=s.get("first_solution_ms"),
               solve_ms=s.get("solve_ms"), solver=s.get("solver"), found_by=s.get("found_by"),
               proved_by=s.get("proved_by"), solver_runs=s.get("solver_runs"),
               events=t.get("goal_event"), first_plan=s.get("first_plan"))
    return row


def sec(v):
    return "—" if v is None or v < 0 else f"{v / 1000:.2f}"


def write_md(path, data):
    labels = list(data["runs"].keys())
    with open(path, "w") as f:
        f.write("# Planner speed at scale (issue 18)\n\n")
        f.write("Seconds end to end (`ctburton solve`, makespan): `first` is the first verified plan "
                "(`stats.first_solution_ms`), `answer` the end of the solve (`stats.solve_ms`: the "
                "proof when the status is optimal); `process` the whole `ctburton solve` process (start, reading "
                "and checking the files, the solve, the answer printed), where measured.\n\n")
        for label in labels:
            run = data["runs"][label]
            f.write(f"## {label}\n\nMade by `{run['command']}` on {run['machine']}; time limit "
                    f"{run['time_limit_ms']} ms. {run.get('note', '')}\n\n")
            f.write("| problem | status | value | bound | first | answer | process | found by | "
                    "proved by | peak MB |\n|---|---|---|---|---|---|---|---|---|---|\n")
            for r in run["rows"]:
                f.write(f"| {r['problem']} | {r['status']} | {json.dumps(r.get('objective'))} | "
                        f"{json.dumps(r.get('bound'))} | {sec(r.get('first_solution_ms'))} | "
                        f"{sec(r.get('solve_ms'))} | {sec(r.get('process_ms'))} | "
                        f"{r.get('found_by') or '—'} | "
                        f"{r.get('proved_by') or '—'} | {r.get('peak_mb')} |\n")
            f.write("\n")
        coupled = data.get("coupled")
        if coupled:
            f.write("## bench/coupled.py rows, before and after (same machine state)\n\n")
            f.write(coupled.get("note", "") + "\n\n")
            f.write("| problem | objective | before: status, value | first | answer | after: status, "
                    "value | first | answer | found by / proved by |\n|---|---|---|---|---|---|---|---|---|\n")
            for rb, ra in zip(coupled["before"], coupled["after"]):
                f.write(f"| {ra['problem']} | {ra['objective_kind']} | {rb['status']} "
                        f"{json.dumps(rb.get('objective'))} | {sec(rb.get('first_solution_ms'))} | "
                        f"{sec(rb.get('solve_ms'))} | {ra['status']} {json.dumps(ra.get('objective'))} | "
                        f"{sec(ra.get('first_solution_ms'))} | {sec(ra.get('solve_ms'))} | "
                        f"{ra.get('found_by') or '—'} / {ra.get('proved_by') or '—'} |\n")
            f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "client", "ctburton"))
    ap.add_argument("--label", default="after")
    ap.add_argument("--note", default="")
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--sizes", default="1,2,4,8,12,16,32,64")
    ap.add_argument("--domain-dir", default=os.path.join(ROOT, "config", "domains"))
    ap.add_argument("--first-plan-ms", type=int, default=None)
    ap.add_argument("--coupled", nargs=2, metavar=("BEFORE", "AFTER"),
                    help="only record two bench/coupled.py outputs (json lines) for the comparison")
    ap.add_argument("--coupled-note", default="")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    jpath = os.path.join(a.out, "scale.json")
    if a.coupled:
        def lines(path):
            return [json.loads(x) for x in open(path) if x.startswith("{")]
        data = json.load(open(jpath)) if os.path.exists(jpath) else {"runs": {}}
        data["coupled"] = {"note": a.coupled_note, "before": lines(a.coupled[0]),
                           "after": lines(a.coupled[1])}
        json.dump(data, open(jpath, "w"), indent=1)
        write_md(os.path.join(a.out, "scale.md"), data)
        return
    sizes = [int(x) for x in a.sizes.split(",") if x]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, domain, plan in problems(tmp, sizes, a.domain_dir):
            r = run(a.bin, label, domain, plan, a.time_limit_ms, a.first_plan_ms)
            print(json.dumps(r), flush=True)
            rows.append(r)
    os.makedirs(a.out, exist_ok=True)
    data = json.load(open(jpath)) if os.path.exists(jpath) else {"runs": {}}
    data["runs"][a.label] = {"command": "python3 bench/scale.py " + " ".join(sys.argv[1:]),
                             "machine": f"{os.cpu_count()} cores, {platform.platform()}",
                             "time_limit_ms": a.time_limit_ms, "note": a.note, "rows": rows}
    with open(jpath, "w") as f:
        json.dump(data, f, indent=1)
    write_md(os.path.join(a.out, "scale.md"), data)


if __name__ == "__main__":
    main()
