// HeapRelease trims on its schedule: not before `every_s` has passed since the first tick, then once
// per period. The server's heap policy serves big blocks from mmap even after one was freed.
#include <catch2/catch.hpp>
#include <malloc.h>

#include <cstdlib>
#include <cstring>

#include "server/http/heap_release.hpp"

using namespace labo::server;

TEST_CASE("heap release: trims once per period, counted from the first tick") {
  HeapRelease release(60.0);
  release.tick(1000.0);  // the first tick starts the clock
  release.tick(1059.9);
  CHECK(release.releases() == 0);
  release.tick(1060.0);
  CHECK(release.releases() == 1);
  release.tick(1100.0);  // 40 s after the last release
  CHECK(release.releases() == 1);
  release.tick(1125.0);
  CHECK(release.releases() == 2);
}

TEST_CASE("heap policy: a frame-sized block comes from mmap, also after a bigger one was freed") {
#if defined(__SANITIZE_ADDRESS__)
  // ASan replaces glibc's malloc: mallopt does not apply and mallinfo2 does not see its heap.
  WARN("not checked under AddressSanitizer");
  return;
#endif
  REQUIRE(configure_server_heap());
  // glibc's own threshold would climb to 4 MiB on this free and serve the next frame from the heap
  // (checked: without the policy the frame adds nothing to the mmapped bytes).
  const auto keep = [](void* p) { asm volatile("" : : "g"(p) : "memory"); };  // the compiler may not drop it
  void* pyramid = std::malloc(4 << 20);
  REQUIRE(pyramid);
  std::memset(pyramid, 1, 4 << 20);
  keep(pyramid);
  std::free(pyramid);
  constexpr std::size_t kFrame = 640 * 360 * 3;  // a BGR frame
  const std::size_t mmapped_before = mallinfo2().hblkhd;
  void* frame = std::malloc(kFrame);
  REQUIRE(frame);
  std::memset(frame, 2, kFrame);
  keep(frame);
  CHECK(mallinfo2().hblkhd >= mmapped_before + kFrame);
  std::free(frame);
}
