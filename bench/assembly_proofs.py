#!/usr/bin/env python3
"""Assembly proofs (issue 18, lever 5): time to prove the makespan optimum of block-stacking plans.

    python3 bench/assembly_proofs.py [--bin build/client/ctburton] [--label after]
                                     [--time-limit-ms 60000] [--only NAME,...] [--note TEXT]
                                     [--out bench/results]

The domain is the assembly domain of ../shared/design/domains.md generalised to any number of
blocks and arms (`assembly(blocks, arms)`; with blocks A, B, C and two arms it is exactly
config/domains/assembly.json, which the script checks). Problems, makespan, every arm home at the
end:
  - "A to the floor, then B on A" (config/examples/assembly/test.json), 3 blocks, 2 arms;
  - reverse a 3-block tower (A on B on C to C on B on A), 2 arms;
  - 4 blocks, 2 and 3 arms: reverse a tower (A on B on C on D to D on C on B on A), swap the
    tops of two towers (A on B, C on D to A on D, C on B), reverse two towers (to B on A, D on C).
Each runs `ctburton solve` once; a row keeps status, value, bound, the first verified plan
(`stats.first_solution_ms`), the answer (`stats.solve_ms`), who found and who proved it, and
peak memory. Results go to bench/results/assembly_proofs.json under --label (rows of other
labels are kept, with the load average before and after the run), and assembly_proofs.md is
rewritten from all labels. Run once with --bin pointing at a build of main (--label before)
and once with this build (--label after).
"""
import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def after(frm, to, secs):
    return {"from": frm, "to": to, "duration": [secs, secs]}


def on(frm, to, guard):
    return {"from": frm, "to": to, "guard": guard}


def assembly(blocks, arms):
    """The assembly domain with these blocks (letters) and this many arms. Picking X needs that no
    other arm is picking or holding X or placing anything onto X; placing onto Y, that no other
    arm is placing onto Y or picking or holding Y (otherwise a block lands on one that is being
    carried away). Arm k's pick and place also need that no arm numbered below k is commanded,
    at that stage, to do what the locations above exclude (pick X or place onto X; place onto Y
    or pick Y): lower numbers have priority."""
    names = [f"arm{k}" for k in range(1, arms + 1)]
    targets = {x: ["Floor"] + [y for y in blocks if y != x] for x in blocks}
    arm_locs = ["home"] + [f"picking{x}" for x in blocks] + [f"holding{x}" for x in blocks]
    arm_locs += [f"placing{x}on{y}" for x in blocks for y in targets[x]]
    arm_cmds = [f"pick{x}" for x in blocks] + [f"place{x}on{y}" for x in blocks for y in targets[x]]
    automata = []
    for k, arm in enumerate(names):
        others = [o for o in names if o != arm]
        ts = []
        for x in blocks:
            parts = [f"{arm}u[i]==pick{x}"]
            parts += [f"block{z}l[i]!=on{x}" for z in blocks if z != x]
            parts += [f"block{x}l[i]!=inArm{j}" for j in range(1, arms + 1)]
            parts += [f"{o}l[i]!={v}" for o in others for v in (f"picking{x}", f"holding{x}")]
            parts += [f"{o}l[i]!=placing{z}on{x}" for o in others for z in blocks if z != x]
            parts += [f"{o}u[i]!=pick{x}" for o in names[:k]]
            parts += [f"{o}u[i]!=place{z}on{x}" for o in names[:k] for z in blocks if z != x]
            ts.append(on("home", f"picking{x}", " /\\ ".join(parts)))
            ts.append(after(f"picking{x}", f"holding{x}", 1))
        for x in blocks:
            for y in targets[x]:
                parts = [f"{arm}u[i]==place{x}on{y}"]
                if y != "Floor":
                    parts += [f"block{z}l[i]!=on{y}" for z in blocks if z != y]
                    parts += [f"block{y}l[i]!=inArm{j}" for j in range(1, arms + 1)]
                    parts += [f"{o}l[i]!=placing{z}on{y}" for o in others for z in blocks if z != y]
                    parts += [f"{o}l[i]!={v}" for o in others for v in (f"picking{y}", f"holding{y}")]
                    parts += [f"{o}u[i]!=place{z}on{y}" for o in names[:k] for z in blocks if z != y]
                    parts += [f"{o}u[i]!=pick{y}" for o in names[:k]]
                ts.append(on(f"holding{x}", f"placing{x}on{y}", " /\\ ".join(parts)))
                ts.append(after(f"placing{x}on{y}", "home", 2))
        automata.append({"name": arm, "locations": arm_locs, "commands": arm_cmds,
                         "transitions": ts})
    for x in blocks:
        rests = ["onFloor"] + [f"on{y}" for y in blocks if y != x]
        ts = []
        for k, arm in enumerate(names, start=1):
            for y in ["Floor"] + [y for y in blocks if y != x]:
                ts.append(on(f"on{y}", f"inArm{k}", f"{arm}l[i]==holding{x}"))
                ts.append(on(f"inArm{k}", f"on{y}", f"{arm}l[i]==placing{x}on{y}"))
        automata.append({"name": f"block{x}",
                         "locations": rests + [f"inArm{k}" for k in range(1, arms + 1)],
                         "commands": [], "transitions": ts})
    return {"name": "assembly",
            "description": f"{arms} arms stack blocks {', '.join(blocks)} on a floor",
            "automata": automata}


def plan(arms, initial, goal):
    """A makespan state plan: blocks from `initial` to `goal` ({block: location}), arms home."""
    init = {f"arm{k}": "home" for k in range(1, arms + 1)}
    init.update({f"block{b}": loc for b, loc in initial.items()})
    parts = [f"arm{k}[i+1]==home" for k in range(1, arms + 1)]
    parts += [f"block{b}[i+1]=={loc}" for b, loc in goal.items()]
    return {"initial_state": init,
            "end_state": {"maintenance_constraint": "true", "goal_constraint": " /\\ ".join(parts)},
            "objective": "makespan"}


TOWER4 = {"A": "onB", "B": "onC", "C": "onD", "D": "onFloor"}
TWO_TOWERS = {"A": "onB", "B": "onFloor", "C": "onD", "D": "onFloor"}


def problems():
    """(name, blocks, arms, state plan or a path to one)."""
    out = [("A to the floor, then B on A (3 blocks)", "ABC", 2,
            os.path.join(ROOT, "config", "examples", "assembly", "test.json")),
           ("reverse a 3-block tower", "ABC", 2,
            plan(2, {"A": "onB", "B": "onC", "C": "onFloor"},
                 {"A": "onFloor", "B": "onA", "C": "onB"}))]
    for arms in (2, 3):
        out.append((f"4 blocks, {arms} arms: reverse a tower", "ABCD", arms,
                    plan(arms, TOWER4, {"A": "onFloor", "B": "onA", "C": "onB", "D": "onC"})))
        out.append((f"4 blocks, {arms} arms: swap the tops of two towers", "ABCD", arms,
                    plan(arms, TWO_TOWERS, {"A": "onD", "B": "onFloor", "C": "onB", "D": "onFloor"})))
        out.append((f"4 blocks, {arms} arms: reverse two towers", "ABCD", arms,
                    plan(arms, TWO_TOWERS, {"A": "onFloor", "B": "onA", "C": "onFloor", "D": "onC"})))
    return out


def load():
    return " ".join(open("/proc/loadavg").read().split()[:3])


def run(binary, domain, state_plan, limit_ms):
    cmd = ["/usr/bin/time", "-f", "%M", binary, "solve", "--domain", domain, state_plan,
           "--objective", "makespan", "--time-limit-ms", str(limit_ms)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_ms / 1000 + 300)
    mem = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "-1"
    row = {"peak_mb": round(int(mem) / 1024, 1) if mem.isdigit() else None}
    if p.returncode != 0:
        row.update(status="error", error=p.stderr.strip()[-300:])
        return row
    t = json.loads(p.stdout)
    s = t["stats"]
    row.update(status=t["status"], objective=t["objective"]["value"], bound=t.get("bound"),
               verified=t["verified"], first_solution_ms=s.get("first_solution_ms"),
               solve_ms=s.get("solve_ms"), found_by=s.get("found_by"),
               proved_by=s.get("proved_by"), solver_runs=s.get("solver_runs"),
               events=t.get("goal_event"))
    return row


def sec(v):
    return "—" if v is None or v < 0 else f"{v / 1000:.2f}"


def write_md(path, data):
    with open(path, "w") as f:
        f.write("# Assembly proofs (issue 18, lever 5: the workload bound)\n\n"
                "Seconds end to end (`ctburton solve --objective makespan`): `first` is the first "
                "verified plan (`stats.first_solution_ms`), `answer` the end of the solve "
                "(`stats.solve_ms`: the proof when the status is optimal). `bound` is the lower "
                "bound a `feasible` answer carries. Targets: the first two rows < 1 s and < 5 s, "
                "the 4-block rows < 30 s. Domain and plans: bench/assembly_proofs.py.\n\n")
        for label, run_ in data["runs"].items():
            f.write(f"## {label}\n\nMade by `{run_['command']}` on {run_['machine']}; time limit "
                    f"{run_['time_limit_ms']} ms; load average {run_['load_before']} before, "
                    f"{run_['load_after']} after. {run_.get('note', '')}\n\n")
            f.write("| problem | status | value | bound | first | answer | found by | proved by | "
                    "peak MB |\n|---|---|---|---|---|---|---|---|---|\n")
            for r in run_["rows"]:
                f.write(f"| {r['problem']} | {r['status']} | {json.dumps(r.get('objective'))} | "
                        f"{json.dumps(r.get('bound'))} | {sec(r.get('first_solution_ms'))} | "
                        f"{sec(r.get('solve_ms'))} | {r.get('found_by') or '—'} | "
                        f"{r.get('proved_by') or '—'} | {r.get('peak_mb')} |\n")
            f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "client", "ctburton"))
    ap.add_argument("--label", default="after")
    ap.add_argument("--note", default="")
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--only", default="", help="comma-separated substrings of problem names")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    shipped = json.load(open(os.path.join(ROOT, "config", "domains", "assembly.json")))
    if assembly("ABC", 2)["automata"] != shipped["automata"]:
        sys.exit("assembly('ABC', 2) differs from config/domains/assembly.json")
    wanted = [w for w in a.only.split(",") if w]
    rows = []
    before = load()
    with tempfile.TemporaryDirectory() as tmp:
        for name, blocks, arms, sp in problems():
            if wanted and not any(w in name for w in wanted):
                continue
            dom = os.path.join(tmp, f"assembly_{blocks}_{arms}.json")
            json.dump(assembly(blocks, arms), open(dom, "w"))
            if isinstance(sp, dict):
                path = os.path.join(tmp, "plan.json")
                json.dump(sp, open(path, "w"))
                sp = path
            r = {"problem": name}
            r.update(run(a.bin, dom, sp, a.time_limit_ms))
            print(json.dumps(r), flush=True)
            rows.append(r)
    os.makedirs(a.out, exist_ok=True)
    jpath = os.path.join(a.out, "assembly_proofs.json")
    data = json.load(open(jpath)) if os.path.exists(jpath) else {"runs": {}}
    data["runs"][a.label] = {"command": "python3 bench/assembly_proofs.py " + shlex.join(sys.argv[1:]),
                             "machine": f"{os.cpu_count()} cores, {platform.platform()}",
                             "time_limit_ms": a.time_limit_ms, "note": a.note,
                             "load_before": before, "load_after": load(), "rows": rows}
    with open(jpath, "w") as f:
        json.dump(data, f, indent=1)
    write_md(os.path.join(a.out, "assembly_proofs.md"), data)


if __name__ == "__main__":
    main()
