#!/usr/bin/env bash
# Black-box test of `ctburton domain check|expand|draw` (docs/domains.md): a template checked,
# expanded with --set, drawn as SVG that an XML parser reads; a broken template's errors point at
# the template and name the instance.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
TEAM=config/templates/search_rescue_team.json

out=$("$BIN" domain check "$TEAM"); rc=$?
[ $rc = 0 ] && [[ "$out" == "valid: search_rescue_team (5 automata, 43 locations, 44 transitions, from templates)" ]] \
  && ok "check template" || bad "check template (rc=$rc): $out"

out=$("$BIN" domain check search_rescue); rc=$?
[ $rc = 0 ] && [[ "$out" == valid:* ]] && ok "check shipped name" || bad "check shipped name (rc=$rc): $out"

"$BIN" domain expand "$TEAM" --set N=4 > "$T/x4.json"; rc=$?
if [ $rc = 0 ] && python3 - "$T/x4.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
names = [a["name"] for a in d["automata"]]
assert names == ["robot1", "robot2", "robot3", "robot4", "door1", "door2", "door3"], names
assert "parameters" not in d
assert d["description"].startswith("4 ground robots"), d["description"]
g = d["automata"][4]["transitions"][0]["guard"]
assert g.count("\\/") == 3 and "robot4l[i]==door1Opening" in g, g
PY
then ok "expand --set N=4"; else bad "expand --set N=4 (rc=$rc)"; fi

# The expansion is a plain domain: it checks, and solves like the generated copies elsewhere.
out=$("$BIN" domain check "$T/x4.json"); rc=$?
[ $rc = 0 ] && [[ "$out" == *"7 automata"* ]] && [[ "$out" != *"from templates"* ]] \
  && ok "expanded file checks" || bad "expanded file checks (rc=$rc): $out"

"$BIN" domain draw "$TEAM" -o "$T/team.svg"; rc=$?
if [ $rc = 0 ] && python3 - "$T/team.svg" <<'PY'
import sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "{http://www.w3.org/2000/svg}svg", root.tag
texts = {"".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text")}
for name in ["automaton robot1", "automaton robot2", "automaton door1", "automaton door3",
             "outside", "rescuedPerson2", "closed", "after 4 s"]:
    assert name in texts, name
PY
then ok "draw: well-formed SVG naming everything"; else bad "draw (rc=$rc)"; fi

# A broken template: one error per instance, at the template's pointer.
python3 - "$TEAM" "$T/broken.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["automata"][0]["transitions"][0]["guard"] = "{self}u[i]==goToDoor1 /\\ robot{k+1}l[i]!=atDoor1"
json.dump(d, open(sys.argv[2], "w"))
PY
out=$("$BIN" domain check "$T/broken.json" --set N=3); rc=$?
[ $rc = 1 ] && [[ "$out" == *"/automata/0/transitions/0/guard: in instance 'robot3' (k=3): "*"robot4"* ]] \
  && [[ "$(echo "$out" | grep -c '^/automata/')" == 1 ]] \
  && ok "broken template: located, instance named" || bad "broken template (rc=$rc): $out"

out=$("$BIN" domain check "$TEAM" --set M=3); rc=$?
[ $rc = 1 ] && [[ "$out" == *"/parameters: no parameter 'M' to set"* ]] && ok "unknown --set" || bad "unknown --set (rc=$rc): $out"

"$BIN" domain check "$TEAM" --set N=x >/dev/null 2>&1; rc=$?
[ $rc = 2 ] && ok "bad --set is a usage error" || bad "bad --set (rc=$rc)"

# domain draft through the application core, against a loopback mock of the chat-completions
# endpoint that answers every request with one recorded draft (good, or broken for ever).
mock() {  # mock ANSWER_FILE PORT_FILE: serves until killed
  python3 - "$1" "$2" <<'PY' &
import http.server, json, sys
answer = open(sys.argv[1]).read()
class H(http.server.BaseHTTPRequestHandler):
    def do_POST(self):
        self.rfile.read(int(self.headers.get("Content-Length", 0)))
        body = json.dumps({"id": "x", "object": "chat.completion", "model": "m",
                           "choices": [{"index": 0, "finish_reason": "stop",
                                        "message": {"role": "assistant", "content": answer}}],
                           "usage": {"prompt_tokens": 1, "completion_tokens": 1, "total_tokens": 2}}).encode()
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)
    def log_message(self, *a): pass
s = http.server.HTTPServer(("127.0.0.1", 0), H)
open(sys.argv[2] + ".tmp", "w").write(str(s.server_port))
import os; os.rename(sys.argv[2] + ".tmp", sys.argv[2])
s.serve_forever()
PY
  MOCK=$!
  for _ in $(seq 100); do [ -s "$2" ] && break; sleep 0.05; done
}
WORDS="two drones that take off from a hangar and fly to A or B"
mock tests/recordings/draft/good.txt "$T/port1"
CTB_LLM_BASE_URL=http://127.0.0.1:$(cat "$T/port1")/v1 CTB_LLM_API_KEY=k CTB_LLM_MODEL=m \
  "$BIN" domain draft "$WORDS" --out "$T/drafted.json" > "$T/draft.json" 2> "$T/draft.err"; rc=$?
kill $MOCK
if [ $rc = 0 ] && python3 -c "
import json; d = json.load(open('$T/draft.json'))
assert d['action_model']['name'] == 'hangar_drones', d
assert 'restatement' in d and isinstance(d['questions'], list), d" \
  && [[ "$("$BIN" domain check "$T/drafted.json")" == "valid: hangar_drones"* ]]; then
  ok "draft through the core: printed, written, loads"
else bad "draft (rc=$rc): $(cat "$T/draft.err")"; fi
mock tests/recordings/draft/broken.txt "$T/port2"
CTB_LLM_BASE_URL=http://127.0.0.1:$(cat "$T/port2")/v1 CTB_LLM_API_KEY=k CTB_LLM_MODEL=m \
  "$BIN" domain draft "$WORDS" --max-repairs 1 > /dev/null 2> "$T/broken.err"; rc=$?
kill $MOCK
[ $rc = 4 ] && grep -q '^/automata/' "$T/broken.err" && ! grep -q '^/action_model' "$T/broken.err" \
  && ok "broken draft: exit 4, errors located in the model" || bad "broken draft (rc=$rc): $(cat "$T/broken.err")"

echo "$fail failure(s)"
[ $fail = 0 ]
