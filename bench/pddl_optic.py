#!/usr/bin/env python3
"""The IPC temporal domains of bench/pddl_ipc.py through OPTIC, a PDDL 2.1 temporal planner, to
sit beside ctburton's own results (bench/results/pddl_ipc.md): per domain, the first N instances,
each one OPTIC run under a wall-clock limit.

OPTIC is anytime: it prints a plan, then better ones (by the problem's metric, by makespan when
there is none), and when its search ends by itself it prints the best plan once more under
";;;; Solution Found" (or ";; Problem unsolvable!" when it found none). At the limit the whole
process group is killed. Per instance: solved (a plan printed), seconds to the first plan (wall
clock, as the line arrived), makespan (max of start + duration) of the first and of the last
plan, the number of plans, how the run ended (search_ended: OPTIC's search ran out by itself, so
no better plan in its search space; limit: cut at the limit; unsolvable; error) and any error in
one line (parse error, unsupported feature, crash).

OPTIC is public code written by others and is not committed: build it outside the repo and pass
the binary. Its origin (repo and commit) is read from --origin, else from a file OPTIC_ORIGIN in
the binary's folder or one of its parents. The competition files are laid out as for
bench/pddl_ipc.py. Runs are one at a time.

  python3 bench/pddl_optic.py /tmp/ipc --optic /tmp/optic-build/optic/optic-clp --limit 30 --instances 3
"""
import argparse
import json
import os
import re
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

from pddl_ipc import DOMAINS, domain_file

HERE = os.path.dirname(os.path.abspath(__file__))
STEP = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*:\s*(\(.*\))\s*\[\s*(\d+(?:\.\d+)?)\s*\]\s*$")


def origin_of(binary, given):
    if given:
        return given
    d = os.path.dirname(os.path.abspath(binary))
    while True:
        f = os.path.join(d, "OPTIC_ORIGIN")
        if os.path.exists(f):
            return open(f).read().strip()
        if os.path.dirname(d) == d:
            return "unknown"
        d = os.path.dirname(d)


def run_optic(cmd, limit, mem_mb, cwd):
    """Run cmd in its own process group; kill the group at `limit` seconds. Returns
    (returncode or None when cut, [(seconds, stdout line)], stderr text, seconds, CPU seconds)."""
    def lim():
        if mem_mb:
            b = mem_mb * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (b, b))
    env = dict(os.environ, GCOV_PREFIX=cwd)  # a build with -fprofile-arcs writes .gcda here
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd, env=env,
                         start_new_session=True, preexec_fn=lim)
    lines, err = [], []

    def read_out():
        for raw in p.stdout:
            lines.append((time.monotonic() - t0, raw.decode("utf-8", "replace").rstrip("\n")))

    def read_err():
        err.append(p.stderr.read().decode("utf-8", "replace"))
    ts = [threading.Thread(target=read_out), threading.Thread(target=read_err)]
    for t in ts:
        t.start()
    cut = False
    try:
        p.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        cut = True
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        p.wait()
    secs = time.monotonic() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime
    for t in ts:
        t.join(10)
    return (None if cut else p.returncode), lines, "".join(err), secs, cpu


def parse(lines):
    """The plans OPTIC printed: [{"t": seconds, "metric", "cpu_s", "steps": [(start, act, dur)]}],
    plus the final block (";;;; Solution Found"), if any, and whether it said unsolvable."""
    plans, final, cur, unsolvable = [], None, None, False
    for t, ln in lines:
        if ln.startswith("; Plan found with metric"):
            cur = {"t": t, "metric": ln.split()[-1], "steps": []}
            plans.append(cur)
        elif ln.startswith(";;;; Solution Found") or ln.startswith(";;;; Post-hoc"):
            cur = {"t": t, "steps": []}
            final = cur
        elif ln.startswith(";; Problem unsolvable"):
            unsolvable, cur = True, None
        elif cur is not None and ln.startswith("; Cost:"):
            cur["metric"] = ln.split()[-1]
        elif cur is not None and ln.startswith("; Time "):
            cur["cpu_s"] = float(ln.split()[-1])
        elif cur is not None:
            m = STEP.match(ln)
            if m:
                cur["steps"].append((float(m.group(1)), m.group(2), float(m.group(3))))
    return plans, final, unsolvable


def makespan(plan):
    return round(max((s + d for s, _, d in plan["steps"]), default=0.0), 3)


def one_line(text, n=300):
    keep = [l.strip() for l in text.splitlines()
            if l.strip() and not set(l.strip()) <= set("-=*")]
    return " ".join(keep[:1])[:n]


DETAIL = re.compile(r"Type problem|Warning:|Error:|error|not supported|unsupported|cannot|fail"
                    r"|terminate called|what\(\)", re.I)


def detail(lines, err):
    """The first line of stdout or stderr that says what went wrong (OPTIC prints a title on
    stderr and the particulars, e.g. the type-checking log or the parser's warnings, on stdout)."""
    for ln in [l for _, l in lines] + err.splitlines():
        ln = ln.strip()
        if DETAIL.search(ln) and not ln.startswith("Errors: 0") and "passes" not in ln:
            return ln
    return ""


def say(*parts, n=300):
    return ": ".join(p for p in parts if p)[:n]


def one(binary, folder, k, limit, mem_mb, tmp):
    dom, prob = domain_file(folder, k), os.path.join(folder, "instances", "instance-%d.pddl" % k)
    r = {"instance": k}
    if not (os.path.exists(dom) and os.path.exists(prob)):
        r.update(solved=False, ended="error", error="missing %s" % (prob if os.path.exists(dom)
                                                                     else dom))
        return r
    load = os.getloadavg()[0]
    rc, lines, err, secs, cpu = run_optic([binary, dom, prob], limit, mem_mb, tmp)
    plans, final, unsolvable = parse(lines)
    if not plans and final is not None:  # no anytime output (e.g. no optimisation): one plan
        plans = [final]
    r["wall_s"] = round(secs, 2)
    r["cpu_s"] = round(cpu, 2)  # OPTIC's CPU seconds: below wall_s when the cores were shared
    r["load1_before"] = round(load, 2)
    r["solved"] = bool(plans)
    r["plans"] = len(plans)
    if plans:
        r["first_plan_s"] = round(plans[0]["t"], 3)
        r["first_plan_cpu_s"] = plans[0].get("cpu_s")
        r["first_makespan"] = makespan(plans[0])
        r["last_makespan"] = makespan(plans[-1])
        r["first_metric"] = plans[0].get("metric")
        r["last_metric"] = plans[-1].get("metric")
        r["last_steps"] = len(plans[-1]["steps"])
    if rc is None:
        r["ended"] = "limit"
    elif rc == 0 and final is not None:
        r["ended"] = "search_ended"
    elif unsolvable:
        r["ended"] = "unsolvable"
        r["error"] = say("OPTIC: problem unsolvable", one_line(err), detail(lines, err))
    else:
        r["ended"] = "error"
        why = ("killed by %s" % signal.Signals(-rc).name) if rc < 0 else "exit %d" % rc
        r["error"] = say(why, one_line(err), detail(lines, err)
                         or one_line("\n".join(l for _, l in lines[-1:])))
    if "error" not in r and err.strip():
        r["warning"] = say(one_line(err), detail(lines, err))
    return r


def median(xs):
    return round(statistics.median(xs), 3) if xs else None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("root", help="the IPC folder (layout as for bench/pddl_ipc.py)")
    ap.add_argument("--optic", required=True, help="the OPTIC binary (optic-clp)")
    ap.add_argument("--limit", type=int, default=30, help="seconds per run (wall clock)")
    ap.add_argument("--instances", type=int, default=3)
    ap.add_argument("--mem-mb", type=int, default=8192, help="address-space limit per run")
    ap.add_argument("--origin", default=None, help="where the binary came from (repo, commit)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "pddl_optic"),
                    help="write OUT.json and OUT.md")
    a = ap.parse_args()
    binary = os.path.abspath(a.optic)
    origin = origin_of(binary, a.origin)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, sub in DOMAINS:
            folder = os.path.join(a.root, sub)
            for k in range(1, a.instances + 1):
                r = one(binary, folder, k, a.limit, a.mem_mb, tmp)
                r["domain"] = label
                rows.append(r)
                print(json.dumps(r), flush=True)
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    command = "python3 bench/pddl_optic.py %s --optic %s --limit %d --instances %d%s" % (
        a.root, a.optic, a.limit, a.instances,
        "" if a.mem_mb == 8192 else " --mem-mb %d" % a.mem_mb)
    summary = summarise(rows)
    json.dump({"command": command, "optic": origin, "binary": binary, "uptime": uptime,
               "limit_s": a.limit, "summary": summary, "rows": rows},
              open(a.out + ".json", "w"), indent=1)
    write_md(a.out, command, origin, uptime, rows, summary, a.instances)


def summarise(rows):
    out = []
    for label, _ in DOMAINS:
        rs = [r for r in rows if r["domain"] == label]
        solved = [r for r in rs if r["solved"]]
        out.append({"domain": label, "instances": len(rs), "solved": len(solved),
                    "search_ended": sum(r["ended"] == "search_ended" for r in rs),
                    "median_first_plan_s": median([r["first_plan_s"] for r in solved]),
                    "errors": sum(r["ended"] in ("error", "unsolvable") for r in rs)})
    return out


def write_md(out, command, origin, uptime, rows, summary, n):
    solved_doms = sum(s["solved"] > 0 for s in summary)
    lines = ["# IPC temporal domains through OPTIC (bench/pddl_optic.py)", "",
             "Command: `%s`" % command, "", "OPTIC: %s" % origin, "",
             "`uptime` at the end: `%s`" % uptime, "",
             "Instances solved (a plan printed): %d of %d; domains with at least one: %d of %d." %
             (sum(s["solved"] for s in summary), len(rows), solved_doms, len(summary)), "",
             "`ended`: search_ended = OPTIC's search ran out by itself (no better plan in its "
             "search space), limit = killed at the limit, unsolvable = OPTIC said so, "
             "error = exit without a plan. First plan: wall-clock seconds to the line. cpu s: "
             "OPTIC's CPU seconds (less than wall s when the two cores were shared).", "",
             "## Per domain (first %d instances)" % n, "",
             "| domain | solved | search ended | median s to first plan | errors |",
             "| --- | --- | --- | --- | --- |"]
    for s in summary:
        lines.append("| %s | %d/%d | %d | %s | %d |" % (
            s["domain"], s["solved"], s["instances"], s["search_ended"],
            "" if s["median_first_plan_s"] is None else s["median_first_plan_s"], s["errors"]))
    lines += ["", "## Per instance", "",
              "| domain | inst | solved | s to first plan | first makespan | last makespan | "
              "plans | ended | wall s | cpu s | error (or warning) |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["domain"], r["instance"], "yes" if r["solved"] else "no",
            r.get("first_plan_s", ""), r.get("first_makespan", ""), r.get("last_makespan", ""),
            r.get("plans", ""), r["ended"], r.get("wall_s", ""), r.get("cpu_s", ""),
            (r.get("error") or ("(warning) " + r["warning"] if r.get("warning") else ""))
            .replace("|", "/")))
    open(out + ".md", "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
