#!/usr/bin/env bash
# Black-box test of `ctburton validate`: exit codes and the one-line-per-error format.
set -u
BIN=$1
SRC=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
check() {  # check NAME EXPECTED_RC PATTERN -- ARGS...
  local name=$1 want=$2 pattern=$3
  shift 4
  local out rc
  out=$("$BIN" validate "$@" 2>&1)
  rc=$?
  if [ "$rc" != "$want" ] || ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL $name: rc=$rc (want $want), output:"
    echo "$out"
    fail=$((fail + 1))
  else
    echo "ok   $name"
  fi
}
cd "$SRC"
for f in config/examples/*/*.json; do
  d=$(basename "$(dirname "$f")")
  check "example $f" 0 '^valid$' -- --domain "$d" "$f"
done
check "warning shown" 0 '^warning: /constraints/temporal/first60/accepting_event1_constraint: offset 6: ' \
  -- --domain presentation config/examples/presentation/test1_direct.json
check "domain by path" 0 '^valid$' -- --domain config/domains/presentation.json \
  config/examples/presentation/test1_cot.json
: > "$T/empty.json"
check "empty file" 1 '^/: not valid JSON|^/: empty input' -- --domain presentation "$T/empty.json"
head -c 200 config/examples/presentation/test1_cot.json > "$T/trunc.json"
check "truncated" 1 '^/: offset [0-9]+: not valid JSON' -- --domain presentation "$T/trunc.json"
sed '0,/"conn"/s/"comp": "compOff",/"comp": "compOff"/' config/examples/presentation/test1_cot.json > "$T/comma.json"
check "missing comma" 1 '^/: offset [0-9]+: not valid JSON' -- --domain presentation "$T/comma.json"
echo '{"initial_state": NaN}' > "$T/nan.json"
check "NaN" 1 'not valid JSON' -- --domain presentation "$T/nan.json"
python3 -c 'print("[" * 100000 + "]" * 100000)' > "$T/deep.json"
check "deep nesting" 1 '^/: offset 64: JSON nested deeper than 64 levels' -- --domain presentation "$T/deep.json"
sed 's/projl\[i\]==projOff \/\\\\ projl\[i+1\]==projWarmUp/projl[i]==projOff \/\\\\ projl[i+1]==projWarmUpp/' \
  config/examples/presentation/test1_cot.json > "$T/typo.json"
check "typo" 1 "^/constraints/temporal/ProjectorOnWithin60/accepting_event1_constraint: offset 33: unknown location 'projWarmUpp' of automaton 'proj' \(did you mean 'projWarmUp'\?\)" \
  -- --domain presentation "$T/typo.json"
check "unknown domain" 2 "unknown domain 'nosuch'" -- --domain nosuch config/examples/presentation/test1_cot.json
check "missing file" 1 "cannot open file" -- --domain presentation "$T/none.json"
echo "$((fail == 0 ? 1 : 0)) passed, $fail failed"
[ "$fail" = 0 ]
