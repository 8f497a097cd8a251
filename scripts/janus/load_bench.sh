#!/usr/bin/env bash
# The Janus fan-out benchmark on loopback (docs/web.md "Many viewers and several labs"): one lab and
# Janus started by run_labs.sh on free ports, a pilot who takes off on the direct WebSocket path, and
# N spectators through Janus for each N of COUNTS, SECONDS each (tests/e2e/janus_load.mjs): the lab
# page in headless Chromium and N - 1 receive-only WebRTC viewers in one Node.js process (werift,
# tests/e2e/webrtc_viewers, installed from npm there on first use). Bounded: at most 60 viewers,
# 120 s a step; stopped at the end. KBPS: the bit rate the admin asks of the drone first
# (PUT /api/video/bitrate, 250-4000): the viewers' SRTP decryption in Node.js grows with it, and on the
# machine that runs them it is what saturates first.
#   [KBPS=1000] scripts/janus/load_bench.sh [COUNTS="1 5 10 20"] [SECONDS=20] [BUILD=build/release]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
counts="${1:-1 5 10 20}" seconds="${2:-20}" build="${BUILD:-build/release}"
for n in $counts $seconds ${KBPS:-}; do [[ "$n" =~ ^[0-9]+$ ]] || { echo "load_bench.sh: '$n' is not a number" >&2; exit 2; }; done
for n in $counts; do ((n >= 1 && n <= 60)) || { echo "load_bench.sh: $n viewers: expected 1 to 60" >&2; exit 2; }; done
((seconds >= 5 && seconds <= 120)) || { echo "load_bench.sh: $seconds s: expected 5 to 120" >&2; exit 2; }
cd "$ROOT"
viewers_dir="$ROOT/tests/e2e/webrtc_viewers"
[ -d "$viewers_dir/node_modules/werift" ] || (cd "$viewers_dir" && npm install --no-audit --no-fund --silent)
build="$(cd "$build" && pwd)"
out="$build/janus-load"
mkdir -p "$out"
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
port=$(free_port) ws_port=$(free_port)
rtp_base=$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1",0)); print(s.getsockname()[1] & ~1)')
LABS=1 PORT=$port JANUS_WS_PORT=$ws_port RTP_BASE=$rtp_base BUILD="$build" bash scripts/janus/run_labs.sh > "$out/run_labs.log" 2>&1 &
labs=$!
trap 'kill -TERM $labs 2>/dev/null; wait $labs 2>/dev/null || true' EXIT
for _ in $(seq 300); do curl -sf "http://127.0.0.1:$port/api/health" >/dev/null && break; sleep 0.1; done
labo_pid=$(sed -n 's/^lab1: .*pid \([0-9]*\))$/\1/p' "$out/run_labs.log")
janus_pid=$(sed -n 's/^Janus: .*pid \([0-9]*\))$/\1/p' "$out/run_labs.log")
[ -n "$labo_pid" ] && [ -n "$janus_pid" ] || { echo "load_bench.sh: the lab or Janus did not start: $out/run_labs.log" >&2; exit 1; }
if [ -n "${KBPS:-}" ]; then
  jar="$out/admin.cookies"
  curl -sf -c "$jar" -H 'Content-Type: application/json' -d '{"user": "admin", "password": "admin-pass"}' \
    "http://127.0.0.1:$port/api/login" > /dev/null
  curl -sS -f -b "$jar" -X PUT -H 'Content-Type: application/json' -d "{\"kbps\": $KBPS}" \
    "http://127.0.0.1:$port/api/video/bitrate" > /dev/null || { echo "load_bench.sh: KBPS=$KBPS refused" >&2; exit 2; }
  echo "the drone's video at $KBPS kbit/s"
fi
echo "load: $(uptime)"
NODE_PATH="$ROOT/tests/e2e/node_modules" node "$ROOT/tests/e2e/janus_load.mjs" "http://127.0.0.1:$port" "$labo_pid" "$janus_pid" \
  "$build/tests/e2e/labo_web_bench" "$counts" "$seconds"
echo "load: $(uptime)"
