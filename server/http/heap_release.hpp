#pragma once
// Hands the memory the C library keeps after free() back to the kernel, once a minute. A server's
// threads (the flight thread, the vision worker, the decoder, each connection's handlers) allocate
// and free frames, JPEGs and access units of every size in glibc's per-thread arenas; what is freed
// in the middle of an arena stays mapped, so the process's RSS grows by what was once live even
// when what is live stays flat (the 30-minute soak: 200 MiB held beyond what was in use). malloc_trim
// gives every arena's free pages back. Its cost (one walk of the free lists) is paid on the web
// server's own thread, never on the flight thread. Under AddressSanitizer it does nothing.
#include <cstdint>

namespace labo::server {

// The C library's heap policy for a long-running server; called once, before its threads start.
//  - Two arenas, not glibc's eight per core: a block freed by another thread than the one that
//    allocated it (a frame decoded on one thread, encoded and sent on others) goes back to its own
//    arena, and every arena holds its own free holes; with fewer of them the holes are reused.
//  - Blocks of 128 KiB and more from mmap, unmapped on free: frames, JPEGs, access units and the SLAM
//    keyframes' images. glibc's threshold otherwise climbs to the largest block freed so far (a
//    video frame), and from then on serves such blocks from the arenas, where they fragment.
// The soak shows why: the heap's bytes in use stay flat (net of the SLAM map) while the bytes it holds,
// and RSS with them, grow. Returns false when the C library refused a setting (under AddressSanitizer,
// whose allocator is not glibc's, the settings have no effect).
bool configure_server_heap();

class HeapRelease {
 public:
  explicit HeapRelease(double every_s = 60.0) : every_s_(every_s) {}
  // Called from a periodic tick with the steady time (s): trims when due.
  void tick(double now_s);
  int releases() const { return releases_; }

 private:
  double every_s_;
  double last_s_ = -1;
  int releases_ = 0;
};

}  // namespace labo::server
