#!/usr/bin/env bash
# The same request through HTTP and through the CLI gives the same bytes (issue 31): `ctburton
# solve --compact` and `ctburton replan --compact` against POST /solve and POST /replan of a real
# `ctburton serve`, with the same options. Both go through the application core once and are
# written by one serializer (WireText). Only durations differ between two runs, so every number
# under a key that names a duration ("..._ms", "ms") is set to 0 in both texts before the
# comparison; nothing else is touched, and the test checks that some were there to mask.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'kill $SERVER 2>/dev/null; rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }

. "$SRC/tests/cli/serve.sh"
start_server "$T/data" "$T/serve.log"

post() {  # post PATH BODY_FILE OUT_FILE: the raw answer body
  python3 - "$PORT" "$1" "$2" "$3" <<'PY'
import sys, urllib.request, urllib.error
port, path, body, out = sys.argv[1:]
req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", data=open(body, "rb").read(),
                             headers={"Content-Type": "application/json"})
try:
    raw = urllib.request.urlopen(req, timeout=120).read()
except urllib.error.HTTPError as e:
    raw = e.read()
open(out, "wb").write(raw)
PY
}

same() {  # same NAME CLI_FILE HTTP_FILE
  python3 - "$2" "$3" <<'PY'
import re, sys
texts = [open(p, "rb").read().rstrip(b"\n") for p in sys.argv[1:]]
duration = re.compile(rb'("(?:[a-z_]*_ms|ms)":)-?[0-9][0-9.eE+-]*')
masked = [duration.subn(rb"\g<1>0", t) for t in texts]
assert masked[0][1] > 0, "no duration to mask: the answer's shape changed"
assert masked[0][1] == masked[1][1], (masked[0][1], masked[1][1])
if masked[0][0] != masked[1][0]:
    a, b = masked[0][0], masked[1][0]
    i = next((k for k in range(min(len(a), len(b))) if a[k] != b[k]), min(len(a), len(b)))
    sys.exit(f"differ at byte {i}:\n cli:  {a[max(0, i - 80):i + 80]!r}\n http: {b[max(0, i - 80):i + 80]!r}")
PY
  if [ $? = 0 ]; then ok "$1"; else bad "$1"; fi
}

OPTS='{"time_limit_ms": 20000, "max_horizon": 32, "objective": "makespan"}'
for ex in presentation/test1_cot search_rescue/test1 assembly/test presentation/impossible_off_within59; do
  d=${ex%%/*}
  f=config/examples/$ex.json
  "$BIN" solve --domain "$d" "$f" --compact --time-limit-ms 20000 --max-horizon 32 --objective makespan \
    > "$T/cli.json" 2> "$T/cli.err" || { bad "solve $ex: the CLI failed: $(cat "$T/cli.err")"; continue; }
  python3 -c "import json,sys; print(json.dumps({'domain': sys.argv[1], 'state_plan': json.load(open(sys.argv[2])), 'options': json.loads(sys.argv[3])}))" \
    "$d" "$f" "$OPTS" > "$T/body.json"
  post /solve "$T/body.json" "$T/http.json"
  same "solve $ex: CLI and HTTP give the same bytes" "$T/cli.json" "$T/http.json"
done

# A replan of the presentation plan at t = 30 from the plan being executed (its history taken
# from the trajectory), and one that must fail at a pointer: the same bytes again.
f=config/examples/presentation/test1_cot.json
"$BIN" solve --domain presentation "$f" --compact > "$T/plan.json" 2>/dev/null
"$BIN" replan --domain presentation "$f" --trajectory "$T/plan.json" --now 30 --compact \
  --time-limit-ms 20000 --max-horizon 32 > "$T/cli.json" 2> "$T/cli.err" || bad "replan: the CLI failed: $(cat "$T/cli.err")"
python3 -c "import json,sys; print(json.dumps({'domain': 'presentation', 'state_plan': json.load(open(sys.argv[1])), 'trajectory': json.load(open(sys.argv[2])), 'now': 30, 'options': {'time_limit_ms': 20000, 'max_horizon': 32}}))" \
  "$f" "$T/plan.json" > "$T/body.json"
post /replan "$T/body.json" "$T/http.json"
same "replan at t = 30: CLI and HTTP give the same bytes" "$T/cli.json" "$T/http.json"
python3 -c "import json; a=json.load(open('$T/http.json')); assert a['status'] == 'optimal' and a['now'] == 30, a" \
  && ok "the replan is optimal from t = 30" || bad "replan answer: $(head -c 300 "$T/http.json")"

echo "$fail failure(s)"
[ $fail = 0 ]
