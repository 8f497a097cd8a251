#pragma once
// Allocator settings for batch commands (every `labodrone-bench` command): keep freed memory in the
// process instead of handing it back to the kernel.
//
// Why: OpenCV's SIFT allocates its scale-space pyramid (a dozen float images of 1280x720, 3.7 MB
// each) on every call and frees it on return. With glibc's defaults those blocks come from mmap, or
// from a heap top that free() trims back, so every SIFT call would fault ~50 MB of fresh zeroed pages
// in again, a sizeable share of a real-vision `sim inspect`'s CPU time (docs/sim.md, "Where the time
// of a real-vision run goes"). Reusing the memory changes no computed value. Test "batch allocator:
// large blocks come from the heap and stay there after free".
// The price: the process keeps its peak heap until it exits, which a batch command can afford and a
// long-running server should not, so `serve` keeps glibc's defaults.

namespace labo::bench {

// Large blocks come from the heap (mmap only above 32 MB), and free() no longer trims the heap.
// Returns false when the C library refused a setting (then nothing is guaranteed).
bool keep_freed_memory_for_batch_runs();

}  // namespace labo::bench
