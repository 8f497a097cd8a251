#include <catch2/catch.hpp>

#include <malloc.h>

#include <cstring>
#include <memory>
#include <vector>

#include "bench/batch_allocator.hpp"

using namespace labo;
using namespace labo::bench;

TEST_CASE("batch allocator: large blocks come from the heap and stay there after free") {
#if defined(__SANITIZE_ADDRESS__)
  // ASan replaces glibc's malloc: mallopt does not apply and mallinfo2 does not see its heap.
  WARN("not checked under AddressSanitizer");
  return;
#endif
  REQUIRE(keep_freed_memory_for_batch_runs());
  constexpr std::size_t kBlock = 4 << 20;  // a SIFT pyramid level of a doubled 640x360 frame
  const std::size_t mmapped_before = mallinfo2().hblkhd;
  std::vector<std::unique_ptr<char[]>> blocks;
  for (int i = 0; i < 8; ++i) {
    blocks.emplace_back(new char[kBlock]);
    std::memset(blocks.back().get(), i, kBlock);  // touch the pages
  }
  CHECK(mallinfo2().hblkhd == mmapped_before);  // none of them mmapped
  blocks.clear();
  // Freed, but kept: the heap still holds the 32 MB for the next frame's pyramid.
  CHECK(mallinfo2().arena >= 8 * kBlock);
  CHECK(mallinfo2().fordblks >= 8 * kBlock);
}
