#pragma once
// The per-frame vision run by LabPipelines::on_video(): a front-end wraps one localization pipeline
// (planar object, face, SLAM) and turns its result into what control reads (TargetObservation,
// SlamSummary). LabPipelines converts each frame to grey once and hands it to the front-ends the
// current PerceptionFocus selects; tests substitute doubles.
//
// Results are returned by reference to a member the front-end reuses, so a steady stream of frames
// allocates nothing beyond what the wrapped pipeline allocates itself.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "localization/fusion/localization_pipelines.hpp"
#include "core/time.hpp"

namespace labo::fusion {

// A planar target (instrument panel, landing platform) or the teacher's face.
class TargetFrontEnd {
 public:
  virtual ~TargetFrontEnd() = default;
  // One 8-bit grey frame of the camera's size. `expected_distance_m` (camera to target, from the
  // state estimator; empty when unknown or too uncertain) lets a planar front-end choose its
  // detector and narrow its search. The observation stays valid until the next call.
  virtual const TargetObservation& process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) = 0;
  // Forget the track (the next frame searches again).
  virtual void reset() = 0;
};

// One frame's SLAM result: the camera's pose in the map (map units) when tracking.
struct SlamFrame {
  bool has_pose = false;
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  SlamSummary summary;
  int map_id = 1;  // a new id whenever the map starts over
};

class SlamFrontEnd {
 public:
  virtual ~SlamFrontEnd() = default;
  // One 8-bit grey front-camera frame. `prior_T_cam_map` (the state estimator's prediction, in the
  // current map) replaces SLAM's own motion model and lets it relocalize from there.
  // `gravity_down_cam`: the IMU's attitude at the frame's capture time as gravity's direction in the
  // camera (SLAM's gravity prior, used when its settings enable it). Valid until the next call.
  virtual const SlamFrame& process(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior_T_cam_map,
                                   const std::optional<Eigen::Vector3d>& gravity_down_cam) = 0;
  // Frames stopped coming (the bottom camera streams): report SLAM off until the next frame.
  virtual const SlamFrame& pause() = 0;
  virtual int map_id() const = 0;
  // At a low rate (the map grows with keyframes, the lab page redraws it once a second): a bounded
  // sample of the current map's points (map units) into `out`, reused; false when not due.
  virtual bool sample_map_points(Seconds t, std::vector<Eigen::Vector3d>& out) {
    (void)t;
    (void)out;
    return false;
  }
};

}  // namespace labo::fusion
