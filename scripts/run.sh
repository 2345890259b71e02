#!/usr/bin/env bash
# One command: install what is missing, build, and run the main job on its defaults.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
exec ./build/client/ctburton validate --domain presentation config/examples/presentation/test1_cot.json
