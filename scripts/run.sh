#!/usr/bin/env bash
# One command: install what is missing, build, and run the service on its defaults
# (http://127.0.0.1:8080: the web chat page, /solve, and /plan for the thesis' recorded prompts
# when no LLM endpoint is configured: --demo). Sessions go to ./data. Stop it with Ctrl-C.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >&2
bash scripts/build.sh >&2
exec ./build/client/ctburton serve --demo "$@"
