#!/usr/bin/env bash
# Installs every Debian package LaboDrone needs, skipping what is present. Idempotent; uses sudo
# when not root. Called by `make run` and `make test`, so a fresh machine needs nothing by hand.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libboost-dev libboost-system-dev libssl-dev
  chromium
  libopencv-dev libopencv-contrib-dev
  libeigen3-dev nlohmann-json3-dev
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev
  catch2
  libdlib-dev libdlib-data
  libceres-dev
  janus libjs-janus-gateway libjs-webrtc-adapter
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#PACKAGES[@]} packages present"
fi

# Face benchmark and tests: the teacher's head is textured with scikit-image's astronaut.png (public
# domain, NASA). Only that file is taken from the Debian package python3-skimage, unpacked without
# installing it (or its SciPy dependencies) into assets/ (git-ignored).
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -f "$ROOT/assets/astronaut.png" ]; then
  tmp="$(mktemp -d)"
  (cd "$tmp" && apt-get download -qq python3-skimage >/dev/null 2>&1 || { apt-get update -qq && apt-get download -qq python3-skimage; })
  dpkg-deb -x "$tmp"/python3-skimage_*.deb "$tmp/x"
  mkdir -p "$ROOT/assets"
  cp "$(find "$tmp/x" -name astronaut.png | head -n 1)" "$ROOT/assets/astronaut.png"
  rm -rf "$tmp"
  echo "setup: assets/astronaut.png extracted from python3-skimage"
fi

# The browser test (tests/e2e): Node.js with npm, and playwright-core from the npm registry. Debian's
# chromium (above) is the browser; playwright never downloads one.
if ! command -v npm >/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm
fi
e2e_dir="$ROOT/tests/e2e"
if [ ! -d "$e2e_dir/node_modules/playwright-core" ]; then
  echo "setup: installing playwright-core (npm) for the browser test"
  (cd "$e2e_dir" && npm install --no-audit --no-fund --silent)
fi
