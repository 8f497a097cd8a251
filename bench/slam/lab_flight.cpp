#include "bench/slam/lab_flight.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/frames.hpp"
#include "drone/sim/lab_renderer.hpp"

namespace labo::bench {

using lab::InstrumentSpec;
using lab::LabDescription;

using lab::InstrumentSpec;
using lab::LabDescription;

using sim::LabRenderOptions;
using sim::LabRenderer;
using sim::SceneState;

namespace {

constexpr double kGravity = 9.81;
constexpr double kStandoffM = 0.8;
constexpr double kPeakSpeedMps = 1.4;  // the inspect mission's approach in the simulated lab

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Quintic ease (zero velocity and acceleration at both ends: the pitch ramps, no step) and its second
// derivative over [0, 1]. Peak speed 1.875 x the mean.
double smootherstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6 * x - 15) + 10);
}
double smootherstep_acceleration(double x) { return x <= 0 || x >= 1 ? 0.0 : x * (60 + x * (-180 + 120 * x)); }

// Both lab flights start as the missions do: a hover on the platform, the climb to their cruise
// height, the scale manoeuvre (up 0.4 m and back); it ends at kTakeOffEndS.
constexpr double kClimbFromS = 1.0, kClimbS = 2.5;
constexpr double kManoeuvreFromS = kClimbFromS + kClimbS + 0.5, kManoeuvreS = 8.0;
constexpr double kTakeOffEndS = kManoeuvreFromS + kManoeuvreS;

// The platform's top, where the drone stands, and the yaw it stands at.
Eigen::Vector3d platform_top(const LabDescription& lab) {
  return lab.T_world_base.translation() + Eigen::Vector3d(0, 0, lab.platform.thickness_m);
}
double base_yaw(const LabDescription& lab) { return std::atan2(lab.T_world_base.linear()(1, 0), lab.T_world_base.linear()(0, 0)); }

Eigen::Vector3d take_off_position(const Eigen::Vector3d& base, double cruise_z, Seconds t) {
  Eigen::Vector3d p = base + Eigen::Vector3d(0, 0, (cruise_z - base.z()) * smoothstep((t - kClimbFromS) / kClimbS));
  p.z() += 0.4 * std::sin(M_PI * std::clamp((t - kManoeuvreFromS) / kManoeuvreS, 0.0, 1.0));
  return p;
}

}  // namespace

Flight lab_inspect_flight(const LabDescription& lab, const InstrumentSpec& instrument, double fps) {
  Flight f;
  f.name = "lab-inspect";
  const Eigen::Vector3d face = instrument.T_world_object.translation();
  const Eigen::Vector3d into_panel = instrument.T_world_object.linear().col(2);  // object z: into the housing
  f.target = face;
  const Eigen::Isometry3d cam_in_body = T_body_cam_front();
  const double cam_ahead = cam_in_body.translation().x();
  const Eigen::Vector3d base = platform_top(lab);
  const double start_yaw = base_yaw(lab);
  const double cruise_z = face.z() + 0.05;
  // Where the camera holds: 0.8 m in front of the panel, facing it; the body is behind the camera.
  const Eigen::Vector3d facing = Eigen::Vector3d(into_panel.x(), into_panel.y(), 0).normalized();
  const double approach_yaw = std::atan2(facing.y(), facing.x());
  const Eigen::Vector3d hold_body = face - kStandoffM * facing - cam_ahead * facing;
  const Eigen::Vector3d climb_top(base.x(), base.y(), cruise_z);
  // Timeline (s): the take-off, turn, approach, hold.
  const double turn_from = kTakeOffEndS, turn_s = 1.5;
  const double leg = (hold_body - climb_top).norm();
  const double approach_from = turn_from + turn_s, approach_s = 1.875 * leg / kPeakSpeedMps;
  const double end = approach_from + approach_s + 3.0;
  const double turn_yaw = std::atan2(hold_body.y() - climb_top.y(), hold_body.x() - climb_top.x());
  for (int i = 0; i < static_cast<int>(end * fps); ++i) {
    const Seconds t = i / fps;
    Eigen::Vector3d p = take_off_position(base, cruise_z, t);
    // Turn towards the hold point, fly the straight leg, and face the panel squarely at the end.
    const double s = (t - approach_from) / approach_s;
    double yaw = start_yaw + (turn_yaw - start_yaw) * smoothstep((t - turn_from) / turn_s);
    yaw += (approach_yaw - turn_yaw) * smoothstep((s - 0.6) / 0.4);
    p += (hold_body - climb_top) * smootherstep(s);
    // The body pitches to accelerate along the leg (nose down) and to brake (nose up).
    const double acceleration = leg * smootherstep_acceleration(s) / (approach_s * approach_s);
    const double pitch = std::atan(acceleration / kGravity) * std::cos(yaw - turn_yaw);
    const double wobble = 0.01 * std::sin(1.7 * t);
    f.frames.push_back({t, make_pose(p, yaw, pitch + wobble, 0.01 * std::sin(1.1 * t + 1)) * cam_in_body, false});
  }
  return f;
}

Flight lab_sweep_flight(const LabDescription& lab, double yaw_rate, int sweeps, double orbit_m, double fps) {
  Flight f;
  f.name = "lab-sweep";
  const Eigen::Isometry3d cam_in_body = T_body_cam_front();
  const Eigen::Vector3d base = platform_top(lab);
  const double start_yaw = base_yaw(lab);
  constexpr double kFaceHeightM = 1.6;
  // Timeline (s): the take-off at face height, a second's hover, the sweeps.
  const double sweep_from = kTakeOffEndS + 1.0, sweep_s = sweeps * 2 * M_PI / yaw_rate;
  const double end = sweep_from + sweep_s + 1.0;
  for (int i = 0; i < static_cast<int>(end * fps); ++i) {
    const Seconds t = i / fps;
    Eigen::Vector3d p = take_off_position(base, kFaceHeightM, t);
    const double swept = yaw_rate * std::clamp(t - sweep_from, 0.0, sweep_s);
    const double yaw = start_yaw + swept;
    // Out onto the circle over the first half turn, so the motion has no step.
    const double radius = orbit_m * smoothstep(swept / M_PI);
    p += radius * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
    const double wobble = 0.01 * std::sin(1.7 * t);
    f.frames.push_back({t, make_pose(p, yaw, wobble, 0.01 * std::sin(1.1 * t + 1)) * cam_in_body, false});
  }
  return f;
}

SimulatedLabFrames::SimulatedLabFrames(const LabDescription& lab, const CamerasConfig& cameras, bool noise) {
  LabRenderOptions options;
  options.noise = noise;
  renderer_ = std::make_unique<LabRenderer>(lab, cameras, std::nullopt, 1, options);
}

SimulatedLabFrames::~SimulatedLabFrames() = default;

cv::Mat SimulatedLabFrames::render(const Flight& flight, std::size_t i) {
  const Eigen::Isometry3d body_cam_inv = LabRenderer::T_body_cam(CameraId::Front).inverse();
  auto body = [&](std::size_t k) { return flight.frames[k].T_world_cam * body_cam_inv; };
  const std::size_t a = i > 0 ? i - 1 : i, b = std::min(i + 1, flight.frames.size() - 1);
  SceneState scene;
  scene.t = flight.frames[i].t;
  scene.T_world_body = body(i);
  scene.teacher_present = false;
  if (b > a) {
    const double dt = flight.frames[b].t - flight.frames[a].t;
    const Eigen::Isometry3d A = body(a), B = body(b);
    scene.velocity_world_mps = (B.translation() - A.translation()) / dt;
    const Eigen::AngleAxisd turn(A.linear().transpose() * B.linear());
    scene.angular_velocity_body_radps = turn.axis() * turn.angle() / dt;
  }
  renderer_->render(CameraId::Front, scene, bgr_);
  cv::Mat gray;
  cv::cvtColor(bgr_, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

}  // namespace labo::bench
