#!/usr/bin/env bash
# The browser test of the video through Janus: two labs behind one front started by
# scripts/janus/run_labs.sh on free ports (Janus, two `labodrone serve --rtp-video`, a shared session
# key; lab 2 without --geometry-udp, so that its page takes the geometry from the WebSocket), driven by
# janus_view.mjs; everything stopped at the end.
# Usage: run_janus_test.sh BUILD_DIR OUT_DIR
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$1"; out="$2"
mkdir -p "$out"
command -v janus >/dev/null || { echo "FAIL: janus is not installed (scripts/setup.sh installs Debian's janus)" >&2; exit 1; }
[ -d "$here/node_modules/playwright-core" ] || (cd "$here" && npm install --no-audit --no-fund --silent)
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
# Two consecutive free TCP ports for the labs, one for Janus, two UDP ports for the mount points.
for _ in $(seq 20); do
  port=$(free_port)
  python3 -c "import socket; s=socket.socket(); s.bind(('127.0.0.1',$port+1))" 2>/dev/null && break
done
ws_port=$(free_port)
rtp_base=$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1",0)); print(s.getsockname()[1] & ~1)')
LABS=2 PORT=$port JANUS_WS_PORT=$ws_port RTP_BASE=$rtp_base BUILD="$build" NO_GEOMETRY_UDP=2 \
  bash "$here/../../scripts/janus/run_labs.sh" > "$out/run_labs.log" 2>&1 &
labs=$!
trap 'kill -TERM $labs 2>/dev/null; wait $labs 2>/dev/null || true' EXIT
for p in $port $((port + 1)); do
  for _ in $(seq 300); do  # each simulated lab loads the teacher's face first
    curl -sf "http://127.0.0.1:$p/api/health" >/dev/null && break
    sleep 0.1
  done
done
node "$here/janus_view.mjs" "http://127.0.0.1:$port" "http://127.0.0.1:$((port + 1))" "$out"
