#pragma once
// `labodrone serve`'s vision worker (server/runtime/vision_worker.hpp) in simulated time, so that a
// lockstep campaign sees what the server does: a frame's results reach the estimator only after the
// time the worker would spend on it, and frames that come while it is busy are skipped, the newest
// kept. The front-ends run at once (the flight stays deterministic: the same seed gives the same
// flight); only when their results are applied is modelled, from what each frame's vision did.
//
// The model's times are the medians `labodrone-bench bench vision` measures per front-end on one
// core (docs/control.md); a slower machine is a larger model.
#include "control/flight_stack.hpp"
#include "localization/fusion/vision_job.hpp"

namespace labo::bench {

struct VisionLatencyModel {
  double template_detection_ms = 3.9;   // planar_detect_far
  double feature_detection_ms = 8.3;    // planar_detect_near (also a search that found nothing)
  double planar_tracking_ms = 1.9;      // planar_track
  double platform_tracking_ms = 1.2;    // platform_track
  double slam_ms = 1.6;                 // slam_track
  double face_ms = 2.5;                 // face_track
  double handoff_ms = 0.2;              // waking the worker and the flight thread

  // How long the worker takes over a frame whose vision gave `results`.
  Seconds latency_of(const fusion::VisionResults& results) const;
};

struct LockstepVisionStats {
  int frames_in = 0, frames_to_vision = 0, frames_skipped = 0;
};

class LockstepVisionWorker {
 public:
  LockstepVisionWorker(control::FlightStack& stack, VisionLatencyModel model);

  // A frame delivered at simulated time `now` (its pixels are valid during the call only).
  void on_frame(const VideoFrame& frame, Seconds now);
  // Applies the results due by `now`, then starts the newest waiting frame: call before each tick.
  void advance(Seconds now);

  const LockstepVisionStats& stats() const { return stats_; }

 private:
  void start(const VideoFrame& frame, Seconds now);

  control::FlightStack& stack_;
  VisionLatencyModel model_;
  fusion::VisionJob job_;
  fusion::VisionResults results_;
  bool busy_ = false;
  Seconds ready_at_ = 0;
  VideoFrame waiting_;  // the newest frame that came while busy
  bool have_waiting_ = false;
  LockstepVisionStats stats_;
};

}  // namespace labo::bench
