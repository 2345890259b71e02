#!/usr/bin/env bash
# Installs every Debian 12 package ctburton needs to build and run. Idempotent.
#   --test   also what the tests need: Chromium and Node.js for the browser test; redis-server and
#            nginx for the replica test; python3-jsonschema to check answers against the OpenAPI
#            document; python3-grpcio and python3-protobuf for the Python gRPC client test;
#            mosquitto (the MQTT broker) for the executive's MQTT test.
#   --mqtt   also the MQTT broker and its command-line clients (mosquitto, mosquitto-clients), to
#            run executions on devices with `serve --mqtt-url` (docs/executive.md, "MQTT").
# The same list is used by docker/Dockerfile (keep them in step).
set -euo pipefail
PACKAGES=(
  build-essential cmake pkg-config python3
  nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev
  minizinc libgecode-dev libz3-dev
  libcurl4-openssl-dev libcpp-httplib-dev libssl-dev zlib1g-dev libbrotli-dev
  libsqlite3-dev libhiredis-dev libmosquitto-dev
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc
)
if [ "${1:-}" = "--test" ]; then
  PACKAGES+=(chromium redis-server nginx python3-jsonschema python3-grpcio python3-protobuf mosquitto)
  command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 || PACKAGES+=(nodejs npm)
fi
if [ "${1:-}" = "--mqtt" ]; then
  PACKAGES+=(mosquitto mosquitto-clients)
fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
