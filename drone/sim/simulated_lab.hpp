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

#include "drone/emulated_vehicle.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/sensor_model.hpp"

namespace labo {

struct SimulatedLabSettings {
  QuadrotorParams dynamics;
  SensorNoise sensors;
  std::uint64_t seed = 1;
};

class SimulatedLab final : public EmulatedVehicle {
 public:
  // Starts landed on the platform (lab.T_world_base) at t = 0. `renderer` must not be null.
  SimulatedLab(LabDescription lab, SimulatedLabSettings settings, std::unique_ptr<SceneRenderer> renderer);
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
  void render(CameraId camera, cv::Mat& bgr) override;

  // Ground truth and the scene the cameras see now.
  const QuadrotorState& truth() const { return dynamics_.state(); }
  SceneState scene() const;
  const LabDescription& lab() const { return lab_; }
  // Disturbances (push, wind) and the collision model, for experiments and tests.
  QuadrotorDynamics& dynamics() { return dynamics_; }
  const SimulatedLabSettings& settings() const { return settings_; }

 private:
  void step();

  LabDescription lab_;
  SimulatedLabSettings settings_;
  std::unique_ptr<SceneRenderer> renderer_;
  QuadrotorDynamics dynamics_;
  SensorModel sensors_;
  Seconds now_ = 0;
  CameraId camera_ = CameraId::Front;
};

}  // namespace labo
