#!/usr/bin/env bash
# `ctburton` and `ctburton-server` (client/CMakeLists.txt): the command-line tool loads none of the
# server's libraries (gRPC, protobuf, MQTT), `ctburton serve` becomes ctburton-server in the same
# process (same pid: signals reach the service) with the same arguments, and without
# ctburton-server beside it `ctburton serve` says what is missing.
set -u
BIN=$1
T=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
pid=

libs=$(ldd "$BIN")
if echo "$libs" | grep -Eq 'libgrpc|libprotobuf|libmosquitto|libabsl'; then
  bad "ctburton loads server libraries: $(echo "$libs" | grep -Eo 'lib(grpc|protobuf|mosquitto|absl)[^ ]*' | head -3 | tr '\n' ' ')"
else
  ok "ctburton loads no gRPC, protobuf, abseil or MQTT library ($(echo "$libs" | wc -l) libraries)"
fi
server="$(dirname "$BIN")/ctburton-server"
ldd "$server" | grep -q libgrpc && ok "ctburton-server links gRPC" || bad "ctburton-server does not link gRPC"

"$BIN" --help | grep -q '^  serve ' && ok "--help lists serve" || bad "--help does not list serve"
"$BIN" serve --help | grep -q -- '--grpc-port' && ok "serve --help shows the server's options" \
  || bad "serve --help lacks --grpc-port"

# Same pid: the process started as ctburton answers as the service and stops on SIGTERM.
"$BIN" serve --port 0 --data-dir "$T/data" > "$T/out" 2> "$T/err" &
pid=$!
port=
for _ in $(seq 1 600); do
  port=$(grep -ho '"event":"listening","host":"[^"]*","port":[0-9]*' "$T/err" "$T/out" 2>/dev/null \
    | head -1 | grep -o '[0-9]*$')
  [ -n "$port" ] && break
  sleep 0.05
done
exe=$(readlink "/proc/$pid/exe" 2>/dev/null)
[ "$(basename "$exe")" = ctburton-server ] && ok "pid $pid is now ctburton-server" || bad "pid $pid runs '$exe'"
if [ -n "$port" ] && curl -fsS "http://127.0.0.1:$port/healthz" > /dev/null; then
  ok "the service answers /healthz on port $port"
else
  bad "no /healthz (port '$port'; log: $(tail -c 300 "$T/err"))"
fi
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 0 ] && ok "SIGTERM to the pid of ctburton stops the service (exit 0)" || bad "exit $rc after SIGTERM"
pid=

# Without ctburton-server beside it.
cp "$BIN" "$T/ctburton"
"$T/ctburton" serve --port 0 > /dev/null 2> "$T/alone"
rc=$?
[ $rc -eq 3 ] && grep -q "ctburton-server" "$T/alone" && ok "alone: exit 3 naming ctburton-server" \
  || bad "alone: exit $rc, '$(cat "$T/alone")'"

[ $fail -eq 0 ] && echo "all passed" || echo "$fail failed"
exit $fail
