#include "drone/sim/airframe.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace labo::sim {

Airframe::Airframe(const AirframeParams& params) : p_(params) {
  constexpr double kPi = std::numbers::pi;
  const std::array<double, 4> angle{0.25 * kPi, 0.75 * kPi, 1.25 * kPi, 1.75 * kPi};
  const std::array<double, 4> spin{1.0, -1.0, 1.0, -1.0};
  for (int i = 0; i < 4; ++i) {
    const double x = p_.arm_m * std::cos(angle[static_cast<std::size_t>(i)]);
    const double y = p_.arm_m * std::sin(angle[static_cast<std::size_t>(i)]);
    mixer_(0, i) = 1.0;
    mixer_(1, i) = y;   // r × (0, 0, T): a left rotor rolls the right side down
    mixer_(2, i) = -x;  // a rear rotor pitches the nose down
    mixer_(3, i) = spin[static_cast<std::size_t>(i)] * p_.yaw_moment_m;
  }
}

double Airframe::ground_effect(double height_m) const {
  const double h = std::max(height_m + p_.rotor_height_m, 0.5 * p_.rotor_radius_m);
  const double r = p_.rotor_radius_m / (4.0 * h);
  return 1.0 / (1.0 - r * r);
}

Eigen::Vector3d Airframe::step(RigidBodyState& s, const RotorThrusts& thrust_n, const Eigen::Vector3d& wind_mps,
                               double height_m, double dt) const {
  const Eigen::Vector4d wrench =
      mixer_ * (ground_effect(height_m) * Eigen::Vector4d(thrust_n[0], thrust_n[1], thrust_n[2], thrust_n[3]));

  const Eigen::Vector3d& J = p_.inertia_kgm2;
  Eigen::Vector3d& w = s.rates_body_radps;
  w += (wrench.tail<3>() - w.cross(J.cwiseProduct(w))).cwiseQuotient(J) * dt;
  const Eigen::Vector3d turn = w * dt;
  if (const double angle = turn.norm(); angle > 0) {
    s.attitude = (s.attitude * Eigen::Quaterniond(Eigen::AngleAxisd(angle, turn / angle))).normalized();
  }

  const Eigen::Matrix3d R = s.attitude.toRotationMatrix();
  const Eigen::Vector3d v_air = s.velocity_mps - wind_mps;
  const Eigen::Vector3d v_air_body = R.transpose() * v_air;
  const double rotor_drag = p_.rotor_drag_per_s / p_.gravity_mps2;  // N per (N of thrust · m/s)
  const Eigen::Vector3d force_body(-rotor_drag * wrench(0) * v_air_body.x(), -rotor_drag * wrench(0) * v_air_body.y(),
                                   wrench(0));
  const Eigen::Vector3d force = R * force_body - p_.air_drag_kg_per_m * v_air.norm() * v_air;
  const Eigen::Vector3d a = force / p_.mass_kg - Eigen::Vector3d(0, 0, p_.gravity_mps2);
  const Eigen::Vector3d v0 = s.velocity_mps;
  s.velocity_mps += a * dt;
  s.position_m += 0.5 * (v0 + s.velocity_mps) * dt;
  return a;
}

}  // namespace labo::sim
