#include "server/http/heap_release.hpp"

#include <malloc.h>

namespace labo::server {

namespace {
constexpr int kArenas = 2;
constexpr int kMmapThresholdBytes = 128 * 1024;
}  // namespace

bool configure_server_heap() {
  const bool arenas = mallopt(M_ARENA_MAX, kArenas) == 1;
  const bool threshold = mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) == 1;
  return arenas && threshold;
}

void HeapRelease::tick(double now_s) {
  if (last_s_ < 0) last_s_ = now_s;
  if (now_s - last_s_ < every_s_) return;
  last_s_ = now_s;
  malloc_trim(0);
  ++releases_;
}

}  // namespace labo::server
