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

# The face benchmark's other people (`labodrone-bench bench faces`, docs/face.md): the 1927 Solvay
# conference photograph (public domain) from the Debian package visp-images-data, its 2126 x 1463 PNG
# only, unpacked without installing the package's 225 MB into assets/ (git-ignored). The faces are cut
# from it by the detector when the benchmark starts.
if [ ! -f "$ROOT/assets/solvay_1927.png" ]; then
  tmp="$(mktemp -d)"
  (cd "$tmp" && apt-get download -qq visp-images-data >/dev/null 2>&1 || { apt-get update -qq && apt-get download -qq visp-images-data; })
  dpkg-deb --fsys-tarfile "$tmp"/visp-images-data_*.deb |
    tar -x -C "$tmp" --wildcards '*/Solvay/Solvay_conference_1927_Version2_2126x1463.png'
  mkdir -p "$ROOT/assets"
  cp "$(find "$tmp" -name Solvay_conference_1927_Version2_2126x1463.png | head -n 1)" "$ROOT/assets/solvay_1927.png"
  rm -rf "$tmp"
  echo "setup: assets/solvay_1927.png extracted from visp-images-data"
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
