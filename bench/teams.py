#!/usr/bin/env python3
"""Teams in the hundreds (issue 29 item 6): search_rescue with N robots, its goal said once with
a quantifier (docs/formats.md, "Quantifiers"), time to the proof with `ctburton solve`.

    python3 bench/teams.py [--bin build/client/ctburton] [--label after] [--sizes 16,64,256,1000]
                           [--forms quantified,written] [--time-limit-ms 60000] [--note TEXT]
                           [--out bench/results]

Problems (bench/gen_scaled.py), makespan, for each N in --sizes:
  "robot k rescues person k": search_rescue_team.json with N robots, robot k's template listing
      only its own person (rescue_team(n, "own")); goal every(k in robot: robot{k}l[i+1]==
      rescuedPerson{k}) ("quantified") or its N conjuncts written out ("written", over 8,192
      characters from N = 256);
  "some robot at each person": N robots, the thesis' two persons (rescue_team(n, 2)); goal
      every(p in 1..2: any(k in robot: robot{k}l[i+1]==rescuedPerson{p})) or written out.
Each runs `ctburton solve` once (bench/scale.py's run: status, objective, bound, first plan,
`solve_ms`, the process's wall time and peak memory; a refused input is an error row with the
message). Results go to bench/results/teams.json under --label (rows of other labels kept) and
bench/results/teams.md is rewritten from every label, under the notes (--notes FILE, kept in the
json).
"""
import argparse
import json
import os
import platform
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gen_scaled  # noqa: E402
import scale  # noqa: E402


def written_some(n, persons):
    plan = gen_scaled.some_robot_each_person_plan(n, persons)
    plan["end_state"]["goal_constraint"] = " /\\ ".join(
        "(" + " \\/ ".join(f"robot{r}l[i+1]==rescuedPerson{p}" for r in range(1, n + 1)) + ")"
        for p in range(1, persons + 1))
    return plan


def problems(tmp, sizes, forms):
    out = []
    for n in sizes:
        own = os.path.join(tmp, f"own{n}.json")
        json.dump(gen_scaled.rescue_team(n), open(own, "w"))
        two = os.path.join(tmp, f"two{n}.json")
        json.dump(gen_scaled.rescue_team(n, 2), open(two, "w"))
        for form in forms:
            p = os.path.join(tmp, f"own{n}_{form}.json")
            json.dump(gen_scaled.rescue_team_plan(n, written_out=form == "written"), open(p, "w"))
            out.append((f"robot k rescues person k, {n} robots, {form}", own, p))
        for form in forms:
            p = os.path.join(tmp, f"two{n}_{form}.json")
            plan = (gen_scaled.some_robot_each_person_plan(n, 2) if form == "quantified"
                    else written_some(n, 2))
            json.dump(plan, open(p, "w"))
            out.append((f"some robot at each of 2 persons, {n} robots, {form}", two, p))
    return out


def reason(error):
    """The first problem of a refusal, without the expanded text it may quote."""
    lines = [x for x in error.splitlines() if x.startswith("/")] or error.splitlines() or [""]
    return lines[0].split(" (offset ")[0][:200].replace("|", "/")


def sec(v):
    return "—" if v is None or v < 0 else f"{v / 1000:.2f}"


def write_md(path, data):
    with open(path, "w") as f:
        f.write("# Teams in the hundreds (issue 29 item 6)\n\n")
        f.write("search_rescue with N robots (bench/gen_scaled.py), makespan, `ctburton solve` "
                "once per row. Seconds: `first` the first verified plan (`stats.first_solution_ms`), "
                "`answer` the end of the solve (`stats.solve_ms`; the proof when optimal), `process` "
                "the whole process (reading and checking the files, the solve, the answer printed). "
                "`quantified`: the goal said once (every/any); `written`: the same goal written out, "
                "one comparison per robot (over 8,192 characters from 256 robots).\n\n")
        f.write(data.get("notes", "") + "\n\n")
        for label, run in data["runs"].items():
            f.write(f"## {label}\n\nMade by `{run['command']}` on {run['machine']}; time limit "
                    f"{run['time_limit_ms']} ms; load average at the start {run.get('load')}. "
                    f"{run.get('note', '')}\n\n")
            f.write("| problem | status | value | bound | first | answer | process | found by | "
                    "proved by | peak MB |\n|---|---|---|---|---|---|---|---|---|---|\n")
            for r in run["rows"]:
                if r["status"] == "error":
                    f.write(f"| {r['problem']} | refused: {reason(r.get('error', ''))} | | | | | "
                            f"{sec(r.get('process_ms'))} | | | {r.get('peak_mb')} |\n")
                    continue
                f.write(f"| {r['problem']} | {r['status']} | {json.dumps(r.get('objective'))} | "
                        f"{json.dumps(r.get('bound'))} | {sec(r.get('first_solution_ms'))} | "
                        f"{sec(r.get('solve_ms'))} | {sec(r.get('process_ms'))} | "
                        f"{r.get('found_by') or '—'} | {r.get('proved_by') or '—'} | "
                        f"{r.get('peak_mb')} |\n")
            f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "client", "ctburton"))
    ap.add_argument("--label", default="after")
    ap.add_argument("--note", default="")
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--sizes", default="16,64,256,1000")
    ap.add_argument("--forms", default="quantified,written")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--notes", help="a markdown file: the notes above the tables (kept otherwise)")
    a = ap.parse_args()
    sizes = [int(x) for x in a.sizes.split(",") if x]
    forms = [x for x in a.forms.split(",") if x]
    load = " ".join(open("/proc/loadavg").read().split()[:3])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, domain, plan in problems(tmp, sizes, forms):
            r = scale.run(a.bin, label, domain, plan, a.time_limit_ms)
            print(json.dumps(r), flush=True)
            rows.append(r)
    os.makedirs(a.out, exist_ok=True)
    jpath = os.path.join(a.out, "teams.json")
    data = json.load(open(jpath)) if os.path.exists(jpath) else {"runs": {}}
    if a.notes:
        data["notes"] = open(a.notes).read().strip()
    data["runs"][a.label] = {"command": "python3 bench/teams.py " + " ".join(sys.argv[1:]),
                             "machine": f"{os.cpu_count()} cores, {platform.platform()}",
                             "time_limit_ms": a.time_limit_ms, "load": load, "note": a.note,
                             "rows": rows}
    with open(jpath, "w") as f:
        json.dump(data, f, indent=1)
    write_md(os.path.join(a.out, "teams.md"), data)


if __name__ == "__main__":
    main()
