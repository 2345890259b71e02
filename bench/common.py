"""What the benchmark scripts share: where the build is, a free loopback port, percentiles, one
makespan solve through the CLI."""
import json
import os
import socket
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "client", "ctburton")


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    p = s.getsockname()[1]
    s.close()
    return p


def pct(xs, p):
    """The p-th percentile of xs (nearest rank)."""
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(p / 100 * (len(xs) - 1))))]


def solve_makespan(binary, dom, sp, limit_ms):
    """`ctburton solve --objective makespan` on two files: status, makespan, bound, verified, the
    first plan and the answer in seconds, who found and who proved it (or status "error")."""
    p = subprocess.run([binary, "solve", "--domain", dom, sp, "--objective", "makespan",
                        "--time-limit-ms", str(limit_ms)], capture_output=True, text=True,
                       timeout=limit_ms / 1000 + 120)
    if p.returncode != 0:
        return {"status": "error", "error": p.stderr.strip()[-200:]}
    t = json.loads(p.stdout)
    s = t["stats"]
    return {"status": t["status"], "makespan": (t.get("objective") or {}).get("value"),
            "bound": t.get("bound"), "verified": t.get("verified"),
            "first_s": round(s.get("first_solution_ms", -1) / 1000, 2),
            "answer_s": round(s.get("solve_ms", -1) / 1000, 2),
            "found_by": s.get("found_by"), "proved_by": s.get("proved_by")}
