// The default z gains against the simulated firmware's vertical dynamics (drone/sim's
// QuadrotorDynamics: the vertical speed follows gaz x control_vz_max through the firmware's shaped
// set point and vertical-speed loop, about as fast as tum_ardrone's fitted 0.8 /s lag). The perturbation
// target: after a z impulse the drone is back within 0.1 m of the set point in 5 s; the gains alone
// must leave time for the vision to come back, so they must do it in 4 s. The firmware's own
// vertical-speed loop stops a 0.6 m/s push within a few centimetres; a displacement of half a metre
// (what a push did to the closed-loop model the simulation used before) is a set-point step here.
#include <catch2/catch.hpp>

#include <cmath>
#include <deque>
#include <functional>

#include "control/control_config.hpp"
#include "control/level_hold.hpp"
#include "control/pid_controller.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::control;

namespace {

struct ZFlight {
  LabDescription lab = load_lab_description(default_lab_path());
  QuadrotorDynamics drone{QuadrotorParams{}, CollisionModel(lab, QuadrotorParams{}.hull), lab.T_world_base};
  control::PoseController controller{control::PoseControlGains{}};
  std::deque<MoveCommand> in_flight;  // the link's delay: a command acts 90 ms after the pose it came from
  control::PoseTarget target;

  ZFlight() {
    drone.takeoff();
    for (int i = 0; i < 4000 && drone.state().phase != FirmwarePhase::Hovering; ++i) drone.step();
    REQUIRE(drone.state().phase == FirmwarePhase::Hovering);
    target.position = drone.state().position_m + Eigen::Vector3d(0, 0, 0.1);
    target.yaw = drone.state().yaw_rad;
    controller.set_target(target);
    fly(6.0);  // settle at the set point
  }

  // 30 ms control periods with the truth as the estimate.
  void fly(Seconds duration, const std::function<void()>& each = [] {}) {
    for (Seconds t = 0; t < duration - 1e-9; t += 0.03) {
      fusion::PoseEstimate pose;
      pose.valid = true;
      pose.T_world_body = drone.state().T_world_body();
      pose.velocity_world = drone.state().velocity_mps;
      pose.yaw_rate = drone.state().yaw_rate_radps;
      in_flight.push_back(controller.update(pose, 0.03));
      if (in_flight.size() > 3) in_flight.pop_front();
      drone.move(in_flight.front(), false);
      for (int i = 0; i < 6; ++i) drone.step();
      each();
    }
  }

  double z_error() const { return drone.state().position_m.z() - target.position.z(); }
};

// Seconds from the push until the error stays below 0.1 m for 1 s (the perturb experiment's rule),
// and the largest error on the far side of the set point (an overshoot towards the floor or ceiling).
struct Recovery {
  double seconds = 1e9;
  double peak = 0;
  double overshoot = 0;
};

Recovery push_and_watch(ZFlight& f, double dv_mps) {
  Recovery r;
  f.drone.push(Eigen::Vector3d(0, 0, dv_mps), 0.0);
  double t = 0, within_since = -1;
  f.fly(10.0, [&] {
    t += 0.03;
    const double e = f.z_error();
    r.peak = std::max(r.peak, std::abs(e));
    if (e * dv_mps < 0) r.overshoot = std::max(r.overshoot, std::abs(e));
    if (std::abs(e) < 0.1) {
      if (within_since < 0) within_since = t;
      if (t - within_since >= 1.0) r.seconds = std::min(r.seconds, within_since);
    } else {
      within_since = -1;
    }
  });
  return r;
}

}  // namespace

TEST_CASE("control: the default z gains recover a 0.6 m/s vertical push on the firmware's dynamics within 4 s") {
  for (const double dv : {0.6, -0.6}) {
    ZFlight f;
    const Recovery r = push_and_watch(f, dv);
    INFO("push " << dv << " m/s: peak " << r.peak << " m, recovered after " << r.seconds << " s, overshoot "
                 << r.overshoot << " m");
    CHECK(r.peak > 0.03);        // the push did displace it (the firmware's loop stops it within ~7 cm)
    CHECK(r.seconds < 4.0);      // tum_ardrone's gains (0.6/0.1, gaz >= -0.25): about 5.9 s
    CHECK(r.overshoot < 0.1);    // not through the set point towards the floor or the ceiling
    CHECK(std::abs(f.z_error()) < 0.05);
  }
}

TEST_CASE("control: the default z gains bring the drone 0.5 m up or down to a new set point within 4 s") {
  for (const double step : {0.5, -0.5}) {
    ZFlight f;
    f.target.position.z() += step;
    f.controller.set_target(f.target);
    double t = 0, within_since = -1, seconds = 1e9, overshoot = 0;
    f.fly(10.0, [&] {
      t += 0.03;
      const double e = f.z_error();
      if (e * step > 0) overshoot = std::max(overshoot, std::abs(e));  // beyond the new set point
      if (std::abs(e) < 0.1) {
        if (within_since < 0) within_since = t;
        if (t - within_since >= 1.0) seconds = std::min(seconds, within_since);
      } else {
        within_since = -1;
      }
    });
    INFO("step " << step << " m: within 0.1 m after " << seconds << " s, overshoot " << overshoot << " m");
    CHECK(seconds < 4.0);
    CHECK(overshoot < 0.1);
    CHECK(std::abs(f.z_error()) < 0.05);
  }
}

TEST_CASE("control: a descent at the z gains' limit is stopped by the clearance climb within 0.15 m") {
  // The safety's net under a bad estimate: below min_clearance_m (0.35 m) the drone climbs (gaz 0.5,
  // level_hold.hpp). A descent at out_min must be stopped before the floor: within 0.15 m.
  ZFlight f;
  const control::PoseControlGains gains;
  f.target.position.z() += 1.0;  // room below for a 3 s descent
  f.controller.set_target(f.target);
  f.fly(6.0);
  MoveCommand down;
  down.gaz = gains.z.out_min;
  for (int i = 0; i < 100; ++i) {  // 3 s: the full descent speed
    f.drone.move(down, false);
    for (int k = 0; k < 6; ++k) f.drone.step();
  }
  REQUIRE(f.drone.state().velocity_mps.z() < -0.3);
  const double z_at_climb = f.drone.state().position_m.z();
  fusion::PoseEstimate pose;
  pose.valid = true;
  double lowest = z_at_climb;
  for (int i = 0; i < 100; ++i) {
    pose.T_world_body = f.drone.state().T_world_body();
    pose.velocity_world = f.drone.state().velocity_mps;
    f.drone.move(climb_command(pose, gains), false);
    for (int k = 0; k < 6; ++k) f.drone.step();
    lowest = std::min(lowest, f.drone.state().position_m.z());
  }
  INFO("dropped " << z_at_climb - lowest << " m after the climb began");
  CHECK(z_at_climb - lowest < 0.15);
  CHECK(f.drone.state().velocity_mps.z() > 0.2);  // climbing
}
