// The bottom camera's velocity failing over a bare floor (it relaxes to zero while the drone moves
// on, as the AR.Drone's does and drone/sim's SensorModel models) must not stop the estimate; a drone
// that really stops must still be estimated as stopped.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>

#include "localization/estimation/state_estimator.hpp"
#include "localization/estimation/velocity_dropout_detector.hpp"
#include "synthetic_flight.hpp"

using namespace labo;
using namespace labo::estimation;
using labo::test::DelayedLink;
using labo::test::SyntheticFlight;
using labo::test::symmetric_positive_definite;

namespace {
constexpr double kDemoPeriod = 1.0 / 15.0;  // navdata demo mode, as in the lab flights
constexpr double kFailedFlowDecayPerS = 3.0;  // drone/sim's SensorModel

// The normalized pitch command that holds `speed` forward against the drag (thrust along the tilt).
double cruise_pitch(double speed, const estimation::MotionModelConstants& m = {}) {
  return std::asin(m.drag_per_s * speed / m.thrust_accel_mps2) / m.tilt_max_rad;
}

struct Phase {
  Seconds duration = 0;
  MoveCommand command;
  bool flow_fails = false;  // the bottom camera sees no texture
  Eigen::Vector2d push = Eigen::Vector2d::Zero();  // a velocity change at the phase's start (world, m/s)
};

struct Outcome {
  Eigen::Vector2d position_error = Eigen::Vector2d::Zero();  // estimate - truth at the end
  double max_position_error = 0;                              // over the run, at the packets
  Eigen::Vector2d estimated_velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d true_velocity = Eigen::Vector2d::Zero();
  std::uint64_t dropouts = 0;
  std::uint64_t dropout_packets = 0;
  std::vector<std::uint64_t> dropout_packets_after_phase;
  estimation::StateCovariance covariance;
};

// Flies `phases` from a cruise at `speed` forward (for 4 s first: the estimate converges and the dropout
// detector learns the tilt offset, VelocityDropoutDetector::kBiasWarmup);
// navdata at 15 Hz whose horizontal velocity, while the flow fails, relaxes to zero with noise.
Outcome fly(double speed, const std::vector<Phase>& phases, bool detect, unsigned seed = 5,
            double imu_offset_rad = 0.0) {
  SyntheticFlight truth(seed);
  truth.s()(est::VX) = speed;
  const MoveCommand cruise{0.0, cruise_pitch(speed), 0.0, 0.0};
  truth.s()(est::PITCH) = cruise.pitch * estimation::MotionModelConstants{}.tilt_max_rad;
  estimation::EstimatorConfig config;
  config.video_delay_s = config.navdata_delay_s = config.control_delay_s = 0.0;
  config.velocity_dropout.enabled = detect;
  estimation::StateEstimator est(config);
  est.reset(truth.T_world_body(), 0.0);
  DelayedLink link{truth, 0.0, 0.0, kDemoPeriod, {}, {}, 0.0};
  std::mt19937 rng(seed + 100);
  std::normal_distribution<double> noise(0.0, 0.03);
  bool failing = false;
  Eigen::Vector2d failed_flow = Eigen::Vector2d::Zero();
  Seconds last_t = 0;
  Outcome out;
  const auto deliver = [&](NavdataSample n) {
    n.roll_rad += imu_offset_rad;  // the IMU's roll/pitch offset without a flat trim
    n.pitch_rad -= imu_offset_rad;
    if (failing) {
      failed_flow *= std::exp(-kFailedFlowDecayPerS * (n.t - last_t));
      n.vx_mps = failed_flow.x() + noise(rng);
      n.vy_mps = failed_flow.y() + noise(rng);
    } else {
      failed_flow = Eigen::Vector2d(n.vx_mps, n.vy_mps);
    }
    last_t = n.t;
    est.add_navdata(n);
    const estimation::FusedState f = est.predict(n.t);
    out.max_position_error = std::max(out.max_position_error, (f.position_world - truth.s().segment<3>(est::X)).head<2>().norm());
  };
  std::vector<Phase> all{{4.0, cruise, false}};
  all.insert(all.end(), phases.begin(), phases.end());
  for (std::size_t i = 0; i < all.size(); ++i) {
    link.send(all[i].command, truth.t);
    est.add_command(all[i].command, truth.t);
    failing = all[i].flow_fails;
    truth.s().segment<2>(est::VX) += all[i].push;
    link.run_until(truth.t + all[i].duration, deliver);
    if (i > 0) out.dropout_packets_after_phase.push_back(est.statistics().count("velocity_dropout_packets"));
  }
  const estimation::FusedState f = est.predict(truth.t);
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
  // Over 10 seeds: the estimate carried across by the model is within a centimetre or two at the
  // resume; the first fused packets then move the position too (the dropout left the position and
  // velocity correlated), by up to ~0.1 m on a noisy sample.
  const double speed = 0.5;
  const MoveCommand cruise{0.0, cruise_pitch(speed), 0.0, 0.0};
  const std::vector<Phase> phases{{2.0, cruise, true}, {1.0, cruise, false}};
  std::vector<double> errors;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const Outcome fused = fly(speed, phases, false, seed);
    const Outcome detected = fly(speed, phases, true, seed);
    INFO("seed " << seed << ": position error after the dropout and 1 s of flow: fusing every velocity "
         << fused.position_error.norm() << " m (max " << fused.max_position_error << "), with detection "
         << detected.position_error.norm() << " m (max " << detected.max_position_error << ")");
    // Fusing the relaxing zero loses most of the 1 m flown in the dropout.
    CHECK(fused.position_error.norm() > 0.5);
    CHECK(detected.dropouts == 1);
    CHECK(detected.max_position_error < 0.15);
    // The flow is back: fused again from its second packet (30 packets at 15 Hz failed, some before
    // the onset was seen), and the velocity is as right as when every velocity is fused (the last
    // packets' noise, 0.03 m/s per axis).
    CHECK(detected.dropout_packets <= 31);
    CHECK((detected.estimated_velocity - detected.true_velocity).norm() <
          (fused.estimated_velocity - fused.true_velocity).norm() + 0.02);
    CHECK(symmetric_positive_definite(detected.covariance));
    errors.push_back(detected.position_error.norm());
  }
  std::sort(errors.begin(), errors.end());
  INFO("final errors with detection, sorted: " << errors[0] << " .. " << errors[4] << ", " << errors[5] << " .. " << errors[9]);
  CHECK(0.5 * (errors[4] + errors[5]) < 0.07);  // median
  CHECK(errors[9] < 0.15);
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
  // Without a false dropout the estimate is the one that fuses every velocity (but for the learned
  // tilt bias in the model, which moves it by less than a centimetre here).
  constexpr double speed = 0.5;
  const MoveCommand brake{0.0, -0.6, 0.0, 0.0};
  const MoveCommand level{};
  const auto check_no_dropout = [](const std::vector<Phase>& phases) {
    const Outcome o = fly(speed, phases, true);
    const Outcome fused = fly(speed, phases, false);
    INFO("true velocity " << o.true_velocity.transpose() << ", estimated " << o.estimated_velocity.transpose());
    CHECK(o.dropouts == 0);
    CHECK(o.dropout_packets == 0);
    CHECK((o.position_error - fused.position_error).norm() < 0.01);
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

TEST_CASE("estimation: with an IMU offset, a drone creeping over a bare floor on a small tilt is caught") {
  // The face-follow failure: over the bare floor the flow reads zero, the estimate stands still, the
  // controller's small tilt makes the drone creep on (0.1-0.2 m/s) unseen. The IMU's 0.6 deg offset
  // (no flat trim) is a push of the same size in the model unless it is learned while the flow works.
  const MoveCommand hover{};
  const MoveCommand creep{0.0, 0.05, 0.0, 0.0};  // 0.6 deg: 0.18 m/s at the drag's balance
  const std::vector<Phase> phases{{4.0, hover, false}, {1.0, hover, true}, {4.0, creep, true}, {2.0, hover, true}};
  const Outcome fused = fly(0.0, phases, false, 7, 0.01);
  const Outcome detected = fly(0.0, phases, true, 7, 0.01);
  INFO("position error: fusing every velocity " << fused.position_error.norm() << " m, with detection "
       << detected.position_error.norm() << " m (max " << detected.max_position_error << ")");
  CHECK(fused.position_error.norm() > 0.6);
  CHECK(detected.dropouts >= 1);
  CHECK(detected.position_error.norm() < 0.3);  // caught after ~1 s of creep: part of it is lost
}

TEST_CASE("estimation: the dropout detector learns the IMU's tilt offset while the flow works") {
  // A hover whose measured tilt is all offset: thrust along it predicts a push the flow never shows.
  estimation::VelocityDropoutDetector d;
  const Eigen::Vector2d offset_push(0.098, -0.05);  // world frame, m/s^2 (0.57 and 0.29 deg)
  const double yaw = 0.3;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.03);
  int not_fused = 0;
  for (int k = 0; k <= 150; ++k) {  // 10 s at 15 Hz
    const estimation::VelocityVerdict v = d.process(k / 15.0, Eigen::Vector2d(noise(rng), noise(rng)), offset_push, yaw, Eigen::Vector2d::Zero());
    d.record_filter_velocity(Eigen::Vector2d::Zero());
    not_fused += v.fuse ? 0 : 1;
  }
  CHECK(not_fused == 0);
  CHECK(d.warmed_up());
  const Eigen::Vector2d b = d.tilt_bias_accel();
  const Eigen::Vector2d learned_world(std::cos(yaw) * b.x() - std::sin(yaw) * b.y(), std::sin(yaw) * b.x() + std::cos(yaw) * b.y());
  INFO("learned " << learned_world.transpose() << " m/s^2, offset's push " << offset_push.transpose());
  CHECK((learned_world - offset_push).norm() < 0.02);  // 0.1 deg: a drift of 0.03 m/s on the model
}

TEST_CASE("estimation: the tilt bias is learned while the flow works, and a hover is not a dropout") {
  // 20 s of hover and manoeuvres with a 0.6 deg IMU offset on both axes: no dropout, and the model's
  // bias is the offset's push (g * 0.01 rad, about 0.1 m/s^2 on each axis).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  std::vector<Phase> phases{{5.0, MoveCommand{}, false}};  // the warm-up: 3 s
  for (int k = 0; k < 10; ++k) phases.push_back({1.0, MoveCommand{u(rng), u(rng), 0.0, 0.0}, false});
  phases.push_back({5.0, MoveCommand{}, false});
  const Outcome o = fly(0.0, phases, true, 9, 0.01);
  CHECK(o.dropouts == 0);
  CHECK(o.position_error.norm() < 0.1);
}

TEST_CASE("estimation: a push (the velocity changes without a tilt) is not a velocity dropout") {
  // The model does not know the push; the flow does. Braking afterwards (tilting back) must not look
  // like a flow that lost speed (sim estimate's delay-compensation run: pushes of 0.8 m/s).
  const MoveCommand hover{};
  std::vector<Phase> phases{{1.0, hover, false}};
  phases.push_back({0.6, MoveCommand{0.0, 0.0, 0.0, 0.0}, false, Eigen::Vector2d(0.8, -0.4)});
  phases.push_back({0.8, MoveCommand{-0.4, -0.6, 0.0, 0.0}, false});
  phases.push_back({1.5, hover, false});
  phases.push_back({0.5, hover, false, Eigen::Vector2d(-0.6, 0.7)});
  phases.push_back({0.7, MoveCommand{0.6, 0.5, 0.0, 0.0}, false});
  phases.push_back({1.0, MoveCommand{0.0, 0.3, 0.0, 0.0}, false, Eigen::Vector2d(-0.5, 0.0)});
  phases.push_back({1.5, hover, false});
  for (const double offset : {0.0, 0.01}) {
    const Outcome fused = fly(0.0, phases, false, 11, offset);
    const Outcome o = fly(0.0, phases, true, 11, offset);
    INFO("IMU offset " << offset << " rad: position error " << o.position_error.norm() << " m, fusing every velocity "
         << fused.position_error.norm() << " m");
    CHECK(o.dropouts == 0);
    CHECK((o.position_error - fused.position_error).norm() < 0.02);
  }
}

TEST_CASE("estimation: a dropout's take-back reaches back at most 1.3 s, whatever the navdata rate") {
  // At the Tello's 10 Hz the ring holds 25 s. A model creeping 0.06-0.09 m/s ahead of a flow that
  // reads zero for 10 s is neither consistent nor lost; when it is judged lost, only the last 1.3 s
  // may be taken back (all 10 s once moved a Tello's estimate 0.87 m).
  estimation::VelocityDropoutDetector d;
  const double rate_hz = 10.0;
  int k = 0;
  auto run = [&](Seconds duration, const Eigen::Vector2d& thrust) {
    bool onset = false;
    for (const int end = k + static_cast<int>(duration * rate_hz); k < end; ++k) {
      onset = d.process(k / rate_hz, Eigen::Vector2d::Zero(), thrust, 0.0, Eigen::Vector2d::Zero()).onset || onset;
      d.record_filter_velocity(Eigen::Vector2d::Zero());
    }
    return onset;
  };
  CHECK_FALSE(run(4.0, Eigen::Vector2d::Zero()));  // the warm-up at rest
  REQUIRE(d.warmed_up());
  CHECK_FALSE(run(10.0, Eigen::Vector2d(0.055, 0.0)));  // the model creeps ~0.075 m/s ahead
  REQUIRE(run(3.0, Eigen::Vector2d(0.3, 0.0)));          // then it is judged lost
  const double taken_back = d.correction().position.norm();
  INFO("taken back " << taken_back << " m");
  CHECK(taken_back > 0.05);
  CHECK(taken_back < 0.6);  // the last 1.3 s at the shadow's speed (0.50 m); the whole span was 1.39 m
}

TEST_CASE("estimation: after a gap in the navdata the dropout detector starts again, and a stopped drone is no dropout") {
  // A Wi-Fi cut at 1 m/s: during the silence the firmware hovers the drone to a stop. The model's
  // velocity carried across the gap still flew, so the stopped drone's zero read as a failed flow,
  // and its take-back threw the estimate metres on (the soak's 18-m estimate).
  const estimation::MotionModelConstants m;
  estimation::VelocityDropoutDetector d({}, m);
  const double rate_hz = 15.0;
  const Eigen::Vector2d cruise_thrust(m.drag_per_s * 1.0, 0.0);  // holds 1 m/s against the drag
  Seconds t = 0;
  bool onset = false;
  for (int k = 0; k < 6 * 15; ++k) {
    t = k / rate_hz;
    onset = d.process(t, Eigen::Vector2d(1.0, 0.0), cruise_thrust, 0.0, Eigen::Vector2d(1.0, 0.0)).onset || onset;
    d.record_filter_velocity(Eigen::Vector2d(1.0, 0.0));
  }
  REQUIRE(d.warmed_up());
  CHECK_FALSE(onset);
  for (int k = 1; k <= 30; ++k) {  // 8 s later: at rest, level
    const VelocityVerdict v = d.process(t + 8.0 + k / rate_hz, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), 0.0,
                                        Eigen::Vector2d::Zero());
    d.record_filter_velocity(Eigen::Vector2d::Zero());
    CHECK_FALSE(v.onset);
    CHECK(v.fuse);
  }
  CHECK(d.warmed_up());  // the learned tilt offset is kept
}
