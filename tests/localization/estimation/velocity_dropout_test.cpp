// The bottom camera's velocity failing over a bare floor (it relaxes to zero while the drone moves
// on, as the AR.Drone's does and drone/sim's SensorModel models) must not stop the estimate; a drone
// that really stops must still be estimated as stopped.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "localization/estimation/state_estimator.hpp"
#include "synthetic_flight.hpp"

using namespace labo;
using labo::test::DelayedLink;
using labo::test::SyntheticFlight;
using labo::test::symmetric_positive_definite;

namespace {
constexpr double kDemoPeriod = 1.0 / 15.0;  // navdata demo mode, as in the lab flights
constexpr double kFailedFlowDecayPerS = 3.0;  // drone/sim's SensorModel

// The normalized pitch command that holds `speed` forward against the drag (thrust along the tilt).
double cruise_pitch(double speed, const MotionModelConstants& m = {}) {
  return std::asin(m.drag_per_s * speed / m.thrust_accel_mps2) / m.tilt_max_rad;
}

struct Phase {
  Seconds duration = 0;
  MoveCommand command;
  bool flow_fails = false;  // the bottom camera sees no texture
};

struct Outcome {
  Eigen::Vector2d position_error = Eigen::Vector2d::Zero();  // estimate - truth at the end
  double max_position_error = 0;                              // over the run, at the packets
  Eigen::Vector2d estimated_velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d true_velocity = Eigen::Vector2d::Zero();
  std::uint64_t dropouts = 0;
  std::uint64_t dropout_packets = 0;
  std::vector<std::uint64_t> dropout_packets_after_phase;
  StateCovariance covariance;
};

// Flies `phases` from a cruise at `speed` forward (the estimate has converged on it for 3 s first);
// navdata at 15 Hz whose horizontal velocity, while the flow fails, relaxes to zero with noise.
Outcome fly(double speed, const std::vector<Phase>& phases, bool detect, unsigned seed = 5) {
  SyntheticFlight truth(seed);
  truth.s()(est::VX) = speed;
  const MoveCommand cruise{0.0, cruise_pitch(speed), 0.0, 0.0};
  truth.s()(est::PITCH) = cruise.pitch * MotionModelConstants{}.tilt_max_rad;
  EstimatorConfig config;
  config.video_delay_s = config.navdata_delay_s = config.control_delay_s = 0.0;
  config.velocity_dropout.enabled = detect;
  StateEstimator est(config);
  est.reset(truth.T_world_body(), 0.0);
  DelayedLink link{truth, 0.0, 0.0, kDemoPeriod, {}, {}, 0.0};
  std::mt19937 rng(seed + 100);
  std::normal_distribution<double> noise(0.0, 0.03);
  bool failing = false;
  Eigen::Vector2d failed_flow = Eigen::Vector2d::Zero();
  Seconds last_t = 0;
  Outcome out;
  const auto deliver = [&](NavdataSample n) {
    if (failing) {
      failed_flow *= std::exp(-kFailedFlowDecayPerS * (n.t - last_t));
      n.vx_mps = failed_flow.x() + noise(rng);
      n.vy_mps = failed_flow.y() + noise(rng);
    } else {
      failed_flow = Eigen::Vector2d(n.vx_mps, n.vy_mps);
    }
    last_t = n.t;
    est.add_navdata(n);
    const FusedState f = est.predict(n.t);
    out.max_position_error = std::max(out.max_position_error, (f.position_world - truth.s().segment<3>(est::X)).head<2>().norm());
  };
  std::vector<Phase> all{{3.0, cruise, false}};
  all.insert(all.end(), phases.begin(), phases.end());
  for (std::size_t i = 0; i < all.size(); ++i) {
    link.send(all[i].command, truth.t);
    est.add_command(all[i].command, truth.t);
    failing = all[i].flow_fails;
    link.run_until(truth.t + all[i].duration, deliver);
    if (i > 0) out.dropout_packets_after_phase.push_back(est.statistics().count("velocity_dropout_packets"));
  }
  const FusedState f = est.predict(truth.t);
  out.position_error = (f.position_world - truth.s().segment<3>(est::X)).head<2>();
  out.estimated_velocity = f.velocity_world.head<2>();
  out.true_velocity = truth.s().segment<2>(est::VX);
  out.dropouts = est.statistics().count("velocity_dropouts");
  out.dropout_packets = est.statistics().count("velocity_dropout_packets");
  out.covariance = f.covariance;
  return out;
}
}  // namespace

TEST_CASE("estimation: a 2 s velocity dropout at 0.5 m/s does not stop the estimate") {
  const double speed = 0.5;
  const MoveCommand cruise{0.0, cruise_pitch(speed), 0.0, 0.0};
  const std::vector<Phase> phases{{2.0, cruise, true}, {1.0, cruise, false}};
  const Outcome fused = fly(speed, phases, false);
  const Outcome detected = fly(speed, phases, true);
  INFO("position error after the dropout and 1 s of flow: fusing every velocity " << fused.position_error.norm()
       << " m (max " << fused.max_position_error << "), with detection " << detected.position_error.norm() << " m (max "
       << detected.max_position_error << ")");
  // Fusing the relaxing zero loses most of the 1 m flown in the dropout.
  CHECK(fused.position_error.norm() > 0.5);
  CHECK(detected.dropouts == 1);
  CHECK(detected.position_error.norm() < 0.1);
  CHECK(detected.max_position_error < 0.1);
  // The flow is back: fused again from its second packet (30 packets at 15 Hz failed, some before the
  // onset was seen), and the velocity is right.
  CHECK(detected.dropout_packets <= 31);
  CHECK((detected.estimated_velocity - detected.true_velocity).norm() < 0.05);
  CHECK(symmetric_positive_definite(detected.covariance));
}

TEST_CASE("estimation: a velocity dropout starting from a hover is caught when the drone tilts away") {
  // The flow fails while the drone hovers (reading zero is right), then the drone accelerates.
  const MoveCommand hover{};
  const MoveCommand go{0.3, 0.3, 0.0, 0.0};
  const std::vector<Phase> phases{{1.0, hover, true}, {1.5, go, true}, {1.0, hover, false}};
  const Outcome fused = fly(0.0, phases, false);
  const Outcome detected = fly(0.0, phases, true);
  INFO("position error: fusing every velocity " << fused.position_error.norm() << " m, with detection "
       << detected.position_error.norm() << " m");
  CHECK(fused.position_error.norm() > 0.5);
  CHECK(detected.dropouts >= 1);
  CHECK(detected.position_error.norm() < 0.15);
}

TEST_CASE("estimation: a drone that really stops is estimated as stopped (no false dropout)") {
  // Without a false dropout the estimate is the one that fuses every velocity, to the bit.
  constexpr double speed = 0.5;
  const MoveCommand brake{0.0, -0.6, 0.0, 0.0};
  const MoveCommand level{};
  const auto check_no_dropout = [](const std::vector<Phase>& phases) {
    const Outcome o = fly(speed, phases, true);
    const Outcome fused = fly(speed, phases, false);
    INFO("true velocity " << o.true_velocity.transpose() << ", estimated " << o.estimated_velocity.transpose());
    CHECK(o.dropouts == 0);
    CHECK(o.dropout_packets == 0);
    CHECK(o.position_error == fused.position_error);
    CHECK(o.position_error.norm() < 0.05);
    return o;
  };
  SECTION("braking hard, then levelled") {
    const Outcome o = check_no_dropout({{0.5, brake, false}, {3.0, level, false}});
    CHECK(o.true_velocity.norm() < 0.05);
    CHECK(o.estimated_velocity.norm() < 0.1);
  }
  SECTION("levelled at once, slowing by the drag alone") {
    check_no_dropout({{5.0, level, false}});
  }
  SECTION("random manoeuvres, 15 Hz navdata") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    std::vector<Phase> phases;
    for (int k = 0; k < 30; ++k) phases.push_back({0.7, MoveCommand{u(rng), u(rng), 0.0, u(rng)}, false});
    const Outcome o = fly(speed, phases, true);
    CHECK(o.dropouts == 0);
    CHECK(o.position_error.norm() < 0.3);
  }
}

TEST_CASE("estimation: a drone that stops during a velocity dropout is fused again once it is at rest") {
  // Over the bare floor the drone brakes and hovers: the zero it reads is right again, and the
  // estimator must take it (the model alone would drift on).
  const double speed = 0.5;
  const MoveCommand cruise{0.0, cruise_pitch(speed), 0.0, 0.0};
  const MoveCommand brake{0.0, -0.6, 0.0, 0.0};
  const Outcome o = fly(speed, {{1.0, cruise, true}, {0.4, brake, true}, {3.0, MoveCommand{}, true}}, true);
  INFO("dropout packets after each phase: " << o.dropout_packets_after_phase[0] << ", "
       << o.dropout_packets_after_phase[1] << ", " << o.dropout_packets_after_phase[2]);
  CHECK(o.dropouts >= 1);
  CHECK(o.dropout_packets_after_phase[2] < o.dropout_packets_after_phase[1] + 30);  // resumed within 2 s of 3
  CHECK(o.estimated_velocity.norm() < 0.05);
  CHECK(o.position_error.norm() < 0.15);
}
