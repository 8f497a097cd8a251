#pragma once
// SimulatedLab: the simulated remote lab as an AR.Drone 2.0 (EmulatedVehicle), for the protocol
// emulator on loopback (drone/ardrone2/ardrone_emulator.hpp) and for lockstep runs. It composes the
// firmware-level flight dynamics (QuadrotorDynamics), the drone's sensors (SensorModel) and the
// cameras (an injected SceneRenderer, chosen by make_scene_renderer() in sim_setup.hpp), on one
// simulated clock advanced in fixed physics steps: the same seed and the same command times give the
// same flight bit for bit. Not thread-safe (the emulator serialises every call).
//
// Body frame origin: the hull's underside centre (the ultrasound's reference), so the true body z
// above the surface below is what the ultrasound measures. The cameras are mounted as in
// core/frames.hpp (front 0.2 m ahead, bottom 5 cm below the origin).
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "drone/emulated_vehicle.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/disturbances.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/sensor_model.hpp"
#include "drone/sim/teacher_walker.hpp"

namespace labo::sim {

struct SimulatedLabSettings {
  QuadrotorParams dynamics;
  SensorNoise sensors;
  SensorBiases biases;  // their attitude bias is also the firmware's (QuadrotorDynamics flies level to it)
  std::uint64_t seed = 1;
  bool teacher = true;  // the teacher walks the lab's path: in the cameras' view, an obstacle, giving way to the drone
  std::vector<Disturbance> disturbances;
};

// Where the simulation's time goes (process CPU seconds), when profiling is on.
struct SimProfile {
  double physics_s = 0, sensors_s = 0, render_s = 0;
  long steps = 0, renders = 0;
};

class SimulatedLab final : public EmulatedVehicle {
 public:
  // Starts landed on the platform (lab.T_world_base) at t = 0. `renderer` must not be null.
  SimulatedLab(lab::LabDescription lab, SimulatedLabSettings settings, std::unique_ptr<SceneRenderer> renderer);
  SimulatedLab(const SimulatedLab&) = delete;
  SimulatedLab& operator=(const SimulatedLab&) = delete;

  // EmulatedVehicle: commands take effect at the first physics step after t.
  void takeoff(Seconds t) override;
  void land(Seconds t) override;
  void emergency(Seconds t) override;
  void flat_trim(Seconds t) override;
  void move(const MoveCommand& command, bool hover, Seconds t) override;
  void select_camera(CameraId camera, Seconds t) override;
  void advance_to(Seconds t) override;
  Seconds now() const override { return now_; }
  VehicleTelemetry telemetry() const override;
  CameraId selected_camera() const override { return camera_; }
  // During a scheduled video dropout `bgr` is left empty: the emulator then sends no frame.
  void render(CameraId camera, cv::Mat& bgr) override;

  // Ground truth and the scene the cameras see now.
  const QuadrotorState& truth() const { return dynamics_.state(); }
  SceneState scene() const;
  const lab::LabDescription& lab() const { return lab_; }
  // An instrument placed while the lab runs (an admin's upload): an obstacle, a surface under the
  // ultrasound and a panel in the cameras' view from the next step. Throws std::runtime_error when its
  // template cannot be read (the lab is left as it was).
  void add_instrument(const lab::InstrumentSpec& instrument);
  // Disturbances from now on (in addition to the settings' ones).
  void schedule(const Disturbance& disturbance) { disturbances_.add(disturbance); }
  bool video_dropout() const { return disturbances_.video_dropout_at(dynamics_.state().t); }
  // A scheduled link outage at time t (SimDroneLink drops everything then).
  bool link_outage(Seconds t) const { return disturbances_.link_outage_at(t); }
  // Direct access for experiments and tests (e.g. QuadrotorDynamics::push between steps).
  QuadrotorDynamics& dynamics() { return dynamics_; }
  const SimulatedLabSettings& settings() const { return settings_; }

  // CPU cost of physics, sensors and rendering (off by default: it reads the clock per step).
  void set_profiling(bool on) { profiling_ = on; }
  const SimProfile& profile() const { return profile_; }

 private:
  void step();
  void apply_disturbances(Seconds from, Seconds to);

  lab::LabDescription lab_;
  SimulatedLabSettings settings_;
  std::unique_ptr<SceneRenderer> renderer_;
  QuadrotorDynamics dynamics_;
  SensorModel sensors_;
  std::optional<TeacherWalker> teacher_;
  DisturbanceSchedule disturbances_;
  Seconds now_ = 0;
  CameraId camera_ = CameraId::Front;
  bool profiling_ = false;
  SimProfile profile_;
};

}  // namespace labo::sim
