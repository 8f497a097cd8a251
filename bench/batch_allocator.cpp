#include "bench/batch_allocator.hpp"

#include <malloc.h>

namespace labo::bench {

bool keep_freed_memory_for_batch_runs() {
  constexpr int kMmapThresholdBytes = 32 << 20;  // glibc's largest allowed value on 64-bit
  constexpr int kTrimThresholdBytes = 1 << 30;   // never reached in practice: no trimming
  constexpr int kTopPadBytes = 64 << 20;         // grow the heap in large steps
  // mallopt returns 1 on success.
  return mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) == 1 && mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes) == 1 &&
         mallopt(M_TOP_PAD, kTopPadBytes) == 1;
}

}  // namespace labo::bench
