#!/usr/bin/env bash
# One command: install what is missing, build, run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --test
# The browser test drives Debian's Chromium with playwright-core from the npm registry.
(cd tests/browser && npm install --no-audit --no-fund --loglevel=error)
bash scripts/build.sh
cd build
ctest --output-on-failure -j2 --timeout 600
