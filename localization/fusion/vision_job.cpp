#include "localization/fusion/vision_job.hpp"

namespace labo::fusion {

void VisionJob::clear() {
  instrument = nullptr;
  instrument_id.clear();
  instrument_distance_m.reset();
  platform = nullptr;
  platform_distance_m.reset();
  face = nullptr;
  slam = nullptr;
  slam_pause = false;
  slam_prior_T_cam_map.reset();
  gravity_down_cam.reset();
}

bool VisionResults::detected() const {
  const auto by_detector = [](const TargetObservation& o) { return o.method == "template" || o.method == "features"; };
  return (has_instrument && by_detector(instrument)) || (has_platform && by_detector(platform));
}

bool VisionResults::tracking() const {
  const auto tracked = [](bool has, const TargetObservation& o) { return has && o.state == TrackState::Tracking; };
  return tracked(has_instrument, instrument) || tracked(has_platform, platform) || tracked(has_face, face);
}

void run_vision_job(const VisionJob& job, VisionResults& out) {
  out.t = job.t;
  out.camera = job.camera;
  out.failure.clear();
  out.has_slam = job.slam != nullptr;
  out.has_slam_points = false;
  if (job.slam) {
    out.slam = job.slam_pause ? job.slam->pause()
                              : job.slam->process(job.gray, job.t, job.slam_prior_T_cam_map, job.gravity_down_cam);
    if (!job.slam_pause) out.has_slam_points = job.slam->sample_map_points(job.t, out.slam_points_map);
  }
  out.has_instrument = job.instrument != nullptr;
  if (job.instrument) {
    out.instrument_id = job.instrument_id;
    out.instrument = job.instrument->process(job.gray, job.t, job.instrument_distance_m);
  }
  out.has_platform = job.platform != nullptr;
  if (job.platform) out.platform = job.platform->process(job.gray, job.t, job.platform_distance_m);
  out.has_face = job.face != nullptr;
  if (job.face) out.face = job.face->process(job.gray, job.t, std::nullopt);
}

}  // namespace labo::fusion
