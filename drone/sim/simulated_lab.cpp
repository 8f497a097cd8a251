#include "drone/sim/simulated_lab.hpp"

#include <cmath>
#include <stdexcept>

#include "core/cpu_time.hpp"

namespace labo::sim {

using lab::InstrumentSpec;
using lab::LabDescription;


namespace {
// A time within this of a step boundary counts as reaching it (the emulator's clock is a double).
constexpr Seconds kTimeEpsilon = 1e-9;
// The teacher's body as an obstacle: up to just above the head.
constexpr double kAboveEyes_m = 0.15;

// The firmware levels its own attitude estimate: the sensors' bias is the plant's too.
QuadrotorParams with_attitude_bias(QuadrotorParams p, const SensorBiases& biases) {
  p.deviation.attitude_bias_rad = biases.attitude_rad;
  return p;
}
}  // namespace

SimulatedLab::SimulatedLab(LabDescription lab, SimulatedLabSettings settings, std::unique_ptr<SceneRenderer> renderer)
    : lab_(std::move(lab)),
      settings_(settings),
      renderer_(std::move(renderer)),
      dynamics_(with_attitude_bias(settings_.dynamics, settings_.biases), CollisionModel(lab_, settings_.dynamics.hull),
                lab_.T_world_base),
      sensors_(settings_.sensors, lab_, settings_.seed, settings_.biases) {
  if (!renderer_) throw std::invalid_argument("SimulatedLab needs a SceneRenderer");
  if (settings_.teacher && !lab_.teacher.waypoints.empty()) teacher_.emplace(lab_.teacher);
  for (const auto& d : settings_.disturbances) disturbances_.add(d);
  apply_disturbances(-1.0, 0.0);
  sensors_.update(dynamics_.state(), 0.0);
}

void SimulatedLab::advance_to(Seconds t) {
  const Seconds step = settings_.dynamics.step_s;
  while (dynamics_.state().t + step <= t + kTimeEpsilon) this->step();
  now_ = std::max(now_, t);
}

void SimulatedLab::step() {
  const double start = profiling_ ? process_cpu_seconds() : 0.0;
  const Seconds t = dynamics_.state().t, step = settings_.dynamics.step_s;
  apply_disturbances(t, t + step);
  dynamics_.set_velocity_observable(sensors_.velocity_valid());
  dynamics_.step();
  if (!profiling_) {
    sensors_.update(dynamics_.state(), step);
    return;
  }
  const double physics_end = process_cpu_seconds();
  sensors_.update(dynamics_.state(), step);
  profile_.physics_s += physics_end - start;
  profile_.sensors_s += process_cpu_seconds() - physics_end;
  ++profile_.steps;
}

// Everything the world does to the drone over the step (from, to]: scheduled pushes, the wind, and
// the teacher's body where it stands at the step's end.
void SimulatedLab::apply_disturbances(Seconds from, Seconds to) {
  const double yaw = dynamics_.state().yaw_rad, c = std::cos(yaw), s = std::sin(yaw);
  disturbances_.for_each_impulse(from, to, [&](const Disturbance& d) {
    const Eigen::Vector3d& h = d.dv_heading_mps;
    dynamics_.push({c * h.x() - s * h.y(), s * h.x() + c * h.y(), h.z()}, d.dyaw_rad);
  });
  dynamics_.set_wind(disturbances_.wind_at(to));
  if (teacher_) {
    teacher_->advance(to, dynamics_.state().position_m, lab_);
    const TeacherPose& p = teacher_->pose();
    dynamics_.collision().set_teacher(p.floor_xy, lab_.teacher.body_radius_m, lab_.teacher.eye_height_m + kAboveEyes_m);
  }
}

void SimulatedLab::takeoff(Seconds t) {
  advance_to(t);
  dynamics_.takeoff();
}

void SimulatedLab::land(Seconds t) {
  advance_to(t);
  dynamics_.land();
}

void SimulatedLab::emergency(Seconds t) {
  advance_to(t);
  dynamics_.emergency();
}

void SimulatedLab::flat_trim(Seconds t) {
  advance_to(t);
  sensors_.flat_trim(dynamics_.state());
}

void SimulatedLab::move(const MoveCommand& command, bool hover, Seconds t) {
  advance_to(t);
  dynamics_.move(command, hover);
}

void SimulatedLab::select_camera(CameraId camera, Seconds t) {
  advance_to(t);
  camera_ = camera;
}

VehicleTelemetry SimulatedLab::telemetry() const {
  const QuadrotorState& s = dynamics_.state();
  VehicleTelemetry tel = sensors_.telemetry();
  tel.nav.control_state = to_control_state(s.phase);
  tel.nav.battery_percent = s.battery_percent;
  tel.flying = s.airborne();
  tel.emergency = s.phase == FirmwarePhase::Emergency;
  tel.motors_cut = tel.emergency;
  tel.battery_low = s.battery_percent < settings_.dynamics.battery.low_percent;
  tel.wind_speed_mps = 0;
  return tel;
}

void SimulatedLab::add_instrument(const InstrumentSpec& instrument) {
  renderer_->add_instrument(instrument);  // first: it throws for a template it cannot read
  lab_.instruments.push_back(instrument);
  dynamics_.collision() = CollisionModel(lab_, settings_.dynamics.hull);
  sensors_.add_instrument(instrument);
}

SceneState SimulatedLab::scene() const {
  const QuadrotorState& s = dynamics_.state();
  SceneState scene;
  scene.t = s.t;
  scene.T_world_body = s.T_world_body();
  scene.velocity_world_mps = s.velocity_mps;
  scene.angular_velocity_body_radps = s.angular_velocity_body_radps;
  scene.teacher_present = teacher_.has_value();
  scene.exposure_gain = disturbances_.exposure_gain_at(s.t);
  if (teacher_) {
    const TeacherPose& p = teacher_->pose();
    scene.T_world_head = p.T_world_head;
    scene.teacher_floor_xy = p.floor_xy;
  }
  return scene;
}

void SimulatedLab::render(CameraId camera, cv::Mat& bgr) {
  if (video_dropout()) {
    bgr.release();
    return;
  }
  const double start = profiling_ ? process_cpu_seconds() : 0.0;
  renderer_->render(camera, scene(), bgr);
  if (profiling_) {
    profile_.render_s += process_cpu_seconds() - start;
    ++profile_.renders;
  }
}

}  // namespace labo::sim
