#pragma once
// How the flight thread keeps time in `labodrone serve`: the interval between control ticks, the
// latency from a frame's capture to its vision result reaching the estimator, the worker's run time
// per frame, and how many frames the flight software saw or skipped. Recorded by the flight thread
// into fixed rings (no allocation per sample), read as percentiles from any thread.
#include <cstdint>
#include <mutex>
#include <vector>

namespace labo::server {

struct Percentiles {
  std::size_t count = 0;  // samples in the window
  double median = 0, p95 = 0, p99 = 0, max = 0;
};

struct RuntimeTimingSummary {
  Percentiles tick_interval_ms;
  Percentiles vision_latency_ms;  // capture (the link's stamp) to the result applied
  // ... of the frames in which a target was tracked (the control loop flies on those; a search's
  // frames, full-frame detections with nothing to control on, are left out)
  Percentiles vision_latency_tracking_ms;
  Percentiles vision_run_ms;      // the worker's time on the frame's front-ends
  std::uint64_t frames_in = 0;         // frames the link delivered
  std::uint64_t frames_to_vision = 0;  // frames given to the vision worker
  std::uint64_t frames_skipped = 0;    // frames replaced by a newer one before the worker was free
  std::uint64_t vision_failures = 0;   // frames whose front-end threw
};

class RuntimeTiming {
 public:
  explicit RuntimeTiming(std::size_t window = 4096);

  void add_tick_interval(double ms);
  // `tracking`: a target was tracked in the frame (VisionResults::tracking()).
  void add_vision(double latency_ms, double run_ms, bool tracking);
  void count_frame_in();
  void count_frame_to_vision();
  void count_frame_skipped();
  void count_vision_failure();

  RuntimeTimingSummary summary() const;

 private:
  struct Ring {
    std::vector<double> values;
    std::size_t next = 0;
    bool full = false;
    void add(double v);
    Percentiles percentiles() const;
  };
  mutable std::mutex mutex_;
  Ring ticks_, latency_, latency_tracking_, run_;
  RuntimeTimingSummary counts_;
};

}  // namespace labo::server
