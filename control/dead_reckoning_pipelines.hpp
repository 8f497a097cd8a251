#pragma once
// Localization from navdata alone: yaw from the IMU (offset at reset), height from the ultrasound,
// horizontal position integrated from the body-frame velocities. No vision: the instrument, platform
// and face are never seen and SLAM is off. The paper's "black/red" source - what the filter falls back
// to. FlightStack uses it until the lab pipelines (estimator + planar + SLAM + face) are wired in, and
// it is honest about it: every pose is reported as DeadReckoning.
#include "control/localization_pipelines.hpp"

namespace labo {

class DeadReckoningPipelines final : public LocalizationPipelines {
 public:
  void on_navdata(const NavdataSample& sample) override;
  void on_command(const MoveCommand&, Seconds) override {}
  void on_video(const VideoFrame&) override {}
  void set_focus(const PerceptionFocus&) override {}
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t) override;

  PoseEstimate predict(Seconds t) const override;
  TargetObservation instrument() const override { return {}; }
  TargetObservation platform() const override { return {}; }
  TargetObservation face() const override { return {}; }
  SlamSummary slam() const override { return {}; }

 private:
  bool have_nav_ = false;
  Seconds t_ = 0;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_ = Eigen::Vector3d::Zero();
  double yaw_ = 0;
  double yaw_offset_ = 0;
  double yaw_rate_ = 0;
  double last_raw_yaw_ = 0;
  bool yaw_anchored_ = false;
  double pitch_ = 0, roll_ = 0;
  double travelled_m_ = 0;
};

}  // namespace labo
