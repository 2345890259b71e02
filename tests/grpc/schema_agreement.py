"""The OpenAPI document and the proto agree on every field they share (issue 19): each pair of
an OpenAPI schema and the proto message that carries the same JSON is walked together, and every
property on one side must be a field on the other, except where the table below says where it
lives instead. Run by tests/grpc/python_client_test.sh with the generated stubs on PYTHONPATH."""
import json
import sys

from ctburton.v1 import planner_pb2 as pb

doc = json.load(open(sys.argv[1]))
S = doc["components"]["schemas"]

# Deliberate differences, each with where the field is on the other side.
ELSEWHERE = {
    ("Trajectory", "bound"): "PlanResult.bound",
    ("Trajectory", "state_plan_summary"): "PlanResult.state_plan_summary",
    ("Trajectory", "explanation"): "PlanResult.explanation",
    ("SolveRequest", "stream"): "the SolveAnytime method",
    ("PlanRequest", "stream"): "the PlanAnytime method",
    ("SolveRequest", "action_model"): "the oneof model",
    ("Trajectory", "session"): "PlanResult.session",
    ("Trajectory", "diff"): "PlanResult.diff",
    ("Trajectory", "report"): "PlanResult.report",
}


def resolve(s):
    while "$ref" in s:
        s = S[s["$ref"].split("/")[-1]]
    for k in ("oneOf", "anyOf"):
        if k in s:
            objs = [resolve(x) for x in s[k] if resolve(x).get("type") == "object"]
            if objs:
                return objs[0]
    return s


problems = []


def walk(name, schema, desc, seen):
    schema = resolve(schema)
    if (name, desc.full_name) in seen:
        return
    seen.add((name, desc.full_name))
    props = schema.get("properties", {})
    fields = {f.name: f for f in desc.fields}
    for p, ps in props.items():
        if (name, p) in ELSEWHERE:
            continue
        if p not in fields:
            problems.append(f"{name}.{p} (OpenAPI) is not a field of {desc.full_name}")
            continue
        f = fields[p]
        if f.message_type is None or f.message_type.full_name.startswith("google.protobuf"):
            continue
        ps = resolve(ps)
        if f.message_type.GetOptions().map_entry:
            value = f.message_type.fields_by_name["value"].message_type
            inner = resolve(ps.get("additionalProperties", {}))
            if value is not None and not value.full_name.startswith("google.protobuf"):
                if inner.get("type") == "array":  # a wrapper message (Timeline.segments)
                    walk(f"{name}.{p}[]", inner["items"], value.fields[0].message_type, seen)
                else:
                    walk(f"{name}.{p}{{}}", inner, value, seen)
        elif ps.get("type") == "array":
            walk(f"{name}.{p}[]", ps.get("items", {}), f.message_type, seen)
        else:
            walk(f"{name}.{p}", ps, f.message_type, seen)
    if props and schema.get("additionalProperties") is False:
        for f in fields:
            if f not in props and (name, f) not in ELSEWHERE:
                problems.append(f"{desc.full_name}.{f} (proto) is not a property of {name}")


pairs = [("Options", pb.Options), ("StatePlan", pb.StatePlan), ("ActionModel", pb.ActionModel),
         ("Trajectory", pb.Trajectory), ("Explanation", pb.Explanation), ("Warning", pb.Warning),
         ("SessionView", pb.Session), ("TranslateAnswer", pb.TranslateResult),
         ("SolveRequest", pb.SolveRequest), ("PlanRequest", pb.PlanRequest)]
seen = set()
for name, msg in pairs:
    walk(name, S[name], msg.DESCRIPTOR, seen)
summary = resolve(S["StatePlanSummary"])["items"]
walk("StatePlanSummary[]", summary, pb.SummaryLine.DESCRIPTOR, seen)
if problems:
    print("\n".join(problems))
    raise SystemExit(f"FAIL: {len(problems)} disagreement(s) between server/openapi.json and the proto")
print(f"ok: server/openapi.json and planner.proto agree ({len(seen)} schema/message pairs walked)")
