#!/usr/bin/python3
"""HTTP and gRPC overhead over the core (issue 19): the same small solves through both front ends
of one `ctburton serve --grpc-port`, from 1 and 16 concurrent clients.

    /usr/bin/python3 bench/bench_grpc.py [--requests N] [--out bench/results]

(Debian's python3, which has python3-grpcio; stubs are generated with protoc and
grpc_python_plugin into a temporary directory.) Two requests: a state plan whose infeasibility
the static analysis proves in well under a millisecond (so the latency is nearly all front end
and core), and the presentation test prompt 1 plan (objective cost, a ~0.4 s solve). Overhead per
request = the client's latency minus the time the call spent in the core (checks, job gate,
planner, summary, explanation), which HTTP reports as `Server-Timing: core;dur=MS` and gRPC as
`metrics["core_ms"]`. The server runs
with 2 solver workers and a queue of 32, so at 16 clients requests wait for a slot: that wait is
in the overhead at 16 clients and is the same for both front ends.
"""
import argparse
import http.client
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

from common import BIN, ROOT, free_port, pct  # noqa: E402 (bench/common.py)
PLANS = {
    "static proof (infeasible)": os.path.join(ROOT, "tests", "data", "deadline_infeasible.json"),
    "test prompt 1, cost": os.path.join(ROOT, "config", "examples", "presentation", "test1_cot.json"),
}


def stubs(tmp):
    subprocess.run(["protoc", "-I", os.path.join(ROOT, "proto"), f"--python_out={tmp}",
                    f"--grpc_out={tmp}",
                    "--plugin=protoc-gen-grpc=" + subprocess.check_output(
                        ["sh", "-c", "command -v grpc_python_plugin"], text=True).strip(),
                    os.path.join(ROOT, "proto", "ctburton", "v1", "planner.proto")], check=True)
    sys.path.insert(0, tmp)


def run_level(call, clients, requests):
    lat, over, errors = [], [], 0
    lock = threading.Lock()
    todo = list(range(requests))

    def worker():
        nonlocal errors
        send = call()
        while True:
            with lock:
                if not todo:
                    return
                todo.pop()
            t0 = time.perf_counter()
            ok, solve_ms = send()
            ms = (time.perf_counter() - t0) * 1000
            with lock:
                if not ok:
                    errors += 1
                    continue
                lat.append(ms)
                over.append(ms - solve_ms)

    t0 = time.perf_counter()
    threads = [threading.Thread(target=worker) for _ in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.perf_counter() - t0
    return {"clients": clients, "requests": requests, "errors": errors,
            "throughput": round(len(lat) / wall, 2),
            "p50_ms": round(pct(lat, 50), 1), "p99_ms": round(pct(lat, 99), 1),
            "overhead_p50_ms": round(pct(over, 50), 1), "overhead_p99_ms": round(pct(over, 99), 1)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--requests", type=int, default=48)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    stubs(tmp)
    import grpc
    from google.protobuf import json_format
    from ctburton.v1 import planner_pb2, planner_pb2_grpc

    port, gport = free_port(), free_port()
    cfg = os.path.join(tmp, "cfg.json")
    json.dump({"solver_queue": 32, "max_connections_per_address": 64}, open(cfg, "w"))
    env = dict(os.environ, CTB_CONFIG_DIR=os.path.join(ROOT, "config"), CTB_DATA_DIR=tmp)
    srv = subprocess.Popen([BIN, "serve", "--port", str(port), "--grpc-port", str(gport),
                            "--config", cfg], cwd=ROOT, env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    grpc.channel_ready_future(grpc.insecure_channel(f"127.0.0.1:{gport}")).result(timeout=30)
    rows = []
    try:
        for name, path in PLANS.items():
            plan = json.load(open(path))
            body = json.dumps({"domain": "presentation", "state_plan": plan,
                               "options": {"objective": "cost"}})
            req = planner_pb2.SolveRequest(
                domain="presentation", state_plan=json_format.ParseDict(plan, planner_pb2.StatePlan()),
                options=planner_pb2.Options(objective="cost"))

            def http_call():
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)

                def send():
                    conn.request("POST", "/solve", body, {"Content-Type": "application/json"})
                    r = conn.getresponse()
                    data = r.read()
                    if r.status != 200:
                        return False, 0
                    timing = r.getheader("Server-Timing", "core;dur=0")
                    return True, float(timing.split("dur=")[1])
                return send

            def grpc_call():
                stub = planner_pb2_grpc.PlannerStub(grpc.insecure_channel(f"127.0.0.1:{gport}"))

                def send():
                    try:
                        r = stub.Solve(req, timeout=120)
                    except grpc.RpcError:
                        return False, 0
                    return True, float(r.metrics["core_ms"])
                return send

            for clients in (1, 16):
                for front, call in (("HTTP", http_call), ("gRPC", grpc_call)):
                    run_level(call, clients, 4)  # warm-up
                    r = run_level(call, clients, a.requests)
                    r.update({"request": name, "front_end": front})
                    rows.append(r)
                    print(r, flush=True)
    finally:
        srv.terminate()
        srv.wait(timeout=30)
    os.makedirs(a.out, exist_ok=True)
    json.dump(rows, open(os.path.join(a.out, "grpc_http.json"), "w"), indent=1)
    with open(os.path.join(a.out, "grpc_http.md"), "w") as f:
        f.write("# HTTP and gRPC overhead over the core (issue 19)\n\n")
        f.write(f"Made by `/usr/bin/python3 bench/bench_grpc.py --requests {a.requests}` on this "
                "2-core machine: one `ctburton serve --grpc-port` (2 solver workers, queue 32), "
                "`POST /solve` (http.client, keep-alive) against `Planner/Solve` (python3-grpcio, "
                "one channel per client). Overhead = client latency minus the time the call "
                "spent in the core (HTTP `Server-Timing: core;dur`, gRPC `metrics[\"core_ms\"]`): "
                "parsing, conversion to JSON or protobuf, the transport, and the client library. "
                "At 16 clients the core time includes the wait for one of the 2 solver slots, so "
                "the overhead stays the front end's own.\n\n")
        f.write("| request | clients | front end | errors | req/s | p50 ms | p99 ms | overhead p50 ms | overhead p99 ms |\n")
        f.write("|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['request']} | {r['clients']} | {r['front_end']} | {r['errors']} | "
                    f"{r['throughput']} | {r['p50_ms']} | {r['p99_ms']} | {r['overhead_p50_ms']} | "
                    f"{r['overhead_p99_ms']} |\n")


if __name__ == "__main__":
    main()
