#!/usr/bin/env bash
# One command: install what is missing, build, run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# The browser test: Debian's Chromium, driven by playwright-core from the npm registry.
missing=()
for p in chromium nodejs npm; do
  command -v "$p" >/dev/null 2>&1 || { [ "$p" = nodejs ] && command -v node >/dev/null 2>&1; } || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
(cd tests/browser && npm install --no-audit --no-fund --loglevel=error)
bash scripts/build.sh
cd build
ctest --output-on-failure -j2 --timeout 600
