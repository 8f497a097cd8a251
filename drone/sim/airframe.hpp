#pragma once
// Airframe: the AR.Drone 2.0 as a rigid body, the physical half of the simulated lab's plant
// (QuadrotorDynamics; the firmware's loops that fly it are FirmwareLoops). Newton-Euler equations of
// a body of `mass_kg` and diagonal inertia, pushed by four rotors in an X:
//  - each rotor's thrust acts along the body's z at its place on the arms; its drag torque turns the
//    body about z (alternate spin directions);
//  - rotor drag: the rotors' induced drag opposes the air-relative velocity in the rotor plane, in
//    proportion to the thrust (per unit mass it is `rotor_drag_per_s` in hover, whatever the mass);
//  - air drag on the hull, quadratic in the air-relative speed;
//  - ground effect: near the surface below, the rotors' thrust grows by 1 / (1 - (R / 4h)^2)
//    (Cheeseman-Bennett), h the rotor plane's height above that surface, bounded at h = R / 2.
// Integrated semi-implicitly (rates, then attitude on SO(3); velocity, then position).
#include <Eigen/Geometry>
#include <array>

namespace labo::sim {

struct AirframeParams {
  double mass_kg = 0.42;                                        // with the indoor hull
  Eigen::Vector3d inertia_kgm2 = Eigen::Vector3d(2.24e-3, 2.99e-3, 4.80e-3);  // about body x, y, z
  double arm_m = 0.18;                                          // body centre to a rotor's axis
  double rotor_radius_m = 0.10;
  double rotor_height_m = 0.06;                                 // rotor plane above the hull's underside
  double yaw_moment_m = 0.025;                                  // rotor drag torque per newton of thrust
  double rotor_drag_per_s = 0.50;                               // induced drag per unit mass in hover
  double air_drag_kg_per_m = 0.034;                             // ½·ρ·Cd·A of the hull: F = −k·|v|·v
  double gravity_mps2 = 9.80665;
};

// Rotor order: front-left, rear-left, rear-right, front-right (body x forward, y left).
using RotorThrusts = std::array<double, 4>;

struct RigidBodyState {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();    // hull underside centre, world
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  // world
  Eigen::Quaterniond attitude = Eigen::Quaterniond::Identity();  // world from body
  Eigen::Vector3d rates_body_radps = Eigen::Vector3d::Zero();
};

class Airframe {
 public:
  explicit Airframe(const AirframeParams& params);

  // The collective thrust and body torques of four rotor thrusts: [F, τx, τy, τz] = mixer · T.
  const Eigen::Matrix4d& mixer() const { return mixer_; }
  // The thrust factor of the ground effect with the underside `height_m` above the surface below.
  double ground_effect(double height_m) const;
  // One sub-step of `dt` under the rotors' thrusts, in `wind_mps` (world), the underside `height_m`
  // above the surface below. Returns the world acceleration over the step.
  Eigen::Vector3d step(RigidBodyState& s, const RotorThrusts& thrust_n, const Eigen::Vector3d& wind_mps,
                       double height_m, double dt) const;
  const AirframeParams& params() const { return p_; }

 private:
  AirframeParams p_;
  Eigen::Matrix4d mixer_;
};

}  // namespace labo::sim
