#!/usr/bin/env bash
# The shipped 60-command eval suite (config/eval/commands.json, written by
# tools/make_eval_suite.py) replayed offline: every reference loads, solves and is decided within
# the time limit (120 s a solve: a bound, not a speed test; alone the whole suite takes about 30 s
# and its slowest item about 6 s, but a stress run at -j4 on 2 cores was measured six times
# slower: 30 s cut two proofs short), and its "recorded" answer (the reference itself, tests/recordings/suite: not a
# model's answer) comes out equivalent. A changed suite or prompt without regenerated recordings
# fails here (unknown: no recorded answer).
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
CTB_LLM_REPLAY=tests/recordings/suite "$BIN" eval --suite config/eval/commands.json --prompting direct \
  --time-limit-ms 120000 --json > "$T/out.txt" 2> "$T/err.txt"
rc=$?
if [ $rc = 0 ] && python3 - "$T/out.txt" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
items, totals = lines[:-1], lines[-1]
assert len(items) >= 60, len(items)
bad = [l for l in items if l["verdict"] != "equivalent"]
assert not bad, bad[:3]
assert totals["items"] == len(items) and totals["equivalent"] == len(items), totals
print(f"ok   {len(items)} commands over "
      f"{len(set(l['domain'] for l in items))} domains replayed: all equivalent, "
      f"{sum(not l['solvable'] for l in items)} impossible by design")
PY
then echo "1 passed, 0 failed"; else echo "FAIL the 60-command suite (rc=$rc)"; tail -5 "$T/out.txt"; cat "$T/err.txt"; exit 1; fi
