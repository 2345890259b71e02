#!/usr/bin/env bash
# One command: install what is missing, build, and run the service on its defaults
# (http://127.0.0.1:8080: the web chat page, /solve, and /plan for the thesis' recorded prompts
# when no LLM endpoint is configured: --demo). Sessions go to ./data. Stop it with Ctrl-C.
#   --with-broker  with --mqtt-url mqtt://127.0.0.1:PORT: also start Debian's mosquitto on that
#                  port (installed if missing) for the executive's MQTT adapter, stopped with it.
set -euo pipefail
cd "$(dirname "$0")/.."
args=()
broker=0
for a in "$@"; do
  if [ "$a" = "--with-broker" ]; then broker=1; else args+=("$a"); fi
done
if [ "$broker" = 1 ]; then
  bash scripts/install-deps.sh --mqtt >&2
else
  bash scripts/install-deps.sh >&2
fi
bash scripts/build.sh >&2
if [ "$broker" = 1 ]; then
  url=""
  for ((i = 0; i < ${#args[@]}; i++)); do
    [ "${args[$i]}" = "--mqtt-url" ] && url="${args[$((i + 1))]:-}"
  done
  port=$(printf '%s' "$url" | sed -n 's|^mqtt://127\.0\.0\.1:\([0-9]*\)$|\1|p; s|^mqtt://localhost:\([0-9]*\)$|\1|p')
  if [ -z "$port" ]; then
    echo "--with-broker needs --mqtt-url mqtt://127.0.0.1:PORT" >&2
    exit 2
  fi
  mosquitto -p "$port" >&2 &
  trap 'kill $! 2>/dev/null' EXIT
  ./build/client/ctburton serve --demo "${args[@]}"
  exit $?
fi
exec ./build/client/ctburton serve --demo "${args[@]}"
