// libFuzzer harness: `make fuzz` (scripts/fuzz.sh) builds it with clang and runs it for a bounded time.
#include "fuzz/fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (!labo::fuzz::tello_reply_target(std::span<const std::uint8_t>(data, size))) __builtin_trap();
  return 0;
}
