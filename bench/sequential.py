#!/usr/bin/env python3
"""Sequential small solves on one keep-alive connection (issue 31 item 7): p99 under 3x p50.

    python3 bench/sequential.py [--requests 200] [--rounds 3] [--out bench/results]

Starts `build/client/ctburton serve` on a free loopback port (its defaults), then sends the
presentation example (config/examples/presentation/test1_cot.json) as `POST /solve` N times in a
row on one HTTP/1.1 keep-alive connection, `rounds` times (a fresh server each). Per request: the
client's latency and the core's time (`Server-Timing: core;dur=`). Writes
bench/results/sequential.{md,json}: per round p50, p90, p99, max and the ratio p99/p50 of both.
Before the fix of the core's job wait (commit 21562a3) about 18 % of these requests took 103 to
110 ms (a 100 ms poll missed the wake-up).
"""
import argparse
import http.client
import json
import os
import re
import subprocess
import time

from common import BIN, ROOT, free_port, pct  # noqa: E402 (bench/common.py)

PLAN = os.path.join(ROOT, "config", "examples", "presentation", "test1_cot.json")


def start_server():
    port = free_port()
    env = dict(os.environ, CTB_CONFIG_DIR=os.path.join(ROOT, "config"))
    data = f"/tmp/ctb-sequential-{os.getpid()}-{port}"
    srv = subprocess.Popen([BIN, "serve", "--port", str(port), "--data-dir", data], cwd=ROOT, env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(400):
        try:
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=2)
            c.request("GET", "/healthz")
            if c.getresponse().status == 200:
                return srv, port
        except OSError:
            time.sleep(0.025)
    srv.kill()
    raise SystemExit("server did not start")


def one_round(n):
    srv, port = start_server()
    body = json.dumps({"domain": "presentation", "state_plan": json.load(open(PLAN))})
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    client_ms, core_ms, statuses = [], [], {}
    try:
        for _ in range(n):
            t0 = time.perf_counter()
            conn.request("POST", "/solve", body, {"Content-Type": "application/json"})
            r = conn.getresponse()
            r.read()
            client_ms.append((time.perf_counter() - t0) * 1000)
            statuses[r.status] = statuses.get(r.status, 0) + 1
            m = re.search(r"core;dur=([0-9.]+)", r.getheader("Server-Timing") or "")
            if m:
                core_ms.append(float(m.group(1)))
    finally:
        conn.close()
        srv.terminate()
        srv.wait(timeout=30)
    return client_ms, core_ms, statuses


def summary(xs):
    p50 = pct(xs, 50)
    return {"p50": round(p50, 2), "p90": round(pct(xs, 90), 2), "p99": round(pct(xs, 99), 2),
            "max": round(max(xs), 2), "p99_over_p50": round(pct(xs, 99) / p50, 2) if p50 > 0 else None,
            "over_100ms": sum(1 for x in xs if x >= 100)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--requests", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    rounds = []
    for i in range(a.rounds):
        client, core, statuses = one_round(a.requests)
        rounds.append({"round": i + 1, "statuses": statuses, "client_ms": summary(client),
                       "core_ms": summary(core) if core else None})
    load = open("/proc/loadavg").read().split()[:3]
    git = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                         text=True).stdout.strip()
    result = {"command": f"python3 bench/sequential.py --requests {a.requests} --rounds {a.rounds}",
              "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "git": git, "loadavg": load,
              "rounds": rounds}
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "sequential.json"), "w") as f:
        json.dump(result, f, indent=1)
    lines = ["# Sequential small solves on one keep-alive connection (issue 31 item 7)", "",
             f"Command: `{result['command']}` at git {git}, {result['date']}; load average at the end "
             f"{' / '.join(load)} (shared 2-core machine). Each round: a fresh `ctburton serve` (defaults), "
             f"{a.requests} `POST /solve` of the presentation example in a row on one keep-alive connection.",
             "", "| round | statuses | client p50 ms | p90 | p99 | max | p99/p50 | ≥ 100 ms | core p50 ms | core p99 | core p99/p50 |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rounds:
        c, k = r["client_ms"], r["core_ms"] or {}
        lines.append(f"| {r['round']} | {r['statuses']} | {c['p50']} | {c['p90']} | {c['p99']} | {c['max']} | "
                     f"{c['p99_over_p50']} | {c['over_100ms']} | {k.get('p50', '')} | {k.get('p99', '')} | "
                     f"{k.get('p99_over_p50', '')} |")
    ok = all(r["client_ms"]["p99_over_p50"] is not None and r["client_ms"]["p99_over_p50"] < 3 for r in rounds)
    lines += ["", f"Target p99 < 3 × p50 (client latency): {'met in every round' if ok else 'NOT met'}.", ""]
    with open(os.path.join(a.out, "sequential.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
