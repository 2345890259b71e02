#!/usr/bin/env bash
# Black-box test of `ctburton eval` offline (contract section 15): the shipped suite of the
# thesis' test prompts replayed from the shipped recordings, its lines and totals, and what a
# reference that means something else turns into.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }

CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite config/eval/thesis.json --prompting cot --json > "$T/out.txt" 2> "$T/err.txt"
rc=$?
if [ $rc = 0 ] && python3 - "$T/out.txt" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
items, totals = lines[:-1], lines[-1]
assert len(items) == 8, lines
for l in items:
    assert set(l) >= {"item", "domain", "parsed", "valid", "solvable", "verdict", "ms", "tokens"}, l
    assert l["verdict"] == "equivalent", l
assert totals == {"items": 8, "equivalent": 8, "not_equivalent": 0, "unparsed": 0, "invalid": 0, "unknown": 0}, totals
PY
then ok "the shipped suite replayed: 8 equivalent"; else bad "thesis suite (rc=$rc)"; cat "$T/out.txt" "$T/err.txt"; fi

# Rates printed without --json; the direct answers: the thesis' answer to presentation test
# prompt 2 is infeasible where its reference is not.
CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite config/eval/thesis.json --prompting direct > "$T/out.txt" 2> "$T/err.txt"
grep -q "^item 1 (presentation): not_equivalent" "$T/out.txt" && grep -q "equivalent 7 (88 %), not equivalent 1 (12 %)" "$T/out.txt" \
  && ok "direct: 7 equivalent, 1 not" || { bad "direct"; cat "$T/out.txt" "$T/err.txt"; }

CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite config/eval/thesis.json --prompting cot > "$T/out.txt" 2> "$T/err.txt"
grep -q "^items 8: parsed 8 (100 %), valid 8 (100 %), solvable 8 (100 %), equivalent 8 (100 %)" "$T/out.txt" \
  && ok "rates printed" || { bad "rates printed"; cat "$T/out.txt"; }

# A reference that asks for another person: the recorded translation is not equivalent.
python3 - <<'PY' > "$T/other.json"
import json
s = json.load(open("config/eval/thesis.json"))
item = s[3]
item["reference"]["end_state"]["goal_constraint"] = item["reference"]["end_state"]["goal_constraint"].replace("rescuedPerson1", "rescuedPerson2")
print(json.dumps([item]))
PY
CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite "$T/other.json" --prompting cot --json > "$T/out.txt" 2> "$T/err.txt"
head -1 "$T/out.txt" | grep -q '"verdict":"not_equivalent"' && ok "another goal: not equivalent" || { bad "another goal"; cat "$T/out.txt" "$T/err.txt"; }

# A reference that forbids what the translation's plan does (robot 1 opening door 1): not
# equivalent (found by a review: the check of one plan against the other state plan fixes the run
# as a history, where forbidden actions were not read).
python3 - <<'PY' > "$T/forbid.json"
import json
item = json.load(open("config/eval/thesis.json"))[3]
item["reference"].setdefault("constraints", {})
item["reference"]["constraints"]["actions"] = {"R1OpensDoor1": {"automaton": "robot1", "command": "openDoor1"}}
item["reference"]["constraints"]["forbidden"] = ["R1OpensDoor1"]
print(json.dumps([item]))
PY
CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite "$T/forbid.json" --prompting cot --json > "$T/out.txt" 2> "$T/err.txt"
head -1 "$T/out.txt" | grep -q '"verdict":"not_equivalent"' && ok "a forbidden action in the reference: not equivalent" || { bad "forbidden in the reference"; cat "$T/out.txt" "$T/err.txt"; }

# A suite that is not a list, and a reference that does not load: exit 1 with the pointer.
echo '{"domain": "presentation"}' > "$T/bad.json"
"$BIN" eval --suite "$T/bad.json" > /dev/null 2> "$T/err.txt"
[ $? = 1 ] && ok "not a list: exit 1" || bad "not a list"
python3 -c "
import json; s=json.load(open('config/eval/thesis.json'))[:1]; s[0]['reference']['initial_state']['comp']='compOf'
print(json.dumps(s))" > "$T/bad.json"
CTB_LLM_REPLAY=tests/recordings/thesis "$BIN" eval --suite "$T/bad.json" > /dev/null 2> "$T/err.txt"
rc=$?
[ $rc = 1 ] && grep -q "/0/reference/initial_state/comp" "$T/err.txt" && ok "bad reference: exit 1 at its pointer" || { bad "bad reference (rc=$rc)"; cat "$T/err.txt"; }

echo "$((fail == 0 ? 1 : 0)) passed, $fail failed"
[ "$fail" = 0 ]
