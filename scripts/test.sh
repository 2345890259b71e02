#!/usr/bin/env bash
# One command: install what is missing, build, run every test.
#   --stress [N]  run the whole suite N times (default 5) at -j4, twice the cores of the machines
#                 it is written for, to flush out tests that depend on the machine's speed.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=1
jobs=2
if [ "${1:-}" = "--stress" ]; then
  runs=${2:-5}
  jobs=4
fi
bash scripts/install-deps.sh --test
# The browser test drives Debian's Chromium with playwright-core from the npm registry.
(cd tests/browser && npm install --no-audit --no-fund --loglevel=error)
# -O1 (build type Check, CMakeLists.txt): the fresh-clone run must stay well under 15 minutes.
# -j3 on 2 cores keeps both busy while one job links or waits on the disk.
CTB_BUILD_TYPE=${CTB_BUILD_TYPE:-Check} bash scripts/build.sh -j3
cd build
for i in $(seq 1 "$runs"); do
  [ "$runs" -gt 1 ] && echo "== run $i of $runs (-j$jobs)"
  ctest --output-on-failure -j"$jobs" --timeout 600
done
