#pragma once
// A synthetic AR.Drone for the estimation tests: the truth integrates the model of DroneEkf with its
// own constants (optionally different from the filter's), plus pushes; it emits navdata with noise.
#include <random>
#include <utility>
#include <vector>

#include "core/frames.hpp"
#include "localization/estimation/drone_ekf.hpp"

namespace labo::test {

struct SyntheticFlight {
  explicit SyntheticFlight(unsigned seed, estimation::MotionModelConstants truth_model = {})
      : model(truth_model, estimation::EstimatorNoise{}), rng(seed) {
    estimation::StateVector s = estimation::StateVector::Zero();
    s(estimation::est::Z) = 1.0;
    model.reset(s, estimation::StateCovariance::Identity());
  }

  estimation::DroneEkf model;  // used for its derivative only
  std::mt19937 rng;
  Seconds t = 0;
  MoveCommand command;
  double floor_z = 0.0;
  double nav_noise = 1.0;  // multiplies every navdata noise
  bool report_vz = true;

  estimation::StateVector& s() { return model.mutable_state(); }

  void step(double dt) {
    const estimation::StateVector d = model.derivative(model.state(), command);
    const Eigen::Vector3d v_old = s().segment<3>(estimation::est::VX);
    s() += d * dt;
    s().segment<3>(estimation::est::X) += -d.segment<3>(estimation::est::X) * dt + 0.5 * (v_old + s().segment<3>(estimation::est::VX)) * dt;
    t += dt;
  }

  NavdataSample navdata() {
    std::normal_distribution<double> n(0.0, 1.0);
    const estimation::StateVector& x = model.state();
    NavdataSample nav;
    nav.t = t;
    nav.control_state = 3;
    nav.roll_rad = x(estimation::est::ROLL) + 0.003 * nav_noise * n(rng);
    nav.pitch_rad = x(estimation::est::PITCH) + 0.003 * nav_noise * n(rng);
    nav.yaw_rad = wrap_angle(x(estimation::est::YAW) + 0.4 + 0.002 * nav_noise * n(rng));  // arbitrary IMU yaw origin
    const double c = std::cos(x(estimation::est::YAW)), sn = std::sin(x(estimation::est::YAW));
    nav.vx_mps = c * x(estimation::est::VX) + sn * x(estimation::est::VY) + 0.03 * nav_noise * n(rng);
    nav.vy_mps = -sn * x(estimation::est::VX) + c * x(estimation::est::VY) + 0.03 * nav_noise * n(rng);
    nav.vz_mps = report_vz ? x(estimation::est::VZ) + 0.03 * nav_noise * n(rng) : 0.0;
    nav.altitude_m = (x(estimation::est::Z) - floor_z) / (std::cos(x(estimation::est::ROLL)) * std::cos(x(estimation::est::PITCH))) + 0.005 * nav_noise * n(rng);
    return nav;
  }

  Eigen::Isometry3d T_world_body() const {
    const estimation::StateVector& x = model.state();
    return make_pose(x.segment<3>(estimation::est::X), x(estimation::est::YAW), x(estimation::est::PITCH), x(estimation::est::ROLL));
  }
};

inline bool symmetric_positive_definite(const estimation::StateCovariance& P) {
  if (!P.allFinite()) return false;
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, P.cwiseAbs().maxCoeff())) return false;
  const Eigen::LLT<estimation::StateCovariance> llt(P);
  return llt.info() == Eigen::Success;
}

}  // namespace labo::test

namespace labo::test {

// Drives a SyntheticFlight and a StateEstimator together with link delays: navdata measured at t
// arrives at t + navdata_delay; a command sent at t acts from t + control_delay.
struct DelayedLink {
  SyntheticFlight& truth;
  Seconds navdata_delay = 0.0;
  Seconds control_delay = 0.0;
  double navdata_period = 1.0 / 200.0;
  std::vector<std::pair<Seconds, MoveCommand>> in_flight;  // commands on their way
  std::vector<NavdataSample> nav_in_flight;
  Seconds next_nav = 0;

  void send(const MoveCommand& c, Seconds t_now) { in_flight.emplace_back(t_now + control_delay, c); }

  // Advances the truth to t_end in 1 ms steps, calling deliver(sample) for each arriving navdata.
  template <typename F>
  void run_until(Seconds t_end, F&& deliver) {
    while (truth.t < t_end - 1e-9) {
      for (auto it = in_flight.begin(); it != in_flight.end();) {
        if (it->first <= truth.t + 1e-12) {
          truth.command = it->second;
          it = in_flight.erase(it);
        } else {
          ++it;
        }
      }
      truth.step(0.001);
      if (truth.t + 1e-9 >= next_nav) {
        NavdataSample n = truth.navdata();
        n.t = truth.t + navdata_delay;
        nav_in_flight.push_back(n);
        next_nav += navdata_period;
      }
      while (!nav_in_flight.empty() && nav_in_flight.front().t <= truth.t + 1e-12) {
        deliver(nav_in_flight.front());
        nav_in_flight.erase(nav_in_flight.begin());
      }
    }
  }
};

}  // namespace labo::test
