#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/*_fuzzer.cpp) with clang + ASan/UBSan and runs each for
# FUZZ_SECONDS (default 60) seconds, starting from the regression corpus tests/data/fuzz/<target>/.
# New findings land in build/fuzz/crashes/; copy a minimized one into tests/data/fuzz/<target>/ so
# the normal tests replay it. Usage: scripts/fuzz.sh [seconds]   (or: make fuzz FUZZ_SECONDS=N)
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET="${1:-${FUZZ_SECONDS:-60}}"
CXX_FUZZ="$(command -v clang++-14 || command -v clang++ || true)"
if [[ -z "$CXX_FUZZ" ]]; then
  echo "clang not found: installing clang-14 and libclang-rt-14-dev" >&2
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get install -y --no-install-recommends clang-14 libclang-rt-14-dev >&2
  CXX_FUZZ="$(command -v clang++-14)"
fi
OUT=build/fuzz
mkdir -p "$OUT/crashes"
SOURCES=(drone/ardrone2/at_command.cpp drone/ardrone2/navdata_schema.cpp drone/ardrone2/navdata_packet.cpp
         drone/ardrone2/navdata_parser.cpp drone/ardrone2/navdata_builder.cpp drone/ardrone2/pave.cpp
         drone/tello/tello_state.cpp drone/tello/tello_rc.cpp drone/tello/tello_command.cpp
         drone/tello/annexb_assembler.cpp)
status=0
for target in navdata pave at tello_state tello_video tello_reply; do
  echo "== building ${target}_fuzzer" >&2
  "$CXX_FUZZ" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I. "fuzz/${target}_fuzzer.cpp" "${SOURCES[@]}" -o "$OUT/${target}_fuzzer"
  corpus="$OUT/corpus/$target"
  mkdir -p "$corpus"
  [[ -d "tests/data/fuzz/$target" ]] && cp -n tests/data/fuzz/$target/* "$corpus/" 2>/dev/null || true
  echo "== running ${target}_fuzzer for ${SECONDS_PER_TARGET}s" >&2
  if ! "$OUT/${target}_fuzzer" "$corpus" -max_total_time="$SECONDS_PER_TARGET" -max_len=4096 \
       -artifact_prefix="$OUT/crashes/${target}-" -print_final_stats=1 2>"$OUT/${target}.log"; then
    echo "!! ${target}_fuzzer found a failure: see $OUT/${target}.log and $OUT/crashes/" >&2
    status=1
  fi
  grep -E "stat::number_of_executed_units|Done [0-9]+ runs" "$OUT/${target}.log" | tail -2 >&2 || true
done
exit $status
