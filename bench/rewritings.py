#!/usr/bin/env python3
"""Equivalent inputs must solve alike (issue 8): the thesis' 4-copy presentation problem (test
prompt 1 per copy, which splits into 4 identical parts) solved in its plain form and with each
rewriting an LLM writes, which before the normalisation pass defeated the split.

    python3 bench/rewritings.py [--copies 4] [--time-limit-ms 60000] [--out bench/results]

Writes bench/results/rewritings.{md,json}: end-to-end time of `ctburton solve --objective cost`,
status, objective, number of parts, and the ratio to the plain form.
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
BIN = os.path.join(ROOT, "build", "client", "ctburton")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gen_scaled  # noqa: E402


def rewritings(plan):
    goal = plan["end_state"]["goal_constraint"]
    out = [("plain", plan)]

    def with_end(maint=None, goal_text=None):
        p = json.loads(json.dumps(plan))
        if maint is not None:
            p["end_state"]["maintenance_constraint"] = maint
        if goal_text is not None:
            p["end_state"]["goal_constraint"] = goal_text
        return p

    out += [("maintenance (true) /\\ (true)", with_end(maint="(true) /\\ (true)")),
            ("maintenance not not true", with_end(maint="not not true")),
            ("maintenance false -> true", with_end(maint="false -> true")),
            ("maintenance true \\/ comp1l[i]==compOff", with_end(maint="true \\/ comp1l[i]==compOff")),
            ("goal not not (G)", with_end(goal_text=f"not not ({goal})")),
            ("goal true -> (G)", with_end(goal_text=f"true -> ({goal})")),
            ("goal (G) \\/ false", with_end(goal_text=f"({goal}) \\/ false"))]
    # A state constraint with a tautology over another automaton.
    p = json.loads(json.dumps(plan))
    name = sorted(p["constraints"]["episodes"])[0]
    ep = p["constraints"]["episodes"][name]
    ep["state_constraint"] = f"({ep['state_constraint']}) /\\ (comp2l[i]==compOn \\/ comp2l[i]!=compOn)"
    out.append(("state constraint with a tautology over another copy", p))
    return out


def run(domain, plan_path, limit_ms):
    t0 = time.monotonic()
    p = subprocess.run([BIN, "solve", "--domain", domain, plan_path, "--objective", "cost",
                        "--time-limit-ms", str(limit_ms)], capture_output=True, text=True,
                       timeout=limit_ms / 1000 + 60)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        return {"status": "error", "error": p.stderr.strip()[-300:], "seconds": round(wall, 2)}
    t = json.loads(p.stdout)
    return {"status": t["status"], "objective": t["objective"]["value"],
            "parts": t["stats"].get("parts", 1), "seconds": round(wall, 2)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--copies", type=int, default=4)
    ap.add_argument("--time-limit-ms", type=int, default=60000)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        gen_scaled.main(tmp)
        domain = os.path.join(tmp, f"presentation_x{a.copies}.json")
        plan = json.load(open(os.path.join(tmp, f"presentation_x{a.copies}_plan.json")))
        rows = []
        for label, p in rewritings(plan):
            path = os.path.join(tmp, "plan.json")
            json.dump(p, open(path, "w"))
            r = run(domain, path, a.time_limit_ms)
            r["form"] = label
            rows.append(r)
            print(label, r, flush=True)
    plain = rows[0]["seconds"]
    for r in rows:
        r["ratio"] = round(r["seconds"] / plain, 2) if plain else None
    os.makedirs(a.out, exist_ok=True)
    cmd = "python3 bench/rewritings.py " + " ".join(sys.argv[1:])
    json.dump({"command": cmd, "rows": rows}, open(os.path.join(a.out, "rewritings.json"), "w"),
              indent=1)
    with open(os.path.join(a.out, "rewritings.md"), "w") as f:
        f.write("# Equivalent inputs solve alike (issue 8)\n\n")
        f.write(f"Made by `{cmd}` on {os.cpu_count()} cores, {platform.platform()}; "
                f"presentation with {a.copies} copies (thesis test prompt 1 per copy), objective "
                f"`cost`, time limit {a.time_limit_ms} ms. Seconds are end to end (`ctburton "
                f"solve`).\n\n")
        f.write("| form | status | objective | parts | seconds | × plain |\n|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['form']} | {r['status']} | {r.get('objective', '')} | "
                    f"{r.get('parts', '')} | {r['seconds']:.2f} | {r['ratio']} |\n")


if __name__ == "__main__":
    main()
