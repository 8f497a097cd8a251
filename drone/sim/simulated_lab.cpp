#include "drone/sim/simulated_lab.hpp"

#include <stdexcept>

namespace labo {

namespace {
// A time within this of a step boundary counts as reaching it (the emulator's clock is a double).
constexpr Seconds kTimeEpsilon = 1e-9;
}  // namespace

SimulatedLab::SimulatedLab(LabDescription lab, SimulatedLabSettings settings, std::unique_ptr<SceneRenderer> renderer)
    : lab_(std::move(lab)),
      settings_(settings),
      renderer_(std::move(renderer)),
      dynamics_(settings_.dynamics, CollisionModel(lab_, settings_.dynamics.hull), lab_.T_world_base),
      sensors_(settings_.sensors, lab_, settings_.seed) {
  if (!renderer_) throw std::invalid_argument("SimulatedLab needs a SceneRenderer");
  sensors_.update(dynamics_.state(), 0.0);
}

void SimulatedLab::advance_to(Seconds t) {
  const Seconds step = settings_.dynamics.step_s;
  while (dynamics_.state().t + step <= t + kTimeEpsilon) this->step();
  now_ = std::max(now_, t);
}

void SimulatedLab::step() {
  dynamics_.set_velocity_observable(sensors_.velocity_valid());
  dynamics_.step();
  sensors_.update(dynamics_.state(), settings_.dynamics.step_s);
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
  tel.nav.control_state = control_state(s.phase);
  tel.nav.battery_percent = s.battery_percent;
  tel.flying = s.airborne();
  tel.emergency = s.phase == FirmwarePhase::Emergency;
  tel.motors_cut = tel.emergency;
  tel.battery_low = s.battery_percent < settings_.dynamics.battery_low_percent;
  tel.wind_speed_mps = 0;
  return tel;
}

SceneState SimulatedLab::scene() const {
  const QuadrotorState& s = dynamics_.state();
  SceneState scene;
  scene.t = s.t;
  scene.T_world_body = s.T_world_body();
  scene.velocity_world_mps = s.velocity_mps;
  scene.angular_velocity_body_radps = s.angular_velocity_body_radps;
  scene.teacher_present = false;  // the walking teacher comes with TeacherMotion
  return scene;
}

void SimulatedLab::render(CameraId camera, cv::Mat& bgr) { renderer_->render(camera, scene(), bgr); }

}  // namespace labo
