#!/usr/bin/env bash
# One command: install what is missing, build, and run the main job on its defaults: the thesis'
# test prompt 1, from natural language (replayed from the shipped recording, no network needed)
# to a verified plan.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >&2
bash scripts/build.sh >&2
TP1="The computer and projector start in the off state, and the connection is disconnected. The projector should turn on and stay on for 1800 seconds, following which everything should turn off within 600 seconds. In addition, the projector should turn on within 60 seconds."
plan=$(mktemp)
trap 'rm -f "$plan"' EXIT
CTB_LLM_REPLAY=${CTB_LLM_REPLAY:-tests/recordings/thesis} \
  ./build/client/ctburton translate --domain presentation "$TP1" \
  | python3 -c 'import json,sys; json.dump(json.load(sys.stdin)["state_plan"], sys.stdout)' > "$plan"
exec ./build/client/ctburton solve --domain presentation "$plan"
