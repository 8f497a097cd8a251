#pragma once
// Test harness: FlightStack flying the ArdroneModel in lockstep, with ModelPipelines that localize
// perfectly from the model's true pose and "see" the instrument, platform and face by geometry (in the
// camera's field of view, in range, facing the camera). Tests switch sight off to provoke losses.
#include <cmath>
#include <memory>
#include <optional>

#include "control/flight_stack.hpp"
#include "core/frames.hpp"
#include "bench/experiments/model_lab.hpp"
#include "bench/experiments/quadrotor_model.hpp"

namespace labo::test {
using namespace labo::bench;

struct ModelWorld {
  QuadrotorModel drone;
  bool instrument_visible = true;
  bool platform_visible = true;
  bool face_visible = true;
  bool face_head_only = false;  // the face not posed, its head followed (position_only) while in the image
  double head_range_scale = 1.0;  // ... its distance read this many times the true one (the patch's scale drifted)
  bool slam_available = true;
  Eigen::Vector3d estimate_offset = Eigen::Vector3d::Zero();  // a bad estimate: truth + this
  // The pipelines' placement of the platform in the world (as the estimator's landmark), off by this;
  // nullopt: not placed. The observation's offset from the body is the camera's, always true.
  std::optional<Eigen::Vector3d> platform_placement_error;
  // The platform as the bottom camera sees it, shifted by this in the world (a camera off its
  // calibration, a jittering homography).
  Eigen::Vector3d platform_seen_shift_m = Eigen::Vector3d::Zero();
  double position_sigma_m = 0;  // the uncertainty the estimate reports
  std::optional<double> altitude_sigma_m;  // ... for the altitude (unset: position_sigma_m)
  double drift_bound_m = 0;     // ... and its dead-reckoning drift bound
  double airborne_since = -1;
  Eigen::Isometry3d T_world_face = facing_base({2.5, -0.5, 1.6});  // z into the head, looking at the base
  fusion::PerceptionFocus focus;  // what the flight stack last asked the pipelines for
};

// In the camera's image (its principal point is off-centre: the AR.Drone's front camera sees 0.39 m
// below its axis per metre of range and only 0.24 above), in range, facing the camera.
inline bool in_front_view(const Eigen::Isometry3d& T_cam_target, double max_range, const CameraIntrinsics& k) {
  const Eigen::Vector3d p = T_cam_target.translation();
  if (p.z() <= 0.1 || p.z() > max_range) return false;
  const double u = k.cx + k.fx * p.x() / p.z(), v = k.cy + k.fy * p.y() / p.z();
  if (u < 0 || u > k.width || v < 0 || v > k.height) return false;
  return T_cam_target.linear().col(2).z() > 0.3;  // the panel's z (into it) points away from the camera
}

class ModelPipelines final : public fusion::LocalizationPipelines {
 public:
  ModelPipelines(std::shared_ptr<ModelWorld> world, fusion::LabGeometry lab, CameraIntrinsics front)
      : world_(std::move(world)), lab_(std::move(lab)), front_(front) {}
  void on_navdata(const NavdataSample& s) override { t_ = s.t; }
  void on_command(const MoveCommand&, Seconds) override {}
  void on_video(const VideoFrame&) override {}
  void set_focus(const fusion::PerceptionFocus& f) override {
    focus_ = f;
    world_->focus = f;
  }
  void reset(const Eigen::Isometry3d&, Seconds) override {}
  void start_at_first_navdata(const Eigen::Isometry3d&) override {}

  fusion::PoseEstimate predict(Seconds t) const override {
    fusion::PoseEstimate e;
    e.valid = true;
    e.t = t;
    e.T_world_body = world_->drone.pose();
    e.T_world_body.translation() += world_->estimate_offset;
    e.velocity_world = world_->drone.v;
    e.yaw_rate = world_->drone.yaw_rate;
    e.quality = 1;
    e.position_sigma_m = world_->position_sigma_m;
    e.altitude_sigma_m = world_->altitude_sigma_m.value_or(world_->position_sigma_m);
    e.drift_bound_m = world_->drift_bound_m;
    const bool slam_ok = slam().state == fusion::SlamState::Good;
    switch (focus_.feedback) {
      case fusion::FeedbackSource::Homography:
        e.source = (focus_.platform ? platform() : instrument()).state == fusion::TrackState::Tracking
                       ? fusion::FeedbackSource::Homography : fusion::FeedbackSource::DeadReckoning;
        break;
      case fusion::FeedbackSource::Face:
        e.source = face().state == fusion::TrackState::Tracking ? fusion::FeedbackSource::Face : fusion::FeedbackSource::DeadReckoning;
        break;
      case fusion::FeedbackSource::Slam:
        e.source = slam_ok ? fusion::FeedbackSource::Slam : fusion::FeedbackSource::DeadReckoning;
        break;
      case fusion::FeedbackSource::DeadReckoning:
        e.source = fusion::FeedbackSource::DeadReckoning;
        break;
    }
    return e;
  }
  fusion::TargetObservation instrument() const override {
    fusion::TargetObservation o;
    const fusion::PlanarTarget* inst = lab_.find_instrument(focus_.instrument_id);
    if (!inst) return o;
    const Eigen::Isometry3d T_world_cam = world_->drone.pose() * T_body_cam_front();
    o.T_cam_target = T_world_cam.inverse() * inst->T_world_object;
    o.state = world_->instrument_visible && in_front_view(o.T_cam_target, 5.0, front_) ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.t = t_;
    return o;
  }
  fusion::TargetObservation platform() const override {
    fusion::TargetObservation o;
    if (!focus_.platform) return o;
    const Eigen::Isometry3d T_world_cam = world_->drone.pose() * T_body_cam_bottom();
    Eigen::Isometry3d T_world_seen = lab_.platform.T_world_object;
    T_world_seen.translation() += world_->platform_seen_shift_m;
    o.T_cam_target = T_world_cam.inverse() * T_world_seen;
    const Eigen::Vector3d p = o.T_cam_target.translation();
    o.state = world_->platform_visible && p.z() > 0.2 && std::abs(p.x() / p.z()) < 0.45 && std::abs(p.y() / p.z()) < 0.25
                  ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.t = t_;
    if (world_->platform_placement_error) {
      o.placed_in_world = true;
      o.T_world_target = lab_.platform.T_world_object;
      o.T_world_target.translation() += *world_->platform_placement_error;
      const Eigen::Vector3d ypr = ypr_from_rotation(world_->drone.pose().linear());
      o.offset_heading_m = fusion::offset_along_heading((T_body_cam_bottom() * o.T_cam_target).translation(), ypr[1], ypr[2]);
    }
    return o;
  }
  fusion::TargetObservation face() const override {
    fusion::TargetObservation o;
    if (!focus_.face) return o;
    const Eigen::Isometry3d T_world_cam = world_->drone.pose() * T_body_cam_front();
    o.T_cam_target = T_world_cam.inverse() * world_->T_world_face;
    if (world_->face_head_only) {
      // The head is seen whichever way it is turned; the rotation is not measured.
      Eigen::Isometry3d facing_camera = o.T_cam_target;
      facing_camera.linear() = Eigen::Matrix3d::Identity();
      o.position_only = true;
      o.T_cam_target.translation() *= world_->head_range_scale;
      o.state = in_front_view(facing_camera, 4.0, front_) ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
      o.t = t_;
      return o;
    }
    o.state = world_->face_visible && in_front_view(o.T_cam_target, 4.0, front_) ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.t = t_;
    return o;
  }
  fusion::SlamSummary slam() const override {
    fusion::SlamSummary s;
    const bool up = control_state::follows_commands(world_->drone.control_state);
    s.state = !focus_.slam ? fusion::SlamState::Off : (world_->slam_available && up ? fusion::SlamState::Good : fusion::SlamState::Initializing);
    s.scale_estimated = s.state == fusion::SlamState::Good;
    return s;
  }

 private:
  std::shared_ptr<ModelWorld> world_;
  fusion::LabGeometry lab_;
  CameraIntrinsics front_;
  fusion::PerceptionFocus focus_;
  Seconds t_ = 0;
};

class ModelFlight {
 public:
  explicit ModelFlight(control::ControlConfig config = {}, fusion::LabGeometry lab_geometry = model_lab())
      : world(std::make_shared<ModelWorld>()), lab(std::move(lab_geometry)) {
    control::FlightStackSetup setup;
    setup.control = config;
    setup.lab = lab;
    stack = std::make_unique<control::FlightStack>(setup, std::make_unique<ModelPipelines>(world, lab, setup.cameras.front));
  }
  // Advances `seconds` in 1/30 s control ticks, 5 physics sub-steps each.
  void run(double seconds) {
    const double dt = 1.0 / 30.0;
    for (double end = t + seconds; t < end - 1e-9;) {
      stack->on_navdata(world->drone.navdata(t));
      last = stack->tick(t);
      apply(last);
      for (int i = 0; i < 5; ++i) world->drone.step(dt / 5);
      t += dt;
    }
  }
  // Runs until pred() or the time-out; returns whether pred() became true.
  template <class Pred>
  bool run_until(Pred pred, double timeout_s) {
    for (double end = t + timeout_s; t < end;) {
      run(1.0 / 30.0);
      if (pred()) return true;
    }
    return false;
  }
  control::CommandResult request(control::MissionRequest r) { return stack->request(r, t); }

  std::shared_ptr<ModelWorld> world;
  fusion::LabGeometry lab;
  std::unique_ptr<control::FlightStack> stack;
  control::FlightOutput last;
  double t = 0;

 private:
  void apply(const control::FlightOutput& out) {
    switch (out.action) {
      case control::FlightOutput::Action::Move: world->drone.move(out.move); break;
      case control::FlightOutput::Action::Hover: world->drone.hover(); break;
      case control::FlightOutput::Action::Takeoff: world->drone.takeoff(); break;
      case control::FlightOutput::Action::Land: world->drone.land(); break;
      case control::FlightOutput::Action::Emergency: world->drone.emergency(); break;
      case control::FlightOutput::Action::None: break;
    }
  }
};

}  // namespace labo::test
