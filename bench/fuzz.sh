#!/usr/bin/env bash
# Fuzz campaigns (issue 30, docs/reliability.md).
#
#   bash bench/fuzz.sh TARGET SECONDS [LIBFUZZER_ARGS...]   one target for SECONDS
#   bash bench/fuzz.sh all SECONDS [LIBFUZZER_ARGS...]      every target in turn, SECONDS each
#   bash bench/fuzz.sh build                                only build the fuzz tree
#
# Targets: expr domain state_plan replan translator pddl network grpc_convert.
# Builds build-fuzz/ (clang++-14, -DCTB_FUZZ=ON: ASan + UBSan + libFuzzer) when needed, at -j2 and
# niced; runs each campaign niced, one at a time, on a working corpus build-fuzz/corpus/TARGET
# started from tests/fuzz/TARGET/{seeds,regressions}, with the target's dictionary, a 1 s limit per
# input (slower is a hang) and a 2 GB memory limit. Findings land in build-fuzz/artifacts/TARGET/
# (crash-*, timeout-*, oom-*, leak-*); the log in build-fuzz/logs/TARGET.log. Prints one Markdown
# row per target: wall seconds, CPU seconds of the fuzzer (user + system: on a shared machine
# less than the wall time), executions, exec/s, cov, ft, corpus, findings.
set -euo pipefail
cd "$(dirname "$0")/.."
TARGETS=(expr domain state_plan replan translator pddl network grpc_convert)
what=${1:?usage: bench/fuzz.sh TARGET|all|build SECONDS [LIBFUZZER_ARGS...]}
B=build-fuzz
CXX_FUZZ=${CXX_FUZZ:-clang++-14}

build() {
  local launcher=()
  if command -v ccache >/dev/null 2>&1; then
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  if [ ! -f "$B/CMakeCache.txt" ]; then
    cmake -S . -B "$B" -DCTB_FUZZ=ON -DCTB_BUILD_TESTS=OFF -DCMAKE_CXX_COMPILER="$CXX_FUZZ" \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 "${launcher[@]}" >/dev/null
  fi
  nice -n 10 cmake --build "$B" -j2 --target "$@"
}

run() {
  local t=$1 secs=$2; shift 2
  local corpus=$B/corpus/$t art=$B/artifacts/$t/ log=$B/logs/$t.log
  mkdir -p "$corpus" "$art" "$B/logs"
  local inputs=(tests/fuzz/$t/seeds)
  [ -d "tests/fuzz/$t/regressions" ] && inputs+=(tests/fuzz/$t/regressions)
  local before; before=$(find "$art" -type f | wc -l)
  # -timeout=1: an input that takes more than 1 s is a hang; -max_len: room to grow past the seeds.
  local TIMEFORMAT='%U %S' cpu
  cpu=$( { time nice -n 10 "$B/tests/fuzz/fuzz_$t" "$corpus" "${inputs[@]}" \
    -dict="tests/fuzz/$t.dict" -max_total_time="$secs" -timeout=1 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$art" "$@" > "$log" 2>&1 || true; } 2>&1 )
  cpu=$(awk '{printf "%.0f", $1 + $2}' <<<"$cpu")
  local after; after=$(find "$art" -type f | wc -l)
  local last; last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  local execs; execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  local eps; eps=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  local cov; cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  local ft; ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  local corp; corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9]*[a-zA-Z]*\).*/\1/p' <<<"$last")
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$t" "$secs" "$cpu" "${execs:-?}" "${eps:-?}" \
    "${cov:-?}" "${ft:-?}" "${corp:-?}" "$((after - before)) new in $art"
}

if [ "$what" = build ]; then
  build "${TARGETS[@]/#/fuzz_}"
  exit 0
fi
secs=${2:?usage: bench/fuzz.sh TARGET|all SECONDS [LIBFUZZER_ARGS...]}
shift 2
if [ "$what" = all ]; then list=("${TARGETS[@]}"); else list=("$what"); fi
build "${list[@]/#/fuzz_}"
echo "| target | seconds | CPU s | executions | exec/s | cov | ft | corpus | findings |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for t in "${list[@]}"; do run "$t" "$secs" "$@"; done
