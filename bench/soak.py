#!/usr/bin/env python3
"""Soak benchmark (issue 30 item 4, "Load held"): mixed traffic at the machine's capacity against
the real server for --minutes, sampling the server's RSS, open files, threads and solver children
every --sample-s seconds.

    python3 bench/soak.py [--minutes 30] [--out bench/results] [--sample-s 60] [--warmup-min 5]
                          [--wrap "heaptrack -o /tmp/soak/ht"]

Copies build/client/ctburton to /tmp/soak/ctburton (so a rebuild does not change it under the
run) and starts `ctburton serve` with its defaults (2 solver workers, queue 8) on free loopback
ports with gRPC on, CTB_CONFIG_DIR=config, CTB_LLM_REPLAY=tests/recordings/thesis and a fresh
--data-dir under /tmp/soak. Client threads (fixed number, see CLIENTS):
  solve         POST /solve, the shipped examples x objectives (some solved by the first-plan
                engine in a millisecond, some by Gecode in 0.1-5 s)
  solve_stream  the same with "stream": true (SSE, read to `event: done`)
  grpc_solve    ctburton.v1.Planner/Solve, the same requests
  plan          POST /plan of the recorded thesis prompts (cot and direct), then
                GET and DELETE /sessions/{id}
  plan_stream   POST /plan with "stream": true, then DELETE /sessions/{id}
  replan        POST /replan, in a session (after a /plan) or with domain + state_plan + trajectory
  domains       POST /domains (a small lamp model, a new name each iteration), GET, POST /solve on
                it, PUT, DELETE; every 4th iteration three deliberate client errors (400, 404, 404)
  disconnect    clients that leave early: mid-body, before the answer (half with RST), mid-stream
                (/solve and /plan), and gRPC calls cancelled mid-solve; a refused try is
                repeated after 0.1-0.3 s until admitted (else they would hardly get a slot)
A refused client waits as told (Retry-After, jittered to 0.5-1x; 1-2 s without one).
Every response is classified: ok (2xx), refused (503 or 429 with Retry-After, a stream's
included: since git 5e6d408 a stream reserves its solver place before its 200 head, so a busy
server refuses it before any event; gRPC RESOURCE_EXHAUSTED or UNAVAILABLE whose trailing
grpc-status-details-bin is a google.rpc.Status with a google.rpc.RetryInfo detail), client_error
(a deliberate bad request answered with the status it should get), disconnect (a deliberate
early close), and unexpected (anything else: 5xx, a 503 without Retry-After, a gRPC refusal
without RetryInfo, a stream answered 200 then ended by an `event: error` 503 `busy` (counted
apart as "in-stream busy", the first run's 2,307), a reset or timeout we did not cause, a 200
whose plan is not verified). Writes OUT/soak.json and OUT/soak.md.

--wrap CMD starts the server under a wrapper (split like a shell would, the server's command
line appended: `heaptrack -o FILE`, `valgrind --leak-check=full`). The wrapper runs the server as
a child (heaptrack's shell script does), so the script looks for the server among the wrapper's
descendants (the process whose /proc/PID/exe is the copied binary; else whose command line holds
it and `serve`) and samples that process, not the wrapper; SIGTERM goes to the server itself
(the wrapper's shell would die without passing it on, and heaptrack would lose its file), then
the script waits for the wrapper to finish writing (up to --wrap-wait-s). Without --wrap nothing
changes: the Popen'd process is the server.

Needs grpcio (Debian's python3-grpcio); when the python3 on PATH lacks it, the script re-runs
itself with /usr/bin/python3.
"""
import os
import sys


def _has_grpc():
    try:
        import grpc  # noqa: F401
        return hasattr(grpc, "insecure_channel")
    except ImportError:
        return False


if not _has_grpc() and not os.environ.get("SOAK_REEXEC") and os.path.exists("/usr/bin/python3"):
    os.environ["SOAK_REEXEC"] = "1"
    os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)

import argparse  # noqa: E402
import datetime  # noqa: E402
import hashlib  # noqa: E402
import http.client  # noqa: E402
import json  # noqa: E402
import random  # noqa: E402
import shutil  # noqa: E402
import statistics  # noqa: E402
import shlex  # noqa: E402
import signal  # noqa: E402
import socket  # noqa: E402
import struct  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402
import threading  # noqa: E402
import time  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import BIN, ROOT, free_port, pct  # noqa: E402 (bench/common.py)

SOAK_DIR = "/tmp/soak"
HOST = "127.0.0.1"
# client threads per kind: 12 of them want a solver slot (solve, streams, gRPC, plan, replan,
# the stored domain's solve, the early closers), 2 more than the server's 2 slots + 8 queue
# places, so the slots stay busy and the queue overflows now and then (with 5 solve clients it
# was full at every sample and the early closers were always refused)
CLIENTS = {"solve": 3, "solve_stream": 2, "grpc_solve": 2, "plan": 1, "plan_stream": 1,
           "replan": 1, "domains": 1, "disconnect": 1}
HTTP_TIMEOUT = 120
KEEP_ALIVE_REUSE_S = 3.0
CLASSES = ("ok", "refused", "client_error", "disconnect", "unexpected")
# the status recorded for a stream answered 200 then ended by a busy error event (unexpected
# since streams reserve their solver place before the head; the first run had 2,307)
IN_STREAM_BUSY = "200+error 503 busy"

EXAMPLES = ["presentation/test1_cot", "presentation/test1_direct", "presentation/test2_cot",
            "presentation/test2_direct", "presentation/impossible_off_within59",
            "presentation/impossible_on1800_off1500", "search_rescue/test1", "search_rescue/test2",
            "search_rescue/impossible_door_shut_deadline", "assembly/test"]
OBJECTIVES = ["cost", "makespan", "cost_then_makespan"]
# the slow cases (Gecode, 0.3-5 s alone) for the early-disconnect clients
SLOW = [("search_rescue/test1", "cost_then_makespan"), ("assembly/test", "cost_then_makespan"),
        ("presentation/test2_cot", "cost"), ("assembly/test", "cost")]

LAMP = {"description": "a lamp that warms up",
        "automata": [{"name": "lamp", "locations": ["off", "warming", "on"],
                      "commands": ["turnOn", "turnOff"],
                      "transitions": [{"from": "off", "to": "warming", "guard": "lampu[i]==turnOn"},
                                      {"from": "warming", "to": "on", "duration": [5, 5]},
                                      {"from": "on", "to": "off", "guard": "lampu[i]==turnOff"}]}]}
LAMP_PLAN = {"initial_state": {"lamp": "off"},
             "end_state": {"maintenance_constraint": "true", "goal_constraint": "lampl[i+1]==off"},
             "constraints": {"episodes": {"LampOn": {"accepting_constraint": "lampl[i]==on",
                                                     "state_constraint": "lampl[i]==on",
                                                     "lower_bound": 10, "upper_bound": 20}},
                             "temporal": {}, "event": {}}}


# ---------------------------------------------------------------- statistics

class Stats:
    def __init__(self, t0):
        self.t0 = t0
        self.lock = threading.Lock()
        self.routes = {}
        self.examples = []        # unexpected answers, the first few per route
        self.notes = {}           # route -> {note: count}

    def _route(self, route):
        r = self.routes.get(route)
        if r is None:
            r = self.routes[route] = {"counts": {c: 0 for c in CLASSES}, "statuses": {},
                                      "lat_ok": [], "lat_refused": [], "per_minute": {}}
        return r

    def rec(self, route, cls, seconds, status=None, example=None):
        now = time.monotonic()
        with self.lock:
            r = self._route(route)
            r["counts"][cls] += 1
            key = str(status)
            r["statuses"][key] = r["statuses"].get(key, 0) + 1
            if cls == "ok":
                r["lat_ok"].append(seconds)
                m = int((now - self.t0) // 60)
                r["per_minute"][m] = r["per_minute"].get(m, 0) + 1
            elif cls == "refused":
                r["lat_refused"].append(seconds)
            if cls == "unexpected":
                n = sum(1 for e in self.examples if e["route"] == route)
                if n < 5:
                    e = {"route": route, "at_s": round(now - self.t0, 1),
                         "utc": datetime.datetime.utcnow().strftime("%H:%M:%S"), "status": status}
                    e.update(example or {})
                    self.examples.append(e)

    def note(self, route, what):
        with self.lock:
            d = self.notes.setdefault(route, {})
            d[what] = d.get(what, 0) + 1

    def ok_total(self):
        with self.lock:
            return {k: v["counts"]["ok"] for k, v in self.routes.items()}


_tls = threading.local()


def backoff(retry_after):
    """A refused client waits as told (Retry-After seconds, jittered to 0.5-1x), as a
    well-behaved client does; without a hint (an unexpected refusal): 1-2 s. The early closers
    retry after 0.1-0.3 s instead, or they would hardly ever get a solver slot to leave."""
    if getattr(_tls, "fast_retry", False):
        time.sleep(random.uniform(0.1, 0.3))
        return
    try:
        ra = float(retry_after)
    except (TypeError, ValueError):
        ra = 2.0
    time.sleep(random.uniform(0.5, 1.0) * ra)


def cut(b, n=300):
    if isinstance(b, bytes):
        b = b.decode("utf-8", "replace")
    return b if len(b) <= n else b[:n] + "..."


# ---------------------------------------------------------------- HTTP clients

class Http:
    """One keep-alive connection per client thread (http.client reconnects after a close)."""

    def __init__(self, port):
        self.port = port
        self.conn = None
        self.last = 0.0
        self.uses = 0

    def call(self, method, path, body=None):
        idle = time.monotonic() - self.last if self.uses else 0.0
        if self.conn is not None and idle > KEEP_ALIVE_REUSE_S:
            # the server closes idle keep-alive connections after keep_alive_s (5 s): reusing
            # one later races its close, so a client opens a new one (as browsers do)
            self.conn.close()
            self.conn = None
        if self.conn is None:
            self.conn = http.client.HTTPConnection(HOST, self.port, timeout=HTTP_TIMEOUT)
            self.uses = 0
            idle = 0.0
        hdrs = {"Content-Type": "application/json"} if body is not None else {}
        t0 = time.perf_counter()
        try:
            self.conn.request(method, path, body, hdrs)
            r = self.conn.getresponse()
            data = r.read()
        except Exception as e:
            self.conn.close()
            self.conn = None
            e.soak_ctx = {"reused_connection": self.uses > 0, "idle_before_s": round(idle, 3),
                          "elapsed_s": round(time.perf_counter() - t0, 3)}
            raise
        self.uses += 1
        self.last = time.monotonic()
        if r.will_close:
            self.conn.close()
            self.conn = None
        return r.status, r.getheader("Retry-After"), r.getheader("Content-Type", ""), data, \
            time.perf_counter() - t0


def classify_http(status, retry_after, expect=None):
    if 200 <= status < 300:
        return "ok"
    if status in (503, 429) and retry_after:
        return "refused"
    if expect is not None and status == expect:
        return "client_error"
    return "unexpected"


def check_plan(doc):
    """A 200 whose plan is not verified is a bug (contract section 5)."""
    st = doc.get("status")
    if st in ("optimal", "feasible") and doc.get("verified") is not True:
        return "plan returned with verified != true"
    if st not in ("optimal", "feasible", "infeasible", "unknown"):
        return "no trajectory status"
    return None


def do_http(stats, h, route, method, path, body, req_desc, expect=None, check=None):
    """Send, classify, record. Returns (status, parsed JSON or None)."""
    try:
        status, ra, ctype, data, dt = h.call(method, path, body)
    except Exception as e:  # noqa: BLE001 (every failure is classified)
        stats.rec(route, "unexpected", 0, "exception",
                  {"request": req_desc, "error": f"{type(e).__name__}: {e}",
                   **getattr(e, "soak_ctx", {})})
        return None, None
    cls = classify_http(status, ra, expect)
    if cls == "refused":
        stats.rec(route, cls, dt, status)
        backoff(ra)
        return status, None
    doc = None
    ex = None
    if cls == "ok" and data and ctype.startswith("application/json"):
        try:
            doc = json.loads(data)
        except ValueError:
            cls, ex = "unexpected", "2xx body is not JSON"
        if doc is not None and check:
            ex = check(doc)
            if ex:
                cls = "unexpected"
    if cls == "unexpected":
        stats.rec(route, cls, dt, status, {"request": req_desc, "retry_after": ra,
                                           "problem": ex, "body": cut(data)})
    else:
        stats.rec(route, cls, dt, status)
    return status, doc


def read_sse(resp):
    """Yield (event, data) of an SSE body."""
    ev, data = None, []
    while True:
        line = resp.readline()
        if not line:
            return
        line = line.decode("utf-8", "replace").rstrip("\r\n")
        if line == "":
            if ev is not None or data:
                yield ev, "\n".join(data)
            ev, data = None, []
        elif line.startswith("event:"):
            ev = line[6:].strip()
        elif line.startswith("data:"):
            data.append(line[5:].lstrip())


def do_stream(stats, port, route, path, body, req_desc, check):
    """POST with "stream": true on its own connection, read to the end; returns the done doc."""
    t0 = time.perf_counter()
    conn = http.client.HTTPConnection(HOST, port, timeout=HTTP_TIMEOUT)
    try:
        conn.request("POST", path, body, {"Content-Type": "application/json"})
        r = conn.getresponse()
        if r.status != 200 or not r.getheader("Content-Type", "").startswith("text/event-stream"):
            data = r.read()
            dt = time.perf_counter() - t0
            cls = classify_http(r.status, r.getheader("Retry-After"))
            if cls == "ok":
                cls = "unexpected"  # a 200 that is not a stream
            stats.rec(route, cls, dt, r.status, {"request": req_desc, "body": cut(data),
                                                 "retry_after": r.getheader("Retry-After")})
            if cls == "refused":
                backoff(r.getheader("Retry-After"))
            return None
        events, done, err = [], None, None
        for ev, data in read_sse(r):
            events.append(ev)
            if ev == "done":
                done = data
            elif ev == "error":
                err = data
        dt = time.perf_counter() - t0
    except Exception as e:  # noqa: BLE001
        stats.rec(route, "unexpected", time.perf_counter() - t0, "exception",
                  {"request": req_desc, "error": f"{type(e).__name__}: {e}"})
        return None
    finally:
        conn.close()
    if err is not None:
        try:
            ed = json.loads(err)
        except ValueError:
            ed = {}
        if ed.get("status") == 503 and ed.get("error", {}).get("code") == "busy":
            # refused after the 200 head: no Retry-After can follow (the first run's finding)
            stats.rec(route, "unexpected", dt, IN_STREAM_BUSY,
                      {"request": req_desc, "error_event": cut(err), "events": events[-5:],
                       "problem": "busy error event inside a 200 stream"})
            backoff(ed.get("error", {}).get("retry_after"))
        else:
            stats.rec(route, "unexpected", dt, f"200+error {ed.get('status')}",
                      {"request": req_desc, "error_event": cut(err), "events": events[-5:]})
        return None
    if done is None:
        stats.rec(route, "unexpected", dt, "200 no done",
                  {"request": req_desc, "events": events[-5:], "problem": "stream ended without done"})
        return None
    try:
        doc = json.loads(done)
    except ValueError:
        stats.rec(route, "unexpected", dt, 200, {"request": req_desc, "problem": "done not JSON",
                                                 "body": cut(done)})
        return None
    bad = check(doc)
    if bad:
        stats.rec(route, "unexpected", dt, 200, {"request": req_desc, "problem": bad,
                                                 "body": cut(done)})
        return None
    stats.rec(route, "ok", dt, 200)
    stats.note(route, "solution events" if "solution" in events else "no solution event")
    return doc


# ---------------------------------------------------------------- workloads

class Ctx:
    def __init__(self, port, gport, stats, stop, grpc_mod):
        self.port, self.gport, self.stats, self.stop = port, gport, stats, stop
        self.grpc = grpc_mod
        self.solves = []      # (label, domain, plan dict, objective)
        for ex in EXAMPLES:
            dom = ex.split("/")[0]
            plan = json.load(open(os.path.join(ROOT, "config", "examples", ex + ".json")))
            for o in OBJECTIVES:
                self.solves.append((f"{ex} {o}", dom, plan, o))
        doc = json.load(open(os.path.join(ROOT, "server", "static", "examples.json")))
        self.prompts = [(dom, e["command"], mode) for dom, lst in doc["domains"].items()
                        for e in lst for mode in ("cot", "direct")]
        self.trajectories = []  # (label, domain, plan, trajectory) for sessionless replans


def solve_body(dom, plan, obj, stream=False):
    b = {"domain": dom, "state_plan": plan, "options": {"objective": obj}}
    if stream:
        b["stream"] = True
    return json.dumps(b)


def w_solve(ctx, rng):
    h = Http(ctx.port)
    while not ctx.stop.is_set():
        label, dom, plan, obj = rng.choice(ctx.solves)
        do_http(ctx.stats, h, "POST /solve", "POST", "/solve", solve_body(dom, plan, obj),
                label, check=check_plan)


def w_solve_stream(ctx, rng):
    while not ctx.stop.is_set():
        label, dom, plan, obj = rng.choice(ctx.solves)
        do_stream(ctx.stats, ctx.port, "POST /solve stream", "/solve",
                  solve_body(dom, plan, obj, True), label, check_plan)


def plan_check(doc):
    if "session" not in doc or "trajectory" not in doc:
        return "no session or trajectory in the /plan answer"
    return check_plan(doc["trajectory"])


def w_plan(ctx, rng):
    h = Http(ctx.port)
    while not ctx.stop.is_set():
        dom, cmd, mode = rng.choice(ctx.prompts)
        label = f"{dom} {mode} {cmd[:40]!r}"
        st, doc = do_http(ctx.stats, h, "POST /plan", "POST", "/plan",
                          json.dumps({"domain": dom, "command": cmd, "prompting": mode}),
                          label, check=plan_check)
        if doc and "session" in doc:
            sid = doc["session"]
            do_http(ctx.stats, h, "GET /sessions/{id}", "GET", f"/sessions/{sid}", None, sid,
                    check=lambda d: None if d.get("turns") else "no turns")
            do_http(ctx.stats, h, "DELETE /sessions/{id}", "DELETE", f"/sessions/{sid}", None, sid)


def w_plan_stream(ctx, rng):
    h = Http(ctx.port)
    while not ctx.stop.is_set():
        dom, cmd, mode = rng.choice(ctx.prompts)
        label = f"{dom} {mode} {cmd[:40]!r}"
        doc = do_stream(ctx.stats, ctx.port, "POST /plan stream", "/plan",
                        json.dumps({"domain": dom, "command": cmd, "prompting": mode,
                                    "stream": True}), label, plan_check)
        if doc and "session" in doc:
            sid = doc["session"]
            do_http(ctx.stats, h, "DELETE /sessions/{id}", "DELETE", f"/sessions/{sid}", None, sid)


def replan_fields(rng, traj):
    """A departure along a plan: now at one of its events, maybe a blocked future move or an
    automaton found back where it was."""
    ts = traj.get("transitions") or []
    times = sorted({t["time"] for t in ts}) or [0]
    now = rng.choice(times)
    f = {"now": now, "options": {"objective": rng.choice(OBJECTIVES)}}
    fut = [t for t in ts if t["time"] >= now and t.get("command")]
    k = rng.random()
    if fut and k < 0.4:
        t = rng.choice(fut)
        f["blocked"] = [{"automaton": t["automaton"], "from": t["from"], "to": t["to"]}]
    elif fut and k < 0.6:
        t = rng.choice(fut)
        f["observed"] = {t["automaton"]: {"location": t["from"], "since": now}}
    return f


def replan_check(doc):
    if doc.get("status") in ("optimal", "feasible") and doc.get("verified") is not True:
        return "replan returned with verified != true"
    return None


def w_replan(ctx, rng):
    h = Http(ctx.port)
    while not ctx.stop.is_set():
        if rng.random() < 0.5 and ctx.trajectories:
            label, dom, plan, traj = rng.choice(ctx.trajectories)
            f = replan_fields(rng, traj)
            f.update({"domain": dom, "state_plan": plan, "trajectory": traj})
            do_http(ctx.stats, h, "POST /replan", "POST", "/replan", json.dumps(f),
                    f"{label} now={f['now']} {list(f)[2:3]}", check=replan_check)
        else:
            dom, cmd, mode = rng.choice([p for p in ctx.prompts if p[2] == "cot"])
            st, doc = do_http(ctx.stats, h, "POST /plan", "POST", "/plan",
                              json.dumps({"domain": dom, "command": cmd, "prompting": mode}),
                              f"{dom} {mode} (for replan)", check=plan_check)
            if not doc or "session" not in doc:
                continue
            sid = doc["session"]
            if doc["trajectory"].get("status") in ("optimal", "feasible"):
                for _ in range(2):
                    f = replan_fields(rng, doc["trajectory"])
                    f["session"] = sid
                    do_http(ctx.stats, h, "POST /replan (session)", "POST", "/replan",
                            json.dumps(f), f"session {dom} now={f['now']}", check=replan_check)
            do_http(ctx.stats, h, "DELETE /sessions/{id}", "DELETE", f"/sessions/{sid}", None, sid)


def w_domains(ctx, rng):
    h = Http(ctx.port)
    i = 0
    while not ctx.stop.is_set():
        i += 1
        name = f"soak{os.getpid()}_{i}"
        dom = dict(LAMP, name=name)
        s = ctx.stats
        st, _ = do_http(s, h, "POST /domains", "POST", "/domains", json.dumps(dom), name)
        if st == 201:
            do_http(s, h, "GET /domains/{name}", "GET", f"/domains/{name}", None, name,
                    check=lambda d: None if d.get("name") == name else "wrong document")
            do_http(s, h, "POST /solve (stored domain)", "POST", "/solve",
                    solve_body(name, LAMP_PLAN, rng.choice(OBJECTIVES)), name, check=check_plan)
            dom2 = json.loads(json.dumps(dom))
            lo = rng.randint(2, 8)
            dom2["automata"][0]["transitions"][1]["duration"] = [lo, lo + rng.randint(0, 3)]
            do_http(s, h, "PUT /domains/{name}", "PUT", f"/domains/{name}", json.dumps(dom2), name)
            do_http(s, h, "DELETE /domains/{name}", "DELETE", f"/domains/{name}", None, name)
        if i % 4 == 0:
            bad = json.loads(json.dumps(dom))
            bad["name"] = name + "_bad"
            bad["automata"][0]["transitions"][0]["guard"] = "lampu[i]==turnOnn"
            do_http(s, h, "deliberate 400 (POST /domains bad guard)", "POST", "/domains",
                    json.dumps(bad), "bad guard", expect=400)
            do_http(s, h, "deliberate 404 (DELETE unknown domain)", "DELETE",
                    f"/domains/{name}_none", None, "unknown", expect=404)
            do_http(s, h, "deliberate 404 (POST /solve unknown domain)", "POST", "/solve",
                    solve_body(name + "_none", LAMP_PLAN, "cost"), "unknown", expect=404)


def raw_request(port, path, body):
    head = (f"POST {path} HTTP/1.1\r\nHost: {HOST}:{port}\r\nContent-Type: application/json\r\n"
            f"Content-Length: {len(body)}\r\n\r\n").encode()
    s = socket.create_connection((HOST, port), timeout=30)
    return s, head, body.encode()


def close_socket(s, rst):
    if rst:  # SO_LINGER 0: the close sends RST instead of FIN
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    s.close()


def refusals(stats, route):
    """Refused tries of a route so far (a busy event inside a stream included)."""
    r = stats.routes.get(route, {})
    return r.get("counts", {}).get("refused", 0) + r.get("statuses", {}).get(IN_STREAM_BUSY, 0)


def w_disconnect(ctx, rng):
    slow = [(f"{e} {o}", e.split("/")[0],
             json.load(open(os.path.join(ROOT, "config", "examples", e + ".json"))), o)
            for e, o in SLOW]
    _tls.fast_retry = True
    kind, tries = None, 0
    while not ctx.stop.is_set():
        if kind is None or tries >= 50:  # else: the last try was refused, try it again
            kind, tries = rng.choice(["mid-body", "before answer", "mid-stream /solve",
                                      "mid-stream /plan", "gRPC cancel"]), 0
        tries += 1
        route = f"early close: {kind}"
        refused_before = refusals(ctx.stats, route)
        one_close(ctx, rng, slow, kind, route)
        if refusals(ctx.stats, route) == refused_before:
            kind = None


def one_close(ctx, rng, slow, kind, route):
    t0 = time.perf_counter()
    try:
        if kind == "gRPC cancel":
            label, dom, plan, obj = rng.choice(slow)
            fut = ctx.grpc_stub.Solve.future(grpc_request(ctx, dom, plan, obj), timeout=60)
            end = time.monotonic() + rng.uniform(0.1, 1.0)
            while time.monotonic() < end and not fut.done():
                time.sleep(0.02)
            if fut.cancel():
                ctx.stats.rec(route, "disconnect", time.perf_counter() - t0, "cancelled")
            else:  # it ended before the cancel: classify its answer
                grpc_outcome(ctx, route, fut, time.perf_counter() - t0, label)
            return
        if kind == "mid-body":
            label, dom, plan, obj = rng.choice(slow)
            s, head, body = raw_request(ctx.port, "/solve", solve_body(dom, plan, obj))
            s.sendall(head + body[:len(body) // 2])
            time.sleep(rng.uniform(0.05, 0.5))
            close_socket(s, rng.random() < 0.5)
            ctx.stats.rec(route, "disconnect", time.perf_counter() - t0, "closed")
            return
        if kind == "mid-stream /plan":
            dom, cmd, mode = rng.choice(ctx.prompts)
            body = json.dumps({"domain": dom, "command": cmd, "prompting": mode, "stream": True})
            path = "/plan"
        else:
            label, dom, plan, obj = rng.choice(slow)
            body = solve_body(dom, plan, obj, kind == "mid-stream /solve")
            path = "/solve"
        s, head, b = raw_request(ctx.port, path, body)
        s.sendall(head + b)
        got = b""
        if kind == "before answer":
            time.sleep(rng.uniform(0.1, 1.0))
        else:  # read until the solve began (or 3 s), then leave
            s.settimeout(0.1)
            end = time.monotonic() + 3
            while time.monotonic() < end and b'"solving"' not in got \
                    and b"event: error" not in got and b"event: done" not in got:
                try:
                    chunk = s.recv(65536)
                except socket.timeout:
                    continue
                if not chunk:
                    break
                got += chunk
        s.setblocking(False)
        try:
            got += s.recv(65536)
        except (BlockingIOError, OSError):
            pass
        close_socket(s, rng.random() < 0.5)
        dt = time.perf_counter() - t0
        head_end = got.find(b"\r\n\r\n")
        first = got.split(b"\r\n", 1)[0].decode("latin-1")
        hdrs = got[:head_end].decode("latin-1").lower() if head_end >= 0 else ""
        if first.startswith("HTTP/1.1 503") or first.startswith("HTTP/1.1 429"):
            # refused before we left: a refusal, not an early close
            if "\r\nretry-after:" in hdrs:
                ctx.stats.rec(route, "refused", dt, int(first.split()[1]))
                backoff(0.5)
            else:
                ctx.stats.rec(route, "unexpected", dt, int(first.split()[1]),
                              {"request": kind, "body": cut(got)})
            return
        if first and not first.startswith("HTTP/1.1 200"):
            ctx.stats.rec(route, "unexpected", dt, first, {"request": kind, "body": cut(got)})
            return
        if b"event: error" in got:
            if b'"busy"' in got:  # refused after the 200 head: unexpected since git 5e6d408
                ctx.stats.rec(route, "unexpected", dt, IN_STREAM_BUSY,
                              {"request": kind, "body": cut(got[head_end:]),
                               "problem": "busy error event inside a 200 stream"})
                backoff(0.5)
            else:
                ctx.stats.rec(route, "unexpected", dt, "200+error",
                              {"request": kind, "body": cut(got[head_end:])})
            return
        if b"event: done" in got:
            what = "after the answer (it came first)"
        elif not got:
            what = "with nothing received yet (queued or solving)"
        elif b"event: solution" in got:
            what = "after a solution event"
        elif b'"solving"' in got:
            what = "while solving"
        elif b"event: stage" in got:
            what = "before solving (translating or waiting for a slot)"
        else:
            what = "after the response head"
        ctx.stats.note(route, "closed " + what)
        ctx.stats.rec(route, "disconnect", dt, "closed")
    except Exception as e:  # noqa: BLE001
        ctx.stats.rec(route, "unexpected", time.perf_counter() - t0, "exception",
                      {"error": f"{type(e).__name__}: {e}"})


# ---------------------------------------------------------------- gRPC

def grpc_stubs():
    tmp = tempfile.mkdtemp(prefix="soak_stubs_")
    plugin = shutil.which("grpc_python_plugin")
    subprocess.run(["protoc", "-I", os.path.join(ROOT, "proto"), f"--python_out={tmp}",
                    f"--grpc_out={tmp}", "--plugin=protoc-gen-grpc=" + plugin,
                    os.path.join(ROOT, "proto", "ctburton", "v1", "planner.proto")], check=True)
    sys.path.insert(0, tmp)
    from google.protobuf import json_format
    from ctburton.v1 import planner_pb2, planner_pb2_grpc
    return json_format, planner_pb2, planner_pb2_grpc


_GRPC_REQ = {}


def grpc_request(ctx, dom, plan, obj):
    key = (dom, id(plan), obj)
    r = _GRPC_REQ.get(key)
    if r is None:
        jf, pb, _ = ctx.pb
        r = _GRPC_REQ[key] = pb.SolveRequest(domain=dom, state_plan=jf.ParseDict(plan, pb.StatePlan()),
                                             options=pb.Options(objective=obj))
    return r


def _pb_fields(buf):
    """The (field number, value) pairs of one protobuf message (wire types 0, 1, 2, 5)."""
    out, i = [], 0

    def varint():
        nonlocal i
        v, shift = 0, 0
        while True:
            b = buf[i]
            i += 1
            v |= (b & 0x7F) << shift
            shift += 7
            if not b & 0x80:
                return v
    while i < len(buf):
        key = varint()
        wt = key & 7
        if wt == 0:
            val = varint()
        elif wt == 1:
            val, i = buf[i:i + 8], i + 8
        elif wt == 2:
            n = varint()
            val, i = buf[i:i + n], i + n
        elif wt == 5:
            val, i = buf[i:i + 4], i + 4
        else:
            raise ValueError(f"wire type {wt}")
        out.append((key >> 3, val))
    return out


def retry_info(trailing):
    """The retry delay in seconds of the google.rpc.RetryInfo in a gRPC error's trailing
    grpc-status-details-bin (a google.rpc.Status: 3 = repeated google.protobuf.Any, whose
    1 = type_url and 2 = value; RetryInfo: 1 = retry_delay, a Duration of 1 = seconds and
    2 = nanos), or None when there is none. Decoded by hand: no generated code is needed."""
    md = dict(trailing or ())
    raw = md.get("grpc-status-details-bin")
    if not raw:
        return None
    try:
        for f, any_ in _pb_fields(raw):
            if f != 3:
                continue
            a = dict(_pb_fields(any_))
            if not a.get(1, b"").decode("utf-8", "replace").endswith("google.rpc.RetryInfo"):
                continue
            d = dict(_pb_fields(a.get(2, b""))).get(1, b"")  # retry_delay
            dur = dict(_pb_fields(d))
            return dur.get(1, 0) + dur.get(2, 0) / 1e9
    except (ValueError, IndexError):
        return None
    return None


def grpc_outcome(ctx, route, fut, dt, label):
    grpc = ctx.grpc
    pb = ctx.pb[1]
    try:
        r = fut.result()
    except grpc.RpcError as e:
        code = e.code()
        if code in (grpc.StatusCode.RESOURCE_EXHAUSTED, grpc.StatusCode.UNAVAILABLE):
            # busy (or unavailable): a refusal only with a google.rpc.RetryInfo saying when to
            # try again, as HTTP's 503 needs its Retry-After
            md = e.trailing_metadata() or ()
            delay = retry_info(md)
            if delay is not None:
                ctx.stats.rec(route, "refused", dt, code.name)
                ctx.stats.note(route, f"{code.name} RetryInfo {delay:g} s")
                backoff(delay)
            else:
                ctx.stats.rec(route, "unexpected", dt, code.name,
                              {"request": label, "details": cut(e.details() or ""),
                               "problem": "no google.rpc.RetryInfo in grpc-status-details-bin",
                               "trailing_keys": sorted(k for k, _ in md)})
                backoff(None)
        elif code == grpc.StatusCode.CANCELLED and route.startswith("early close"):
            ctx.stats.rec(route, "disconnect", dt, code.name)
        else:
            ctx.stats.rec(route, "unexpected", dt, code.name,
                          {"request": label, "details": cut(e.details() or "")})
        return
    name = pb.PlanStatus.Name(r.status)
    if name in ("SOLVED_OPTIMALLY", "SOLVED_SATISFICING", "UNSOLVABLE_PROVEN",
                "UNSOLVABLE_INCOMPLETELY", "TIMEOUT"):
        if name.startswith("SOLVED") and not r.trajectory.verified:
            ctx.stats.rec(route, "unexpected", dt, name, {"request": label, "problem": "not verified"})
        else:
            ctx.stats.rec(route, "ok", dt, "OK")
    else:
        ctx.stats.rec(route, "unexpected", dt, name, {"request": label})


def w_grpc_solve(ctx, rng):
    stub = ctx.pb[2].PlannerStub(ctx.grpc.insecure_channel(f"{HOST}:{ctx.gport}"))
    while not ctx.stop.is_set():
        label, dom, plan, obj = rng.choice(ctx.solves)
        t0 = time.perf_counter()
        fut = stub.Solve.future(grpc_request(ctx, dom, plan, obj), timeout=HTTP_TIMEOUT)
        try:
            fut.result()
        except Exception:  # noqa: BLE001 (classified below)
            pass
        grpc_outcome(ctx, "gRPC Solve", fut, time.perf_counter() - t0, label)


WORKERS = {"solve": w_solve, "solve_stream": w_solve_stream, "grpc_solve": w_grpc_solve,
           "plan": w_plan, "plan_stream": w_plan_stream, "replan": w_replan,
           "domains": w_domains, "disconnect": w_disconnect}


# ---------------------------------------------------------------- sampling

def descendants(pid):
    kids = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            stat = open(f"/proc/{d}/stat").read()
        except OSError:
            continue
        rest = stat[stat.rfind(")") + 2:].split()
        kids.setdefault(int(rest[1]), []).append(int(d))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        for k in kids.get(p, []):
            out.append(k)
            todo.append(k)
    return out


def cpu_times():
    f = open("/proc/stat").readline().split()[1:]
    user, nice, system, idle, iowait, irq, softirq, steal = (int(x) for x in f[:8])
    return {"user": user, "nice": nice, "system": system + irq + softirq, "idle": idle,
            "iowait": iowait, "steal": steal}


def proc_cpu(pid):
    stat = open(f"/proc/{pid}/stat").read()
    rest = stat[stat.rfind(")") + 2:].split()
    return sum(int(x) for x in rest[11:15])  # utime stime cutime cstime


def metrics(port):
    want = ("ctb_connections_open", "ctb_solver_jobs_running", "ctb_solver_jobs_queued",
            "ctb_solver_jobs_rejected_total", "ctb_connections_refused_total",
            "ctb_requests_timed_out_total")
    out = {}
    try:
        c = http.client.HTTPConnection(HOST, port, timeout=10)
        c.request("GET", "/metrics")
        for line in c.getresponse().read().decode().splitlines():
            name = line.split("{")[0].split(" ")[0]
            if name in want:
                out[name] = out.get(name, 0) + float(line.rsplit(" ", 1)[1])
        c.close()
    except Exception as e:  # noqa: BLE001
        out["error"] = f"{type(e).__name__}: {e}"
    return out


class Sampler:
    def __init__(self, pid, port, t0, stats):
        self.pid, self.port, self.t0, self.stats = pid, port, t0, stats
        self.samples = []
        self.prev = None
        self.hz = os.sysconf("SC_CLK_TCK")

    def sample(self, phase):
        now = time.monotonic()
        st = {}
        for line in open(f"/proc/{self.pid}/status"):
            k, v = line.split(":", 1)
            if k in ("VmRSS", "VmHWM", "Threads", "RssAnon", "RssFile"):
                st[k] = int(v.split()[0])
        fds = len(os.listdir(f"/proc/{self.pid}/fd"))
        cpu, pcpu, me = cpu_times(), proc_cpu(self.pid), os.times()
        s = {"t_s": round(now - self.t0, 1), "utc": datetime.datetime.utcnow().strftime("%H:%M:%S"),
             "phase": phase, "rss_mb": round(st["VmRSS"] / 1024, 1),
             "hwm_mb": round(st["VmHWM"] / 1024, 1), "fds": fds, "threads": st["Threads"],
             # anonymous (the heap, stacks) and file-backed (code and libraries paged in) parts
             "rss_anon_mb": round(st.get("RssAnon", 0) / 1024, 1),
             "rss_file_mb": round(st.get("RssFile", 0) / 1024, 1),
             "children": len(descendants(self.pid)),
             "loadavg": [float(x) for x in open("/proc/loadavg").read().split()[:3]],
             "metrics": metrics(self.port), "ok_so_far": sum(self.stats.ok_total().values())}
        if self.prev:
            pc, ppc, pme, pt = self.prev
            tot = sum(cpu.values()) - sum(pc.values())
            if tot > 0:
                s["cpu_pct"] = {k: round(100 * (cpu[k] - pc[k]) / tot, 1) for k in cpu}
            wall = now - pt
            s["server_cpu_cores"] = round((pcpu - ppc) / self.hz / wall, 2)
            s["client_cpu_cores"] = round(((me.user + me.system) - (pme.user + pme.system)) / wall, 2)
            if "cpu_pct" in s:
                busy = 100 - s["cpu_pct"]["idle"] - s["cpu_pct"]["iowait"]
                s["other_cpu_cores"] = round(max(0.0, busy / 100 * (os.cpu_count() or 1)
                                                 - s["server_cpu_cores"] - s["client_cpu_cores"]), 2)
        self.prev = (cpu, pcpu, me, now)
        self.samples.append(s)
        print(json.dumps({k: s[k] for k in ("utc", "phase", "rss_mb", "fds", "threads", "children",
                                            "loadavg")} | {"cpu": s.get("cpu_pct"),
                                                           "server_cores": s.get("server_cpu_cores"),
                                                           "ok": s["ok_so_far"]}), flush=True)
        return s


def top_others():
    """The busiest processes other than ours (the machine is shared)."""
    try:
        out = subprocess.run(["ps", "-eo", "pid,ni,pcpu,etime,comm", "--sort=-pcpu"],
                             capture_output=True, text=True, timeout=10).stdout.splitlines()
        return out[:8]
    except Exception:  # noqa: BLE001
        return []


# ---------------------------------------------------------------- main

def find_server(wrapper, binary, timeout_s=60, grace_s=10):
    """The pid of the server started under a wrapper: the wrapper itself or one of its
    descendants whose executable is the copied binary (heaptrack runs it as a child of its
    shell). Failing that for grace_s (a wrapper that execs its own tool, as valgrind does), the
    deepest process whose command line holds the binary and `serve` (not earlier: the wrapper's
    own command line holds them too)."""
    real = os.path.realpath(binary)
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        if wrapper.poll() is not None:
            raise SystemExit(f"wrapper exited with {wrapper.returncode} at start")
        by_cmd = set()
        for p in [wrapper.pid] + descendants(wrapper.pid):
            try:
                if os.path.realpath(f"/proc/{p}/exe") == real:
                    return p
                argv = open(f"/proc/{p}/cmdline", "rb").read().split(b"\0")
            except OSError:
                continue
            if binary.encode() in argv and b"serve" in argv:
                by_cmd.add(p)
        if time.monotonic() - t0 > grace_s:
            deepest = [p for p in by_cmd if not by_cmd.intersection(descendants(p))]
            if deepest:
                return deepest[0]
        time.sleep(0.1)
    raise SystemExit("server process not found under the wrapper")


def alive(pid):
    """A process that exists and is not a zombie."""
    try:
        stat = open(f"/proc/{pid}/stat").read()
    except OSError:
        return False
    return stat[stat.rfind(")") + 2] != "Z"


def wait_ready(port, proc):
    for _ in range(300):
        if proc.poll() is not None:
            raise SystemExit(f"server exited with {proc.returncode} at start")
        try:
            c = http.client.HTTPConnection(HOST, port, timeout=2)
            c.request("GET", "/healthz")
            if c.getresponse().status == 200:
                return
        except OSError:
            pass
        time.sleep(0.1)
    raise SystemExit("server not ready")


def summarize_log(path):
    levels, examples = {}, []
    events = {}
    with open(path, errors="replace") as f:
        for line in f:
            try:
                d = json.loads(line)
            except ValueError:
                levels["(not JSON)"] = levels.get("(not JSON)", 0) + 1
                if len(examples) < 10:
                    examples.append(cut(line.strip(), 300))
                continue
            lv = d.get("level", "?")
            levels[lv] = levels.get(lv, 0) + 1
            log = d.get("log") if isinstance(d.get("log"), dict) else {}
            if lv not in ("info", "debug"):
                key = lv + " " + str(log.get("event") or log.get("message") or cut(json.dumps(log), 80))
                events[key] = events.get(key, 0) + 1
                if len(examples) < 10 and events[key] <= 2:
                    examples.append(cut(line.strip(), 400))
            elif log.get("event") == "request" and isinstance(log.get("status"), int) \
                    and log["status"] >= 500:
                key = f"request {log.get('route')} {log['status']}"
                events[key] = events.get(key, 0) + 1
    return {"levels": levels, "non_info": events, "examples": examples}


def route_summary(r):
    ok, rf = r["lat_ok"], r["lat_refused"]
    ms = lambda x: round(x * 1000, 1)  # noqa: E731
    out = {"counts": r["counts"], "statuses": r["statuses"],
           "total": sum(r["counts"].values()),
           "per_minute_ok": [r["per_minute"].get(m, 0) for m in range(max(r["per_minute"], default=-1) + 1)]}
    if ok:
        out.update({"p50_ms": ms(pct(ok, 50)), "p99_ms": ms(pct(ok, 99)), "max_ms": ms(max(ok))})
    if rf:
        out.update({"refused_p50_ms": ms(pct(rf, 50)), "refused_max_ms": ms(max(rf))})
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--minutes", type=float, default=30)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--sample-s", type=float, default=60, help="seconds between samples")
    ap.add_argument("--warmup-min", type=float, default=None,
                    help="warm-up excluded from the growth verdict (default min(5, minutes/2))")
    ap.add_argument("--bin", default=BIN, help="the ctburton to copy and run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--render", metavar="SOAK_JSON",
                    help="no run: rewrite OUT/soak.{json,md} from an earlier soak.json")
    ap.add_argument("--append", metavar="MD", help="with --render: a follow-up section to add")
    ap.add_argument("--wrap", default="", metavar="CMD",
                    help='start the server under CMD, e.g. "heaptrack -o /tmp/soak/ht"; RSS and '
                         "SIGTERM go to the server process found under it")
    ap.add_argument("--wrap-wait-s", type=float, default=900,
                    help="with --wrap: how long to wait for the wrapper after the server exited")
    a = ap.parse_args()
    if a.render:
        res = json.load(open(a.render))
        res.pop("follow_up_md", None)
        write_results(res, a.out, a.append)
        return
    warm = a.warmup_min if a.warmup_min is not None else min(5.0, a.minutes / 2)
    cmd = " ".join(["python3 bench/soak.py"] + sys.argv[1:])

    os.makedirs(SOAK_DIR, exist_ok=True)
    # `ctburton serve` execs ctburton-server from its folder: run (a copy of) that one directly.
    server_bin = os.path.join(os.path.dirname(os.path.abspath(a.bin)), "ctburton-server")
    source = server_bin if os.path.exists(server_bin) else a.bin
    binary = os.path.join(SOAK_DIR, os.path.basename(source))
    shutil.copy2(source, binary)
    sha = hashlib.sha256(open(binary, "rb").read()).hexdigest()[:16]
    bin_mtime = datetime.datetime.utcfromtimestamp(os.path.getmtime(source)).strftime("%Y-%m-%d %H:%M UTC")
    try:
        head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True).stdout.strip()
    except OSError:
        head = "?"
    run_dir = tempfile.mkdtemp(prefix="run-", dir=SOAK_DIR)
    data_dir = os.path.join(run_dir, "data")
    os.makedirs(data_dir)
    log_path = os.path.join(run_dir, "server.log")

    grpc = None
    pb = None
    import grpc as grpc_mod
    grpc = grpc_mod
    pb = grpc_stubs()

    port, gport = free_port(), free_port()
    env = dict(os.environ, CTB_CONFIG_DIR=os.path.join(ROOT, "config"),
               CTB_LLM_REPLAY=os.path.join(ROOT, "tests", "recordings", "thesis"))
    for k in ("CTB_LLM_BASE_URL", "CTB_LLM_API_KEY", "CTB_LLM_RECORD"):
        env.pop(k, None)
    logf = open(log_path, "wb")
    wrap = shlex.split(a.wrap)
    srv = subprocess.Popen(wrap + [binary, "serve", "--port", str(port), "--grpc-port", str(gport),
                                   "--data-dir", data_dir], cwd=ROOT, env=env,
                           stdout=logf, stderr=subprocess.STDOUT)
    # the process to sample and to stop: the Popen'd one, or the server under the wrapper
    server_pid = find_server(srv, binary) if wrap else srv.pid
    print(f"server pid {server_pid}" + (f" (under {a.wrap!r}, pid {srv.pid})" if wrap else "")
          + f" http {port} grpc {gport}; run dir {run_dir}", flush=True)
    started_utc = datetime.datetime.utcnow()
    crash = None
    try:
        wait_ready(port, srv)
        grpc.channel_ready_future(grpc.insecure_channel(f"{HOST}:{gport}")).result(timeout=30)
        stop = threading.Event()
        t0 = time.monotonic()
        stats = Stats(t0)
        ctx = Ctx(port, gport, stats, stop, grpc)
        ctx.pb = pb
        ctx.grpc_stub = pb[2].PlannerStub(grpc.insecure_channel(f"{HOST}:{gport}"))
        # plans to replan without a session (solved before the traffic starts)
        for ex in ("search_rescue/test1", "search_rescue/test2", "presentation/test1_cot",
                   "assembly/test"):
            dom = ex.split("/")[0]
            plan = json.load(open(os.path.join(ROOT, "config", "examples", ex + ".json")))
            c = http.client.HTTPConnection(HOST, port, timeout=120)
            c.request("POST", "/solve", json.dumps({"domain": dom, "state_plan": plan,
                                                    "options": {"objective": "makespan"}}),
                      {"Content-Type": "application/json"})
            r = c.getresponse()
            traj = json.loads(r.read())
            if r.status == 200 and traj.get("status") in ("optimal", "feasible"):
                ctx.trajectories.append((ex, dom, plan, traj))
        sampler = Sampler(server_pid, port, t0, stats)
        others_start = top_others()
        sampler.sample("start")
        threads = []
        n = 0
        for kind, count in CLIENTS.items():
            for _ in range(count):
                n += 1
                rng = random.Random(a.seed * 1000 + n)
                t = threading.Thread(target=WORKERS[kind], args=(ctx, rng), name=f"{kind}{n}",
                                     daemon=True)
                threads.append(t)
                t.start()
        end = t0 + a.minutes * 60
        next_s = t0 + a.sample_s
        while time.monotonic() < end:
            time.sleep(min(1.0, max(0.0, end - time.monotonic())))
            if srv.poll() is not None or not alive(server_pid):
                crash = {"at_s": round(time.monotonic() - t0, 1), "returncode": srv.poll(),
                         "utc": datetime.datetime.utcnow().strftime("%H:%M:%S")}
                print("SERVER DIED", crash, flush=True)
                break
            if time.monotonic() >= next_s:
                sampler.sample("load")
                next_s += a.sample_s
        traffic_s = time.monotonic() - t0
        if not crash and time.monotonic() - (next_s - a.sample_s) > 5:
            sampler.sample("load")  # the last sample under load
        others_end = top_others()
        stop.set()
        for t in threads:
            t.join(timeout=HTTP_TIMEOUT + 10)
        stuck = [t.name for t in threads if t.is_alive()]
        idle_samples = []
        if not crash:
            time.sleep(10)
            idle_samples.append(sampler.sample("idle 10 s after the traffic"))
        shutdown = None
        if srv.poll() is None and not wrap:
            ts = time.monotonic()
            srv.send_signal(signal.SIGTERM)
            try:
                rc = srv.wait(timeout=60)
            except subprocess.TimeoutExpired:
                srv.kill()
                rc = "killed after 60 s"
            shutdown = {"returncode": rc, "seconds": round(time.monotonic() - ts, 2)}
        elif srv.poll() is None:
            # the server itself gets the SIGTERM (it drains and exits; the wrapper then writes
            # its data), and the wrapper is waited for
            ts = time.monotonic()
            os.kill(server_pid, signal.SIGTERM)
            while alive(server_pid) and time.monotonic() - ts < 60:
                time.sleep(0.05)
            gone = not alive(server_pid)
            server_s = round(time.monotonic() - ts, 2)
            if not gone:
                os.kill(server_pid, signal.SIGKILL)
            try:
                rc = srv.wait(timeout=a.wrap_wait_s)
            except subprocess.TimeoutExpired:
                srv.kill()
                rc = f"wrapper killed after {a.wrap_wait_s:g} s"
            # heaptrack's script exits with the server's code
            shutdown = {"returncode": rc if gone else "killed after 60 s", "seconds": server_s,
                        "wrapper_seconds": round(time.monotonic() - ts, 2)}
    finally:
        if wrap and alive(server_pid):
            os.kill(server_pid, signal.SIGKILL)
        if srv.poll() is None:
            srv.kill()
        logf.close()
    finished_utc = datetime.datetime.utcnow()
    logsum = summarize_log(log_path)

    # ------------------------------------------------------------ results
    routes = {k: route_summary(v) for k, v in sorted(stats.routes.items())}
    minutes = int(traffic_s // 60) + 1
    per_minute = [sum(r["per_minute_ok"][m] if m < len(r["per_minute_ok"]) else 0
                      for r in routes.values()) for m in range(minutes)]
    totals = {c: sum(r["counts"][c] for r in routes.values()) for c in CLASSES}
    res = {"command": cmd, "started_utc": started_utc.strftime("%Y-%m-%d %H:%M:%S"),
           "finished_utc": finished_utc.strftime("%Y-%m-%d %H:%M:%S"),
           "traffic_s": round(traffic_s, 1), "binary": {"source": source, "copy": binary, "sha256_16": sha,
                                                          "built": bin_mtime, "git_head": head},
           "server": {"port": port, "grpc_port": gport, "data_dir": data_dir, "log": log_path,
                      "wrap": a.wrap, "pid": server_pid,
                      "config": "defaults (2 solver workers, queue 8, max_connections 128)"},
           "clients": CLIENTS, "cores": os.cpu_count(), "routes": routes, "totals": totals,
           "per_minute_ok": per_minute, "samples": sampler.samples,
           "verdict": {"warmup_min": warm, "crash": crash, "stuck_client_threads": stuck,
                       "shutdown": shutdown},
           "unexpected_examples": stats.examples, "notes": stats.notes, "server_log": logsum,
           "busiest_processes": {"start": others_start, "end": others_end}}
    write_results(res, a.out)


def slope(pts):
    """Least-squares slope of [(x, y)], or None."""
    if len(pts) < 3:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    den = sum((x - mx) ** 2 for x, _ in pts)
    return round(sum((x - mx) * (y - my) for x, y in pts) / den, 3) if den else None


def compute_verdict(res):
    """The growth and error verdict from the samples and totals (also for --render)."""
    v = dict(res["verdict"])
    warm_s = v["warmup_min"] * 60
    samples, totals = res["samples"], res["totals"]
    load = [s for s in samples if s["phase"] in ("start", "load")]
    idle = [s for s in samples if s["phase"].startswith("idle")]
    after = [s for s in load if s["t_s"] >= warm_s - 1] or load[-1:]
    base, last = after[0], load[-1]
    half = [s for s in load if s["t_s"] >= last["t_s"] / 2 - 1]
    growth = round(last["rss_mb"] - base["rss_mb"], 1)
    served = last["ok_so_far"] - base["ok_so_far"]
    v.update({
        "rss_mb_at_warmup": base["rss_mb"], "rss_mb_end": last["rss_mb"],
        "rss_growth_mb": growth,
        "rss_growth_pct": round(100 * growth / base["rss_mb"], 1) if base["rss_mb"] else None,
        "rss_slope_mb_per_min_after_warmup": slope([(s["t_s"] / 60, s["rss_mb"]) for s in after]),
        "rss_slope_mb_per_min_second_half": slope([(s["t_s"] / 60, s["rss_mb"]) for s in half]),
        "rss_kb_per_ok_answer_after_warmup": round(growth * 1024 / served, 2) if served else None,
        "ok_answers_after_warmup": served,
        "rss_max_after_warmup_mb": max(s["rss_mb"] for s in after),
        "fds_at_warmup": base["fds"], "fds_end": last["fds"],
        "fds_max_after_warmup": max(s["fds"] for s in after),
        "fds_idle_after": idle[0]["fds"] if idle else None,
        "threads_at_warmup": base["threads"], "threads_end": last["threads"],
        "threads_max_after_warmup": max(s["threads"] for s in after),
        "children_after_traffic": idle[0]["children"] if idle else None,
        "unexpected": totals["unexpected"],
        "in_stream_busy": sum(r.get("statuses", {}).get(IN_STREAM_BUSY, 0)
                              for r in res["routes"].values()),
        "grpc_refusals_with_retry_info": retry_info_notes(res)})
    # A single sample holds the requests in flight (a solve keeps a few MB while it runs), so the
    # verdict compares the median of the first five minutes after the warm-up with the median of
    # the last five minutes of traffic; the point values above stay in the report.
    win_s = 5 * 60
    first_win = [s["rss_mb"] for s in after if s["t_s"] <= base["t_s"] + win_s]
    last_win = [s["rss_mb"] for s in after if s["t_s"] >= last["t_s"] - win_s]
    med_first, med_last = statistics.median(first_win), statistics.median(last_win)
    med_growth = round(med_last - med_first, 1)
    v.update({"rss_median_first_5min_after_warmup_mb": med_first,
              "rss_median_last_5min_mb": med_last, "rss_median_growth_mb": med_growth})
    rss_ok = med_growth <= max(5.0, 0.10 * med_first)
    fd_ok = last["fds"] <= base["fds"] + 4 and (not idle or idle[0]["fds"] <= base["fds"] + 4)
    v["rss_ok"], v["fds_ok"] = rss_ok, fd_ok
    v["holds"] = bool(rss_ok and fd_ok and totals["unexpected"] == 0 and not v.get("crash")
                      and not v.get("stuck_client_threads"))
    return v


def retry_info_notes(res):
    """gRPC refusals with a RetryInfo, by code and delay (from the notes)."""
    out = {}
    for d in (res.get("notes") or {}).values():
        for k, n in d.items():
            if " RetryInfo " in k:
                out[k] = out.get(k, 0) + n
    return out


def write_results(res, out, append=None):
    res["verdict"] = compute_verdict(res)
    if append:
        res["follow_up_md"] = open(append).read()
    os.makedirs(out, exist_ok=True)
    json.dump(res, open(os.path.join(out, "soak.json"), "w"), indent=1)
    write_md(os.path.join(out, "soak.md"), res)
    print("wrote", os.path.join(out, "soak.md"), "verdict:", json.dumps(res["verdict"]), flush=True)


def num(m, k):
    return f"{m[k]:.0f}" if isinstance(m.get(k), (int, float)) else "?"


def write_md(path, res):
    v = res["verdict"]
    rss_ok, fd_ok = v["rss_ok"], v["fds_ok"]
    L = ["# Soak: load held (issue 30 item 4)", "",
         f"Command: `{res['command'].strip()}`, {res['started_utc']} to {res['finished_utc']} UTC, "
         f"{res['traffic_s'] / 60:.1f} min of traffic on this {res['cores']}-core machine (shared: "
         "see the load below). Server: a copy of `build/client/ctburton` (built "
         f"{res['binary']['built']}, git {res['binary']['git_head']}, Release, sha256 "
         f"{res['binary']['sha256_16']}...) running `serve` with its "
         f"{res['server']['config']}, gRPC on, `CTB_LLM_REPLAY=tests/recordings/thesis`, a fresh "
         "`--data-dir`" + (f", under `{res['server']['wrap']}` (RSS sampled from the server process "
                           "itself, not the wrapper; under heaptrack it includes heaptrack's own "
                           "bookkeeping inside the server)" if res["server"].get("wrap") else "") +
         ". Clients (threads): " +
         ", ".join(f"{k} {n}" for k, n in res["clients"].items()) + ".", "",
         "Classes: **ok** 2xx; **refused** 503/429 with `Retry-After`, streams included (a "
         "`\"stream\": true` request now reserves its solver place before its 200 head, so a busy "
         "server refuses it with a 503 before any event), and gRPC `RESOURCE_EXHAUSTED` or "
         "`UNAVAILABLE` whose trailing `grpc-status-details-bin` is a `google.rpc.Status` with a "
         "`google.rpc.RetryInfo` detail (decoded); **client err** a deliberate bad request "
         "answered as it should; **closed** a deliberate early close (no answer expected); "
         "**unexpected** anything else, including a stream answered 200 then ended by an "
         "`event: error` 503 `busy` (column **in-stream busy**, a part of unexpected; the first "
         "run's 2,307) and a gRPC refusal without `RetryInfo`. Latencies are of ok answers, whole "
         "request to last byte (streams: to `event: done`), queueing for a solver slot included.",
         "", "| route | total | ok | refused | client err | closed | unexpected | in-stream busy | "
         "ok/min | p50 ms | p99 ms | max ms |", "|---|" + "---|" * 11]
    mins = max(res["traffic_s"] / 60, 1e-9)
    for name, r in res["routes"].items():
        c = r["counts"]
        L.append(f"| {name} | {r['total']} | {c['ok']} | {c['refused']} | "
                 f"{c['client_error']} | {c['disconnect']} | {c['unexpected']} | "
                 f"{r['statuses'].get(IN_STREAM_BUSY, 0)} | "
                 f"{c['ok'] / mins:.1f} | {r.get('p50_ms', '')} | {r.get('p99_ms', '')} | "
                 f"{r.get('max_ms', '')} |")
    t = res["totals"]
    L.append(f"| **all** | {sum(t.values())} | {t['ok']} | {t['refused']} | "
             f"{t['client_error']} | {t['disconnect']} | {t['unexpected']} | {v['in_stream_busy']} | "
             f"{t['ok'] / mins:.1f} | | | |")
    L += ["", "ok answers per minute (all routes): " + ", ".join(map(str, res["per_minute_ok"])), "",
          "## The server over time", "",
          "| UTC | min | phase | RSS MB | RSS anon/file MB | peak RSS MB | open fds | threads | solver procs | "
          "jobs running/queued | rejected (total) | conns open | server CPU (cores) | "
          "client CPU (cores) | others' CPU (cores) | CPU user/nice/sys/idle % | loadavg 1/5/15 |",
          "|---|" + "---|" * 16]
    for s in res["samples"]:
        m = s.get("metrics", {})
        cp = s.get("cpu_pct")
        cps = f"{cp['user']}/{cp['nice']}/{cp['system']}/{cp['idle']}" if cp else ""
        af = f"{s['rss_anon_mb']}/{s['rss_file_mb']}" if "rss_anon_mb" in s else ""
        L.append(f"| {s['utc']} | {s['t_s'] / 60:.1f} | {s['phase']} | {s['rss_mb']} | {af} | {s['hwm_mb']} | "
                 f"{s['fds']} | {s['threads']} | {s['children']} | "
                 f"{num(m, 'ctb_solver_jobs_running')}/{num(m, 'ctb_solver_jobs_queued')} | "
                 f"{num(m, 'ctb_solver_jobs_rejected_total')} | {num(m, 'ctb_connections_open')} | "
                 f"{s.get('server_cpu_cores', '')} | {s.get('client_cpu_cores', '')} | "
                 f"{s.get('other_cpu_cores', '')} | {cps} | "
                 f"{' / '.join(map(str, s['loadavg']))} |")
    under = [x for x in res["samples"] if x["phase"] == "load" and "server_cpu_cores" in x]
    avg = (lambda k: round(sum(x.get(k, 0) for x in under) / len(under), 2)) if under else (lambda k: "?")
    L += ["", "Solver procs: the server's descendant processes (minizinc, fzn-gecode) at the sample. "
          "CPU: the whole machine's split between samples (`nice`: niced work of other users, the "
          "fuzzers at nice 19 and builds at nice 5-10, which the scheduler still gave a large "
          "share). Server CPU includes its reaped solver children; others' CPU is the machine's "
          "busy time minus the server's and the load generator's. Under load the server had on "
          f"average {avg('server_cpu_cores')} cores, the load generator {avg('client_cpu_cores')}, "
          f"other users {avg('other_cpu_cores')} (of {res['cores']}).", "",
          "Busiest processes at the start and at the end of the traffic (`ps --sort=-pcpu`, "
          "lifetime averages):", "", "```"] + res["busiest_processes"]["start"][:6] + ["..."] + \
        res["busiest_processes"]["end"][:6] + ["```", "", "## Verdict", ""]
    L.append(f"- RSS after the warm-up ({v['warmup_min']} min): {v['rss_mb_at_warmup']} MB, at the end "
             f"of the traffic {v['rss_mb_end']} MB: growth {v['rss_growth_mb']:+} MB "
             f"({v['rss_growth_pct']:+}%), least-squares slope after warm-up "
             f"{v['rss_slope_mb_per_min_after_warmup']} MB/min (second half of the run: "
             f"{v.get('rss_slope_mb_per_min_second_half')} MB/min), peak after warm-up "
             f"{v['rss_max_after_warmup_mb']} MB; {v.get('ok_answers_after_warmup')} ok answers after "
             f"the warm-up, {v.get('rss_kb_per_ok_answer_after_warmup')} KB of growth per answer. "
             f"Median of the first 5 minutes after the warm-up {v['rss_median_first_5min_after_warmup_mb']} MB, "
             f"of the last 5 minutes {v['rss_median_last_5min_mb']} MB: {v['rss_median_growth_mb']:+} MB. "
             f"{'No growth' if rss_ok else 'GROWTH'} (threshold on the medians: at most +5 MB or +10%).")
    L.append(f"- Open fds: {v['fds_at_warmup']} after warm-up, {v['fds_end']} at the end, at most "
             f"{v['fds_max_after_warmup']}; threads {v['threads_at_warmup']} / {v['threads_end']} / "
             f"at most {v['threads_max_after_warmup']}. {'No fd growth' if fd_ok else 'FD GROWTH'} "
             "(threshold: +4). Solver processes left 10 s after the traffic: "
             f"{v['children_after_traffic']}.")
    L.append(f"- Unexpected answers: {v['unexpected']}, of which refused inside a stream (200, then "
             f"`event: error` 503 `busy`, no `Retry-After`): {v['in_stream_busy']}. gRPC refusals "
             "with a `google.rpc.RetryInfo` (code, delay: count): "
             f"{v['grpc_refusals_with_retry_info'] or 'none'}.")
    if v["crash"]:
        L.append(f"- **The server died**: {v['crash']}.")
    if v["stuck_client_threads"]:
        L.append(f"- Client threads still waiting {HTTP_TIMEOUT + 10} s after the stop: "
                 f"{v['stuck_client_threads']}.")
    if v["shutdown"]:
        L.append(f"- SIGTERM after the run: exit {v['shutdown']['returncode']} in "
                 f"{v['shutdown']['seconds']} s"
                 + (f" (the wrapper finished {v['shutdown']['wrapper_seconds']} s after the "
                    "signal)" if "wrapper_seconds" in v["shutdown"] else "") + ".")
    L.append(f"- Server log: lines by level {res['server_log']['levels']}; not info: "
             f"{res['server_log']['non_info'] or 'none'}.")
    why = [w for w, bad in (("RSS grew past the threshold", not rss_ok),
                            ("open fds grew", not fd_ok),
                            (f"{v['unexpected']} unexpected answers", v["unexpected"]),
                            ("the server died", v.get("crash")),
                            ("client threads hung", v.get("stuck_client_threads"))) if bad]
    L.append(f"- **Claim {'holds' if v['holds'] else 'does not hold'}**: "
             + ("no growth after warm-up and every refusal a 503 with `Retry-After`"
                if v["holds"] else "; ".join(why))
             + (f" ({v['in_stream_busy']} of them streams refused in-band: 200, then a 503 "
                "`busy` event without a retry hint)" if v["in_stream_busy"] else "") + ".")
    if res["unexpected_examples"]:
        L += ["", "### Unexpected answers (first 5 per route)", ""]
        for e in res["unexpected_examples"]:
            L.append("- `" + json.dumps(e)[:600] + "`")
    if res.get("follow_up_md"):
        L += ["", res["follow_up_md"].rstrip()]
    if res["notes"]:
        L += ["", "### Notes per route", ""]
        for r, d in sorted(res["notes"].items()):
            L.append(f"- {r}: " + ", ".join(f"{k} {n}" for k, n in sorted(d.items())))
    open(path, "w").write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
