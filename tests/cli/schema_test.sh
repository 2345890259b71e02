#!/usr/bin/env bash
# Black-box test of `ctburton schema`: the printed schema of each shipped domain accepts every
# shipped example and rejects broken ones, checked by the jsonschema package (python3-jsonschema,
# installed by scripts/install-deps.sh --test) independently of the C++ test validator.
set -u
BIN=$1
SRC=$2
cd "$SRC"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }

PY=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null 2>&1 && "$p" -c "import jsonschema" 2>/dev/null; then PY=$p; break; fi
done
[ -n "$PY" ] && ok "jsonschema found ($PY)" || bad "no python3 with jsonschema: run scripts/install-deps.sh --test"

for dir in config/examples/*/; do
  domain=$(basename "$dir")
  "$BIN" schema --domain "$domain" > "$T/$domain.json" 2> "$T/err.txt"
  rc=$?
  [ $rc = 0 ] && ok "schema --domain $domain" || { bad "schema --domain $domain (rc=$rc)"; cat "$T/err.txt"; continue; }
  [ -n "$PY" ] || continue
  if "$PY" - "$T/$domain.json" "$dir" <<'PYEOF'
import copy, glob, json, sys
import jsonschema
schema = json.load(open(sys.argv[1]))
jsonschema.Draft202012Validator.check_schema(schema)
v = jsonschema.Draft202012Validator(schema)
files = sorted(glob.glob(sys.argv[2] + "/*.json"))
assert files, "no examples"
for f in files:
    errors = list(v.iter_errors(json.load(open(f))))
    assert not errors, f + ": " + errors[0].message
good = json.load(open(files[0]))
automaton = next(iter(good["initial_state"]))
breaks = []
b = copy.deepcopy(good); b["initial_state"][automaton] = "noSuchLocation"; breaks.append(b)
b = copy.deepcopy(good); del b["initial_state"][automaton]; breaks.append(b)
b = copy.deepcopy(good); b["initial_state"]["noSuchAutomaton"] = "x"; breaks.append(b)
b = copy.deepcopy(good); del b["end_state"]; breaks.append(b)
b = copy.deepcopy(good); b["objective"] = "fastest"; breaks.append(b)
b = copy.deepcopy(good); b.setdefault("constraints", {})["episodes"] = {"E": {"accepting_constraint": "true", "lower_bound": "30 min", "upper_bound": 1}}; breaks.append(b)
for i, b in enumerate(breaks):
    assert list(v.iter_errors(b)), "broken plan %d accepted" % i
print(len(files), "examples accepted,", len(breaks), "broken plans rejected")
PYEOF
  then ok "$domain: examples accepted, broken plans rejected"; else bad "$domain: jsonschema check"; fi
done

"$BIN" schema --domain no_such_domain > /dev/null 2> "$T/err.txt"
rc=$?
[ $rc = 2 ] && grep -q "invalid domain" "$T/err.txt" && ok "unknown domain: exit 2" || bad "unknown domain (rc=$rc)"

echo "$((fail == 0 ? 1 : 0)) passed, $fail failed"
[ "$fail" = 0 ]
