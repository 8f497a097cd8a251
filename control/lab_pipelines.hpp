#pragma once
// The lab's localization pipelines behind FlightStack: the StateEstimator (localization/estimation/)
// fed with navdata, the commands sent, and the vision results of the source LocalizationSwitch chose
// (SLAM far, the instrument's or platform's homography near, the face in face-follow).
//
// Vision results come in through add_*_result(), stamped with their frame time: from the vision
// front-ends run on each frame by on_video() (a VisionFrontEnds member per camera, wired as the
// planar/SLAM/face branches land), or from a perception model in the lockstep experiments.
// Convention: every TargetObservation's T_cam_target has z pointing into the target (away from a viewer
// in front of it), for panels and faces alike; faces are converted at this edge.
#include <memory>
#include <optional>
#include <vector>

#include "control/lab_geometry.hpp"
#include "control/localization_pipelines.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo {

// Optional per-frame vision; each returns nothing when it has no result for this frame.
class VisionFrontEnd {
 public:
  virtual ~VisionFrontEnd() = default;
  virtual std::optional<TargetObservation> process(const VideoFrame& frame, const PerceptionFocus& focus) = 0;
};

class LabPipelines final : public LocalizationPipelines {
 public:
  LabPipelines(LabGeometry lab, const EstimatorConfig& config, const VisionThresholds& thresholds);

  void set_instrument_front_end(std::unique_ptr<VisionFrontEnd> front_end) { instrument_fe_ = std::move(front_end); }
  void set_platform_front_end(std::unique_ptr<VisionFrontEnd> front_end) { platform_fe_ = std::move(front_end); }
  void set_face_front_end(std::unique_ptr<VisionFrontEnd> front_end) { face_fe_ = std::move(front_end); }

  // Vision results (frame-stamped). The estimator is corrected only by the chosen source.
  void add_instrument_result(const TargetObservation& obs);
  void add_platform_result(const TargetObservation& obs);
  void add_face_result(const TargetObservation& obs);
  void add_slam_result(const Eigen::Isometry3d& T_map_cam, const SlamSummary& summary, int map_id, Seconds t);

  void on_navdata(const NavdataSample& sample) override;
  void on_command(const MoveCommand& command, Seconds t) override;
  void on_video(const VideoFrame& frame) override;
  void set_focus(const PerceptionFocus& focus) override { focus_ = focus; }
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t) override;

  PoseEstimate predict(Seconds t) const override;
  TargetObservation instrument() const override { return instrument_; }
  TargetObservation platform() const override { return platform_; }
  TargetObservation face() const override { return face_; }
  SlamSummary slam() const override;

  const StateEstimator& estimator() const { return estimator_; }
  const PerceptionFocus& focus() const { return focus_; }

 private:
  int instrument_index(const std::string& id) const;

  LabGeometry lab_;
  StateEstimator estimator_;
  PerceptionFocus focus_;
  TargetObservation instrument_, platform_, face_;
  SlamSummary slam_;
  std::unique_ptr<VisionFrontEnd> instrument_fe_, platform_fe_, face_fe_;
};

// Rotation by pi about y: between "z into the face" (control) and "z out of the face" (face/).
Eigen::Isometry3d flip_about_y();

}  // namespace labo
