# Sourced by the CLI tests that need a real server: start_server DATA_DIR LOG starts
# `ctburton serve` ($BIN, with $SRC/config) on a free loopback port, sets PORT and SERVER (its
# pid), and returns once /healthz answers (at most 20 s).
start_server() {
  PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
  CTB_CONFIG_DIR=$SRC/config "$BIN" serve --port "$PORT" --data-dir "$1" > /dev/null 2> "$2" &
  SERVER=$!
  python3 - "$PORT" <<'PY'
import sys, time, urllib.request
for _ in range(400):
    try:
        urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/healthz", timeout=1)
        break
    except Exception:
        time.sleep(0.05)
PY
}
