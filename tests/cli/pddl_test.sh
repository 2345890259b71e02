#!/usr/bin/env bash
# Black-box test of `ctburton domain import-pddl` (docs/domains.md, "Importing PDDL"): the PDDL
# search_rescue imported with its problem, checked by `domain check`, solved by `solve` to the
# shipped domain's optimum and written back with `solve --pddl-plan`; a domain without a problem;
# an action changing two state variables; bad usage.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
P=tests/interchange/pddl

out=$("$BIN" domain import-pddl $P/search_rescue_domain.pddl $P/search_rescue_problem.pddl \
      -o "$T/sr.json" --state-plan-out "$T/plan.json" 2>"$T/err"); rc=$?
[ $rc = 0 ] && [[ "$out" == "imported: search_rescue (5 automata, 39 locations, 40 transitions from 22 ground actions)" ]] \
  && [ ! -s "$T/err" ] && ok "import with a problem" || bad "import (rc=$rc): $out $(cat "$T/err")"

out=$("$BIN" domain check "$T/sr.json"); rc=$?
[ $rc = 0 ] && [[ "$out" == "valid: search_rescue (5 automata, 39 locations, 40 transitions)" ]] \
  && ok "imported domain checks" || bad "domain check (rc=$rc): $out"

"$BIN" solve --domain "$T/sr.json" "$T/plan.json" > "$T/t.json"; rc=$?
if [ $rc = 0 ] && python3 - "$T/t.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
assert t["status"] == "optimal", t["status"]
assert t["verified"] is True
assert t["objective"] == {"kind": "makespan", "value": 11}, t["objective"]
ends = {tr["automaton"]: tr["to"] for tr in t["transitions"] if tr["automaton"].startswith("robot")}
assert sorted([ends["robot1"], ends["robot2"]]) == ["person1", "person2"], ends
PY
then ok "solve: optimal makespan 11"; else bad "solve (rc=$rc)"; fi

# The same solve written back as a PDDL 2.1 plan: 11 s, one robot opening door 1, both through it.
"$BIN" solve --domain "$T/sr.json" "$T/plan.json" --pddl $P/search_rescue_domain.pddl \
  $P/search_rescue_problem.pddl --pddl-plan "$T/out.plan" > /dev/null; rc=$?
if [ $rc = 0 ] && python3 - "$T/out.plan" <<'PY'
import re, sys
lines = open(sys.argv[1]).read().splitlines()
acts = [re.fullmatch(r"(\d+\.\d{3}): \(([a-z0-9 -]+)\)( \[(\d+\.\d{3})\])?", l) for l in lines]
assert all(acts), lines
names = [a.group(2).split()[0] for a in acts]
assert names.count("open-door") == 1 and names.count("pass") == 2, lines
ends = [float(a.group(1)) + float(a.group(4) or 0) for a in acts]
assert max(ends) == 11.0, lines
times = [float(a.group(1)) for a in acts]
assert times == sorted(times), lines
assert any(l.startswith("0.000: (drive robot") and l.endswith("[1.000]") for l in lines), lines
PY
then ok "solve --pddl-plan: a PDDL 2.1 plan ending at 11 s"; else bad "--pddl-plan (rc=$rc) $(cat "$T/out.plan")"; fi

# Without --domain, --pddl DOMAIN PROBLEM is imported and solved at once (no JSON file between).
"$BIN" solve --pddl $P/search_rescue_domain.pddl $P/search_rescue_problem.pddl \
  --pddl-plan "$T/direct.plan" > "$T/direct.json"; rc=$?
if [ $rc = 0 ] && python3 - "$T/direct.json" "$T/direct.plan" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
assert t["status"] == "optimal" and t["verified"] is True, (t["status"], t["verified"])
assert t["objective"] == {"kind": "makespan", "value": 11}, t["objective"]
assert t["max_horizon"] == 200, t["max_horizon"]  # two events per action: the largest default
lines = open(sys.argv[2]).read().splitlines()
assert sum(1 for l in lines if "(pass " in l) == 2, lines
PY
then ok "solve --pddl DOMAIN PROBLEM: imported and solved, makespan 11"; else bad "direct solve (rc=$rc)"; fi
"$BIN" solve --pddl $P/search_rescue_domain.pddl >/dev/null 2>&1; rc=$?
[ $rc = 2 ] && ok "--pddl DOMAIN alone is a usage error" || bad "--pddl alone (rc=$rc)"

# A model file larger than the 4 MiB of an HTTP body is read from disk (LocalFileLimits: 256 MiB).
python3 - "$T/sr.json" "$T/big.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["description"] = "x" * (5 << 20)
json.dump(d, open(sys.argv[2], "w"))
PY
"$BIN" solve --domain "$T/big.json" "$T/plan.json" > "$T/big_t.json" 2>"$T/err"; rc=$?
[ $rc = 0 ] && python3 -c "import json,sys; t=json.load(open(sys.argv[1])); assert t['objective']['value'] == 11" "$T/big_t.json" \
  && ok "a 5 MiB model file solves" || bad "5 MiB model (rc=$rc): $(head -c 300 "$T/err")"

"$BIN" solve --domain "$T/sr.json" "$T/plan.json" --pddl-plan "$T/x.plan" >/dev/null 2>&1; rc=$?
[ $rc != 0 ] && [ ! -e "$T/x.plan" ] && ok "--pddl-plan needs --pddl" || bad "--pddl-plan alone (rc=$rc)"

"$BIN" domain import-pddl $P/presentation_domain.pddl > "$T/pres.json" 2>"$T/err"; rc=$?
if [ $rc = 0 ] && python3 - "$T/pres.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert [a["name"] for a in d["automata"]] == ["comp", "conn", "proj"], d["automata"]
PY
then ok "import from constants to stdout"; else bad "constants import (rc=$rc) $(cat "$T/err")"; fi

# An action that moves the computer and the cable at once.
python3 - $P/presentation_domain.pddl "$T/two.pddl" <<'PY'
import sys
s = open(sys.argv[1]).read().rstrip()
assert s.endswith(")")
s = s[:-1] + """
  (:action boot-and-connect
    :parameters (?c - computer ?k - cable)
    :precondition (and (comp-off ?c) (disconnected ?k))
    :effect (and (not (comp-off ?c)) (comp-on ?c) (not (disconnected ?k)) (connected ?k))))
"""
open(sys.argv[2], "w").write(s)
PY
"$BIN" domain import-pddl "$T/two.pddl" > "$T/two.json" 2>"$T/err"; rc=$?
# Since issue 32 an action may change several objects: both change at one event.
[ $rc = 0 ] && grep -q 'boot_and_connect' "$T/two.json" \
  && ok "two state variables at once: imported" || bad "two variables (rc=$rc): $(cat "$T/err")"

"$BIN" domain import-pddl $P/presentation_domain.pddl --state-plan-out "$T/x.json" >/dev/null 2>&1; rc=$?
[ $rc = 2 ] && ok "--state-plan-out without a problem is a usage error" || bad "usage (rc=$rc)"

"$BIN" domain import-pddl "$T/missing.pddl" >/dev/null 2>&1; rc=$?
[ $rc = 1 ] && ok "missing file" || bad "missing file (rc=$rc)"

echo "$fail failure(s)"
[ $fail = 0 ]
