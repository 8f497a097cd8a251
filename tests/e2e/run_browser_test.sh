#!/usr/bin/env bash
# Runs a browser test: installs Debian's chromium and the npm package when missing, starts the
# server on a free port, drives it with the test script, stops the server.
# Usage: run_browser_test.sh SERVER_BINARY OUT_DIR [student_flow|video_paths|roles_flow|video_controls|teacher_flow|replay_flow|instrument_flow] [sim|tello]
#   SERVER_BINARY labo_e2e_server: the web layer over test doubles (a test card, a scripted mission);
#   SERVER_BINARY labodrone: `labodrone serve`, i.e. the simulated lab on loopback with the real
#   driver, flight stack and vision, as `make run` starts it; with `tello`, `labodrone emulate
#   --protocol tello` (the simulated lab as a Tello on the SDK's fixed ports of 127.0.0.1) flown by
#   `labodrone serve --drone tello:127.0.0.1`.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
server="$1"; out="$2"; script="${3:-student_flow}"; drone="${4:-sim}"
mkdir -p "$out"
if ! command -v chromium >/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium
fi
if [ ! -d "$here/node_modules/playwright-core" ]; then
  (cd "$here" && npm install --no-audit --no-fund --silent)
fi
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
emulator=""
if [ "$drone" = tello ]; then
  "$server" emulate --protocol tello > "$out/emulator.log" 2>&1 &
  emulator=$!
  "$server" serve --port "$port" --drone tello:127.0.0.1 > "$out/server.log" 2>&1 &
elif [ "$script" = teacher_flow ]; then
  # Registered faces are written where face.people_dir says: a copy of the config, never the source
  # tree's. The photo is the simulated teacher's face through the front camera, 0.8 m in front of
  # them; the portrait it is textured with is a photo of the wrong size.
  rm -rf "$out/teacher" && mkdir -p "$out/teacher/photos" && cp -r "$here/../../config" "$out/teacher/config"
  ln -s "$(cd "$here/../../web" && pwd)" "$out/teacher/web"
  ln -s "$(cd "$here/../../assets" && pwd)" "$out/teacher/assets"
  "$server" sim render --pose 2.8,-2,1.62,180 --teacher 2,-2,0 --sharp --config "$out/teacher/config/default.json" \
    --out "$out/teacher/photos/teacher" > "$out/render.log" 2>&1
  "$server" serve --port "$port" --config "$out/teacher/config/default.json" > "$out/server.log" 2>&1 &
elif [ "$script" = replay_flow ]; then
  # A flight to replay: the simulated lab as the driver recorded it for a few seconds, written into
  # the recordings folder of a copy of the config (recordings_dir: ../var/recordings).
  rm -rf "$out/replay" && mkdir -p "$out/replay/var/recordings" && cp -r "$here/../../config" "$out/replay/config"
  ln -s "$(cd "$here/../../web" && pwd)" "$out/replay/web"
  ln -s "$(cd "$here/../../assets" && pwd)" "$out/replay/assets"
  node -e 'const fs = require("fs"); const [from, to, file] = process.argv.slice(1);
           const c = JSON.parse(fs.readFileSync(from)); c.link.recording = file; fs.writeFileSync(to, JSON.stringify(c));' \
    "$out/replay/config/default.json" "$out/replay/config/record.json" "$out/replay/var/recordings/flight.ldrec"
  "$server" serve --port "$port" --config "$out/replay/config/record.json" > "$out/record.log" 2>&1 &
  recorder=$!
  for _ in $(seq 300); do curl -sf "http://127.0.0.1:$port/api/health" >/dev/null && break; sleep 0.1; done
  sleep 6
  kill -TERM $recorder; wait $recorder || true
  "$server" serve --port "$port" --config "$out/replay/config/default.json" > "$out/server.log" 2>&1 &
elif [ "$script" = instrument_flow ]; then
  # Uploaded instruments are stored where server.instruments_dir says, and placed again at the next
  # start: a fresh copy of the config, never the source tree's.
  rm -rf "$out/instrument" && mkdir -p "$out/instrument" && cp -r "$here/../../config" "$out/instrument/config"
  ln -s "$(cd "$here/../../web" && pwd)" "$out/instrument/web"
  ln -s "$(cd "$here/../../assets" && pwd)" "$out/instrument/assets"
  "$server" serve --port "$port" --config "$out/instrument/config/default.json" > "$out/server.log" 2>&1 &
elif [ "$(basename "$server")" = labodrone ]; then
  "$server" serve --port "$port" > "$out/server.log" 2>&1 &
elif [ "$script" = roles_flow ]; then
  # The admin's user routes write the config file: a copy, beside the pages it serves, never the source tree's.
  rm -rf "$out/roles" && mkdir -p "$out/roles" && cp -r "$here/../../config" "$out/roles/config"
  ln -s "$(cd "$here/../../web" && pwd)" "$out/roles/web"
  "$server" "$port" 1.5 30 plain "$out/roles/config/default.json" > "$out/server.log" 2>&1 &
else
  "$server" "$port" 1.5 30 > "$out/server.log" 2>&1 &
fi
pid=$!
trap 'kill -TERM $pid $emulator 2>/dev/null; wait $pid $emulator 2>/dev/null || true' EXIT
for _ in $(seq 300); do  # the simulated lab loads the teacher's face first
  curl -sf "http://127.0.0.1:$port/api/health" >/dev/null && break
  sleep 0.1
done
mode=scripted; [ "$(basename "$server")" = labodrone ] && mode=sim
case "$script" in
  student_flow) node "$here/student_flow.mjs" "http://127.0.0.1:$port" "$out/student_flow.png" "$mode" ;;
  video_paths) node "$here/video_paths.mjs" "http://127.0.0.1:$port" "$out" "$mode" ;;
  video_controls) node "$here/video_controls.mjs" "http://127.0.0.1:$port" "$out" "$mode" ;;
  roles_flow) node "$here/roles_flow.mjs" "http://127.0.0.1:$port" "$out" ;;
  teacher_flow) node "$here/teacher_flow.mjs" "http://127.0.0.1:$port" "$out" "$out/teacher/photos/teacher_front.png" \
                  "$out/teacher/assets/astronaut.png" ;;
  replay_flow) node "$here/replay_flow.mjs" "http://127.0.0.1:$port" "$out" ;;
  instrument_flow) node "$here/instrument_flow.mjs" "http://127.0.0.1:$port" "$out" ;;
  *) echo "unknown browser test '$script' (expected student_flow, video_paths, roles_flow, video_controls, teacher_flow, replay_flow or instrument_flow)" >&2; exit 2 ;;
esac
