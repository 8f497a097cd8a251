#include "bench/experiments/lockstep_vision_worker.hpp"

namespace labo::bench {

namespace {
bool tracked_by_tracker(const fusion::TargetObservation& o) { return o.method == "ic" || o.method == "ecc"; }
}  // namespace

Seconds VisionLatencyModel::latency_of(const fusion::VisionResults& r) const {
  double ms = handoff_ms;
  if (r.has_slam && r.slam.summary.state != fusion::SlamState::Off) ms += slam_ms;
  const auto planar = [&](const fusion::TargetObservation& o, double tracking_ms) {
    if (tracked_by_tracker(o)) return tracking_ms;
    return o.method == "template" ? template_detection_ms : feature_detection_ms;
  };
  if (r.has_instrument) ms += planar(r.instrument, planar_tracking_ms);
  if (r.has_platform) ms += planar(r.platform, platform_tracking_ms);
  if (r.has_face) ms += face_ms;
  return ms / 1000.0;
}

LockstepVisionWorker::LockstepVisionWorker(control::FlightStack& stack, VisionLatencyModel model) : stack_(stack), model_(model) {}

void LockstepVisionWorker::on_frame(const VideoFrame& frame, Seconds now) {
  ++stats_.frames_in;
  if (!busy_) return start(frame, now);
  if (have_waiting_) ++stats_.frames_skipped;
  waiting_.t = frame.t;
  waiting_.camera = frame.camera;
  waiting_.frame_number = frame.frame_number;
  frame.bgr.copyTo(waiting_.bgr);
  have_waiting_ = true;
}

void LockstepVisionWorker::advance(Seconds now) {
  if (busy_ && now >= ready_at_) {
    stack_.apply_vision(results_);
    busy_ = false;
  }
  if (!busy_ && have_waiting_) {
    have_waiting_ = false;
    start(waiting_, now);
  }
}

void LockstepVisionWorker::start(const VideoFrame& frame, Seconds now) {
  if (!stack_.prepare_vision(frame, job_)) return;
  ++stats_.frames_to_vision;
  fusion::run_vision_job(job_, results_);
  busy_ = true;
  ready_at_ = now + model_.latency_of(results_);
}

}  // namespace labo::bench
