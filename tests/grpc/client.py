"""A ctburton gRPC client in Python (the README shows its first lines). Run by
tests/grpc/python_client_test.sh: each check raises on a wrong answer."""
import json
import sys
import time
import urllib.request

import grpc
from google.protobuf import json_format

from ctburton.v1 import planner_pb2, planner_pb2_grpc
from google.rpc import error_details_pb2, status_pb2

target, src = sys.argv[1], sys.argv[2]
http = sys.argv[3] if len(sys.argv) > 3 else None  # the same server's HTTP front end
channel = grpc.insecure_channel(target)
grpc.channel_ready_future(channel).result(timeout=20)
planner = planner_pb2_grpc.PlannerStub(channel)


def state_plan(path):
    with open(f"{src}/{path}") as f:
        return json_format.ParseDict(json.load(f), planner_pb2.StatePlan())


def check(cond, what):
    if not cond:
        raise SystemExit(f"FAIL: {what}")
    print(f"ok: {what}")


# The domains the server knows.
domains = planner.ListDomains(planner_pb2.ListDomainsRequest(), timeout=10)
check({d.name for d in domains.domains} == {"presentation", "search_rescue", "assembly"},
      "ListDomains lists the three shipped domains")

# Solve a state plan (the thesis' test prompt 1), fastest.
request = planner_pb2.SolveRequest(
    domain="presentation",
    state_plan=state_plan("config/examples/presentation/test1_cot.json"),
    options=planner_pb2.Options(objective="makespan", time_limit_ms=30000))
result = planner.Solve(request, timeout=60)
check(result.status == planner_pb2.SOLVED_OPTIMALLY, "Solve answers SOLVED_OPTIMALLY")
check(result.trajectory.verified, "the trajectory is verified")
check(result.objective.number_value == result.trajectory.goal_reached_at,
      "the objective is the goal time")
first = result.trajectory.transitions[0]
check(first.time == 0 and first.HasField("command"), "the first transition is a command at 0 s")

# The same, streaming: INTERMEDIATE results, then the final one.
statuses = [r.status for r in planner.SolveAnytime(request, timeout=60)]
check(statuses[-1] == planner_pb2.SOLVED_OPTIMALLY and
      all(s == planner_pb2.INTERMEDIATE for s in statuses[:-1]),
      f"SolveAnytime streams {len(statuses) - 1} INTERMEDIATE result(s), then the answer")

# A bad state plan: INVALID_ARGUMENT with a BadRequest naming the JSON pointer.
bad = planner_pb2.SolveRequest(domain="presentation",
                               state_plan=state_plan("config/examples/presentation/test1_cot.json"))
bad.state_plan.end_state.goal_constraint = "projl[i+1]==projOnn"
try:
    planner.Validate(bad, timeout=10)
    check(False, "Validate refuses a bad state plan")
except grpc.RpcError as e:
    check(e.code() == grpc.StatusCode.INVALID_ARGUMENT, "Validate answers INVALID_ARGUMENT")
    details = dict(e.trailing_metadata()).get("grpc-status-details-bin")
    status = status_pb2.Status.FromString(details)
    violation = error_details_pb2.BadRequest()
    status.details[0].Unpack(violation)
    fields = [v.field for v in violation.field_violations]
    check("/state_plan/end_state/goal_constraint" in fields, f"the error names {fields}")

# Natural language, from the shipped recordings (--demo), streamed.
command = ("The computer and projector start in the off state, and the connection is "
           "disconnected. The projector should turn on and stay on for 1800 seconds, following "
           "which everything should turn off within 600 seconds. In addition, the projector "
           "should turn on within 60 seconds.")
t0 = time.time()
final = list(planner.PlanAnytime(planner_pb2.PlanRequest(domain="presentation", command=command),
                                 timeout=90))[-1]
check(final.status in (planner_pb2.SOLVED_OPTIMALLY, planner_pb2.SOLVED_SATISFICING) and
      final.session and final.state_plan.initial_state["proj"] == "projOff",
      f"PlanAnytime plans from words in {time.time() - t0:.1f} s (session {final.session[:8]}...)")
session = planner.GetSession(planner_pb2.GetSessionRequest(session=final.session), timeout=10)
check(len(session.turns.values) == 1, "the session holds the turn")

# Replanning (contract section 11): robot 1 stands at door 1 at t = 1 and cannot open it; robot 2
# comes to open it, and the goal moves from 11 to 12. The same request to POST /replan gives the
# same plan.
with open(f"{src}/config/examples/search_rescue/test2.json") as f:
    rescue = json.load(f)
plan = planner.Solve(planner_pb2.SolveRequest(
    domain="search_rescue", state_plan=state_plan("config/examples/search_rescue/test2.json"),
    options=planner_pb2.Options(objective="makespan", time_limit_ms=30000)), timeout=60)
body = {
    "domain": "search_rescue", "state_plan": rescue, "now": 1,
    "trajectory": {"events": list(plan.trajectory.events),
                   "transitions": [{"time": t.time, "automaton": t.automaton,
                                    "from": getattr(t, "from"), "to": t.to}
                                   for t in plan.trajectory.transitions]},
    "executed": [{"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
                 {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}],
    "blocked": [{"automaton": "robot1", "from": "atDoor1", "to": "door1Opening"}],
    "options": {"objective": "cost_then_makespan", "time_limit_ms": 30000},  # one optimal future
}
replanned = planner.Replan(json_format.ParseDict(body, planner_pb2.ReplanRequest()), timeout=60)
future = [(t.automaton, getattr(t, "from"), t.to) for t in replanned.trajectory.transitions
          if not t.executed]
check(replanned.status == planner_pb2.SOLVED_OPTIMALLY and replanned.trajectory.verified and
      replanned.trajectory.goal_reached_at == 12 and
      ("robot2", "atDoor1", "door1Opening") in future and
      ("robot1", "atDoor1", "door1Opening") not in future,
      "Replan: robot 2 comes to open door 1, goal at 12 s")
check(any(d.automaton == "robot1" and d.command == "openDoor1" for d in replanned.diff.dropped),
      "Replan's diff drops robot 1's openDoor1")
if http:
    request = urllib.request.Request(f"{http}/replan", json.dumps(body).encode(),
                                     {"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=60) as r:
        answer = json.load(r)
    as_http = [(t["automaton"], t["from"], t["to"], t["time"], t.get("executed", False))
               for t in answer["transitions"]]
    as_grpc = [(t.automaton, getattr(t, "from"), t.to, t.time, t.executed)
               for t in replanned.trajectory.transitions]
    check(as_http == as_grpc and answer["goal_reached_at"] == replanned.trajectory.goal_reached_at,
          "POST /replan gives the same plan as gRPC Replan")
