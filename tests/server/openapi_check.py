#!/usr/bin/env python3
"""Checks recorded HTTP answers against server/openapi.json (issue 13: the document cannot drift).

Usage: openapi_check.py OPENAPI.json ANSWERS.jsonl
Each line: {"method", "path", "status", "content_type", "body"}. The path is matched against the
document's path templates; the status must be documented for that operation; a JSON body must
validate against the schema of that status and media type (JSON Schema 2020-12, python3-jsonschema).
A text/event-stream body is split into its events; each event's name must be one the media type
lists in `x-events`, and its data must validate against the schema given there (a last, unfinished
event, from a client that hung up, is skipped).
Exit 0 when every answer conforms, 1 otherwise (each problem printed).
"""
import json
import re
import sys

import jsonschema


def template_regex(t):
    parts = re.split(r"\{[^}]+\}", t)
    return re.compile("^" + "[^/]+".join(re.escape(p) for p in parts) + "$")


def main():
    doc = json.load(open(sys.argv[1]))
    defs = doc["components"]["schemas"]
    # Refs to components become refs into $defs of one self-contained schema.
    defs_text = json.dumps(defs).replace("#/components/schemas/", "#/$defs/")
    defs = json.loads(defs_text)
    # A literal path before a template that also matches it ("/executions" before "/{file}").
    paths = sorted(((template_regex(t), t, ops) for t, ops in doc["paths"].items()),
                   key=lambda p: p[1].count("{"))
    problems = checked = 0
    for n, line in enumerate(open(sys.argv[2]), 1):
        if not line.strip():
            continue
        a = json.loads(line)
        path = a["path"].split("?")[0]
        where = f"{a['method']} {path[:80]} -> {a['status']}"
        ops = next((ops for rx, t, ops in paths if rx.match(path)), None)
        if ops is None or a["method"].lower() not in ops:
            # Unknown routes are answered 404 (or refused earlier: 408/414/431/503); the error
            # shape is still the document's.
            op = {"responses": {"404": doc["paths"]["/solve"]["post"]["responses"]["404"]}}
            for s in ("400", "408", "411", "413", "414", "431", "503"):
                op["responses"][s] = doc["paths"]["/solve"]["post"]["responses"][s]
        else:
            op = ops[a["method"].lower()]
        resp = op["responses"].get(str(a["status"]))
        if resp is None:
            print(f"{where}: status not documented")
            problems += 1
            continue
        ctype = (a.get("content_type") or "").split(";")[0].strip()
        if "content" not in resp:
            if a["body"]:
                print(f"{where}: a body where the document has none")
                problems += 1
            checked += 1
            continue
        media = resp["content"].get(ctype)
        if media is None:
            print(f"{where}: content type {ctype!r} not documented ({list(resp['content'])})")
            problems += 1
            continue
        checked += 1

        def validate(schema, value, where):
            schema = json.loads(json.dumps(schema).replace("#/components/schemas/", "#/$defs/"))
            schema = {"$schema": "https://json-schema.org/draft/2020-12/schema", "$defs": defs, **schema}
            errors = list(jsonschema.Draft202012Validator(schema).iter_errors(value))
            for e in errors[:3]:
                print(f"{where}: {'/'.join(map(str, e.absolute_path))}: {e.message[:200]}")
            return bool(errors)

        if ctype == "text/event-stream":
            events = media.get("x-events")
            if events is None:
                print(f"{where}: no x-events for the event stream")
                problems += 1
                continue
            frames = a["body"].split("\n\n")
            bad = False
            for k, frame in enumerate(frames[:-1]):  # the last is unfinished (or empty)
                name, data = "message", ""
                for l in frame.split("\n"):
                    if l.startswith("event: "):
                        name = l[7:]
                    elif l.startswith("data: "):
                        data += l[6:]
                if name not in events:
                    print(f"{where}: event {k} {name!r} not documented ({list(events)})")
                    bad = True
                    continue
                try:
                    value = json.loads(data)
                except ValueError as e:
                    print(f"{where}: event {k} {name!r}: data is not JSON: {e}")
                    bad = True
                    continue
                bad |= validate(events[name], value, f"{where} event {k} {name!r}")
            problems += bad
            continue
        if ctype != "application/json":
            continue
        try:
            body = json.loads(a["body"])
        except ValueError as e:
            print(f"{where}: body is not JSON: {e}")
            problems += 1
            continue
        problems += validate(media["schema"], body, where)
    print(f"{checked} answers checked, {problems} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
