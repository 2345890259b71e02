"""A ctburton gRPC client in Python (the README shows its first lines). Run by
tests/grpc/python_client_test.sh: each check raises on a wrong answer."""
import json
import sys
import time

import grpc
from google.protobuf import json_format

from ctburton.v1 import planner_pb2, planner_pb2_grpc
from google.rpc import error_details_pb2, status_pb2

target, src = sys.argv[1], sys.argv[2]
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
