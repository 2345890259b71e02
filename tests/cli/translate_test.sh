#!/usr/bin/env bash
# Black-box test of `ctburton translate` offline, from the shipped recordings.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
TP1="The computer and projector start in the off state, and the connection is disconnected. The projector should turn on and stay on for 1800 seconds, following which everything should turn off within 600 seconds. In addition, the projector should turn on within 60 seconds."

CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" translate --domain presentation "$TP1" > "$T/out.json" 2> "$T/err.txt"
rc=$?
if [ $rc = 0 ] && python3 -c "
import json,sys; t=json.load(open('$T/out.json'))
assert 'ProjectorOnWithin60' in t['state_plan']['constraints']['temporal']
assert t['reasoning'].startswith('Initial State')" ; then ok "replayed chain of thought"; else bad "replayed chain of thought (rc=$rc)"; cat "$T/err.txt"; fi

CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" translate --domain presentation --prompting direct "$TP1" > "$T/out.json" 2> "$T/err.txt"
[ $? = 0 ] && grep -q '"repairs": 1' "$T/out.json" && ok "replayed direct with its repair" || bad "replayed direct"

env -u CTB_LLM_BASE_URL -u CTB_LLM_REPLAY "$BIN" translate --domain presentation "$TP1" > /dev/null 2> "$T/err.txt"
rc=$?
[ $rc = 3 ] && grep -q "no LLM endpoint configured: set CTB_LLM_BASE_URL" "$T/err.txt" && ok "no endpoint: exit 3 with how to configure" || bad "no endpoint (rc=$rc)"

CTB_LLM_BASE_URL=http://127.0.0.1:1/v1 CTB_LLM_TIMEOUT_MS=500 "$BIN" translate --domain presentation "$TP1" > /dev/null 2> "$T/err.txt"
rc=$?
[ $rc = 3 ] && grep -q "cannot reach the LLM endpoint" "$T/err.txt" && ok "unreachable endpoint: exit 3" || bad "unreachable endpoint (rc=$rc)"

CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" translate --domain presentation "something never recorded" > /dev/null 2> "$T/err.txt"
rc=$?
[ $rc = 3 ] && grep -q "no recorded LLM answer" "$T/err.txt" && ok "replay miss: exit 3" || bad "replay miss (rc=$rc)"

echo "$((fail == 0 ? 1 : 0)) passed, $fail failed"
[ "$fail" = 0 ]
