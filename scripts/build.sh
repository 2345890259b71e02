#!/usr/bin/env bash
# Configures and builds into ./build: Release (-O2) by default; CTB_BUILD_TYPE=RelWithDebInfo adds
# debug info for profiling and debugging (a fresh build then takes about a third longer);
# CTB_BUILD_TYPE=Check (-O1) is what scripts/test.sh builds. Uses
# ccache when it is installed (several work trees then share compiled objects; CCACHE_BASEDIR
# makes their paths relative).
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE="${CTB_BUILD_TYPE:-Release}" "${launcher[@]}" >/dev/null
cmake --build build -j"$(nproc)" "$@"
