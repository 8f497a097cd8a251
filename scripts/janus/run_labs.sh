#!/usr/bin/env bash
# Starts Janus and LABS LaboDrone processes behind one front, until Ctrl-C (docs/web.md "Many viewers
# and several labs"). Everything generated goes to $BUILD/labs: the shared session key, the lab
# directory (labs.json), Janus's configuration (janus/) and the logs. Lab i (1..LABS) serves on
# PORT + i - 1, flies its own simulated lab, and forwards its H.264 as RTP to Janus's mount point i
# on UDP RTP_BASE + 2 (i - 1), and its overlay geometry to the mount point's data port, the next
# one; the labs listed in NO_GEOMETRY_UDP (e.g. "2 3") send no geometry there, and their pages take it
# from the WebSocket. Without Janus installed the labs still run and the pages use the WebSocket video.
#   LABS=3 PORT=8080 JANUS_WS_PORT=8188 RTP_BASE=18004 BIND=127.0.0.1 BUILD=build/release \
#     [NO_GEOMETRY_UDP="2"] bash scripts/janus/run_labs.sh [extra serve options...]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
LABS="${LABS:-1}" PORT="${PORT:-8080}" JANUS_WS_PORT="${JANUS_WS_PORT:-8188}" RTP_BASE="${RTP_BASE:-18004}"
BIND="${BIND:-127.0.0.1}" BUILD="${BUILD:-build/release}" NO_GEOMETRY_UDP="${NO_GEOMETRY_UDP:-}"
for n in "$LABS" "$PORT" "$JANUS_WS_PORT" "$RTP_BASE" $NO_GEOMETRY_UDP; do
  [[ "$n" =~ ^[0-9]+$ ]] || { echo "run_labs.sh: '$n' is not a number" >&2; exit 2; }
done
((LABS >= 1 && LABS <= 16)) || { echo "run_labs.sh: LABS=$LABS: expected 1 to 16" >&2; exit 2; }
cd "$ROOT"
labodrone="$BUILD/labodrone"
[ -x "$labodrone" ] || { echo "run_labs.sh: $labodrone is not built (make build)" >&2; exit 2; }
out="$(cd "$BUILD" && pwd)/labs"
mkdir -p "$out"

# One key for every lab of this front, kept between runs so that logins survive a restart.
key="$out/session.key"
if [ ! -s "$key" ]; then (umask 077 && head -c 48 /dev/urandom | base64 > "$key"); fi

have_janus=0
command -v janus >/dev/null && have_janus=1
{
  echo '{"labs": ['
  for ((i = 1; i <= LABS; i++)); do
    janus_entry=""
    ((have_janus)) && janus_entry=", \"janus\": {\"url\": \"ws://{host}:$JANUS_WS_PORT/\", \"mountpoint\": $i}"
    echo "  {\"id\": \"lab$i\", \"name\": \"Lab $i\", \"url\": \"http://{host}:$((PORT + i - 1))/lab.html\"$janus_entry}$( ((i < LABS)) && echo ,)"
  done
  echo ']}'
} > "$out/labs.json"

pids=()
stop() {
  trap - INT TERM EXIT
  # The labs first (each lands its drone), then Janus.
  for ((j = ${#pids[@]} - 1; j >= 0; j--)); do kill -TERM "${pids[j]}" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
}
trap stop EXIT
trap 'stop; exit 0' INT TERM

if ((have_janus)); then
  bash "$ROOT/scripts/janus/janus_config.sh" "$out/janus" "$LABS" "$JANUS_WS_PORT" "$RTP_BASE" "$BIND"
  janus -F "$out/janus" -C "$out/janus/janus.jcfg" -o > "$out/janus.log" 2>&1 &
  pids+=($!)
  echo "Janus: ws://$BIND:$JANUS_WS_PORT/ (log $out/janus.log, pid ${pids[0]})"
else
  echo "run_labs.sh: janus is not installed (scripts/setup.sh installs it): the pages use the WebSocket video" >&2
fi

for ((i = 1; i <= LABS; i++)); do
  rtp=()
  ((have_janus)) && rtp=(--rtp-video "127.0.0.1:$((RTP_BASE + 2 * (i - 1)))")
  ((have_janus)) && [[ " $NO_GEOMETRY_UDP " != *" $i "* ]] && rtp+=(--geometry-udp "127.0.0.1:$((RTP_BASE + 2 * (i - 1) + 1))")
  "$labodrone" serve --port $((PORT + i - 1)) --bind "$BIND" --labs "$out/labs.json" --lab-id "lab$i" \
      --session-key "$key" "${rtp[@]}" "$@" > "$out/lab$i.log" 2>&1 &
  pids+=($!)
  echo "lab$i: http://$BIND:$((PORT + i - 1))/ (log $out/lab$i.log, pid $!)"
done
echo "The labs: http://$BIND:$PORT/labs.html. Ctrl-C lands every drone and stops."
wait -n "${pids[@]}" || true
echo "run_labs.sh: a process ended; stopping the others" >&2
