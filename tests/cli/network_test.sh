#!/usr/bin/env bash
# Black-box test of `ctburton network check FILE` (contract section 13): the answer JSON with
# exit 0, located errors with exit 1.
set -u
BIN=$1
SRC=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }

# A ==[1,3]==> C, C -[0,1]-> B: dynamic (B the moment C is seen), not strong.
cat > "$T/dc.json" <<'JSON'
{"points": ["A", "B", "C"],
 "links": [{"from": "A", "to": "C", "lb": 1, "ub": 3, "contingent": true},
           {"from": "C", "to": "B", "lb": 0, "ub": 1}]}
JSON
out=$("$BIN" network check "$T/dc.json" 2> "$T/err.txt"); rc=$?
[ $rc = 0 ] && ok "dc: exit 0" || { bad "dc: exit $rc"; cat "$T/err.txt"; }
python3 -c '
import json, sys
a = json.loads(sys.argv[1])
assert a["consistent"] is True and a["strong"] is False and a["dynamic"] is True, a
assert "conflict" not in a and a["ms"] >= 0, a' "$out" && ok "dc: consistent, not strong, dynamic" || bad "dc answer: $out"

# C -[-2,-1]-> B instead: B must precede C, unseen: not dynamic, conflict = both links.
sed 's/"lb": 0, "ub": 1/"lb": -2, "ub": -1/' "$T/dc.json" > "$T/not.json"
out=$("$BIN" network check "$T/not.json"); rc=$?
[ $rc = 0 ] && ok "not dc: exit 0" || bad "not dc: exit $rc"
python3 -c '
import json, sys
a = json.loads(sys.argv[1])
assert a["dynamic"] is False and a["strong"] is False and a["consistent"] is True, a
assert a["conflict"] == [0, 1], a' "$out" && ok "not dc: conflict [0, 1]" || bad "not dc answer: $out"

# Errors at their pointers, exit 1.
cat > "$T/bad.json" <<'JSON'
{"points": ["start", "end"], "links": [{"from": "start", "to": "edn", "lb": 0}, {"from": "start", "to": "end", "lb": 1, "ub": 0}]}
JSON
"$BIN" network check "$T/bad.json" > /dev/null 2> "$T/err.txt"; rc=$?
[ $rc = 1 ] && ok "bad: exit 1" || bad "bad: exit $rc"
grep -q "/links/0/to: unknown point 'edn' (did you mean 'end'?)" "$T/err.txt" && ok "bad: unknown point located" || { bad "bad: unknown point"; cat "$T/err.txt"; }
grep -q "/links/1/ub: ub is below lb" "$T/err.txt" && ok "bad: ub below lb located" || { bad "bad: ub below lb"; cat "$T/err.txt"; }
"$BIN" network check "$T/missing.json" > /dev/null 2>&1; rc=$?
[ $rc = 1 ] && ok "missing file: exit 1" || bad "missing file: exit $rc"

echo "$((fail == 0 ? 1 : 0)) passed, $fail failed"
[ "$fail" = 0 ]
