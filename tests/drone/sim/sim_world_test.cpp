// SimWorld: the nominal world is the configuration exactly; a randomized world is drawn per seed,
// deterministically, within the documented ranges, and a simulated lab built from it reruns bit for bit.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "core/camera_config.hpp"
#include "core/frames.hpp"
#include "drone/sim/sim_setup.hpp"
#include "drone/sim/sim_world.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

SimWorld world(WorldMode mode, std::uint64_t seed, const WorldRanges& ranges = {}) {
  SimConfig sim;
  sim.world = mode;
  sim.lab.seed = seed;
  sim.link.seed = seed;
  return make_sim_world(test::shipped_lab(), test::stock_cameras(), sim, ranges);
}

bool same_camera(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return std::memcmp(&a, &b, sizeof(CameraIntrinsics)) == 0;
}

std::size_t count_events(const SimWorld& w, Disturbance::Kind kind) {
  return static_cast<std::size_t>(std::count_if(w.settings.disturbances.begin(), w.settings.disturbances.end(),
                                                [&](const Disturbance& e) { return e.kind == kind; }));
}

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

bool same_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return a.isApprox(b, 1e-12); }

}  // namespace

TEST_CASE("sim world: the nominal world is the lab file, the calibration and the sim section exactly", "[sim][world]") {
  const SimWorld w = world(WorldMode::Nominal, 7);
  const LabDescription& lab = test::shipped_lab();
  REQUIRE(w.lab.instruments.size() == lab.instruments.size());
  for (std::size_t i = 0; i < lab.instruments.size(); ++i)
    CHECK(same_pose(w.lab.instruments[i].T_world_object, lab.instruments[i].T_world_object));
  CHECK(same_pose(w.lab.platform.T_world_object, lab.platform.T_world_object));
  CHECK(same_pose(w.lab.T_world_base, lab.T_world_base));
  const CameraIntrinsics configured = test::stock_cameras().front;
  CHECK(std::memcmp(&w.cameras.front, &configured, sizeof(CameraIntrinsics)) == 0);
  CHECK(same_pose(w.mounts.front, T_body_cam_front()));
  CHECK(same_pose(w.mounts.bottom, T_body_cam_bottom()));
  CHECK(w.settings.dynamics.deviation.mass_factor == 1.0);
  CHECK(w.settings.biases.attitude_rad.isZero());
  CHECK(w.settings.disturbances.empty());
  CHECK(w.link.video_delay_s == SimLinkSettings{}.video_delay_s);
  CHECK(w.placements.empty());
  // The teacher walks the lab file's path.
  CHECK(w.lab.teacher.loop);
  CHECK(w.lab.teacher.waypoints == lab.teacher.waypoints);
  CHECK(w.lab.teacher.speed_mps == lab.teacher.speed_mps);
}

TEST_CASE("sim world: a randomized world is the same for the same seed and differs for another", "[sim][world]") {
  const SimWorld a = world(WorldMode::Randomized, 11), b = world(WorldMode::Randomized, 11), c = world(WorldMode::Randomized, 12);
  CHECK(a.placements[0].offset_m == b.placements[0].offset_m);
  CHECK(a.cameras.front.fx == b.cameras.front.fx);
  CHECK(a.link.video_delay_s == b.link.video_delay_s);
  CHECK(a.settings.dynamics.deviation.mass_factor == b.settings.dynamics.deviation.mass_factor);
  CHECK(a.settings.disturbances.size() == b.settings.disturbances.size());
  CHECK(a.placements[0].offset_m != c.placements[0].offset_m);
  CHECK(a.cameras.front.fx != c.cameras.front.fx);
  CHECK(a.link.video_delay_s != c.link.video_delay_s);
  // The teacher walks a path drawn for the run, not the lab file's.
  CHECK(a.lab.teacher.waypoints == b.lab.teacher.waypoints);
  CHECK(a.lab.teacher.waypoints != c.lab.teacher.waypoints);
  CHECK(a.lab.teacher.waypoints != test::shipped_lab().teacher.waypoints);
  CHECK_FALSE(a.lab.teacher.loop);
  // The sensors' and the link's noise keep the run's seed: only the world's draws come from elsewhere.
  CHECK(a.settings.seed == 11);
  CHECK(a.link.seed == 11);
}

TEST_CASE("sim world: every draw of 300 randomized worlds lies within the documented ranges", "[sim][world]") {
  const WorldRanges r;
  const LabDescription& lab = test::shipped_lab();
  const CamerasConfig k = test::stock_cameras();
  int lighting = 0, flicker = 0, outages = 0, stalls = 0;
  double largest_offset = 0, largest_tilt = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const SimWorld w = world(WorldMode::Randomized, seed);
    for (std::size_t i = 0; i < lab.instruments.size(); ++i) {
      const Eigen::Isometry3d& truth = w.lab.instruments[i].T_world_object;
      const Eigen::Isometry3d& file = lab.instruments[i].T_world_object;
      CHECK((truth.translation() - file.translation()).norm() <= r.placement_m + 1e-12);
      CHECK(angle_between(truth.linear(), file.linear()) <= r.placement_deg * kDeg + 1e-9);
      largest_offset = std::max(largest_offset, (truth.translation() - file.translation()).norm());
    }
    // The platform moves on the floor and turns about the vertical; the drone stands on it.
    const Eigen::Isometry3d& platform = w.lab.platform.T_world_object;
    CHECK(platform.translation().z() == lab.platform.T_world_object.translation().z());
    CHECK((platform.translation() - lab.platform.T_world_object.translation()).norm() <= r.placement_m + 1e-12);
    CHECK(angle_between(platform.linear(), lab.platform.T_world_object.linear()) <= r.placement_deg * kDeg + 1e-9);
    CHECK((platform.linear() * Eigen::Vector3d::UnitZ() - lab.platform.T_world_object.linear() * Eigen::Vector3d::UnitZ()).norm() < 1e-12);
    CHECK(same_pose(platform.inverse() * w.lab.T_world_base, lab.platform.T_world_object.inverse() * lab.T_world_base));
    // Cameras.
    for (const auto& [drawn, configured] : {std::pair{w.cameras.front, k.front}, std::pair{w.cameras.bottom, k.bottom}}) {
      CHECK(std::abs(drawn.fy / configured.fy - 1.0) <= r.focal_fraction + 1e-12);
      CHECK(std::abs((drawn.fx / configured.fx) / (drawn.fy / configured.fy) - 1.0) <= r.aspect_fraction + 1e-12);
      CHECK(std::abs(drawn.cx - configured.cx) <= r.principal_point_px);
      CHECK(std::abs(drawn.cy - configured.cy) <= r.principal_point_px);
      CHECK(std::abs(drawn.k2 - configured.k2) <= r.k2);
      CHECK(std::abs(drawn.p1 - configured.p1) <= r.tangential);
    }
    CHECK(std::abs(w.cameras.front.k1 - k.front.k1) <= r.k1);
    CHECK(std::abs(w.cameras.bottom.k1 - k.bottom.k1) <= r.bottom_k1);
    CHECK(angle_between(w.mounts.front.linear(), T_body_cam_front().linear()) <= r.mounting_tilt_deg * kDeg + 1e-9);
    CHECK(angle_between(w.mounts.bottom.linear(), T_body_cam_bottom().linear()) <= r.mounting_tilt_deg * kDeg + 1e-9);
    CHECK((w.mounts.front.translation() - T_body_cam_front().translation()).norm() < 1e-12);
    largest_tilt = std::max(largest_tilt, angle_between(w.mounts.front.linear(), T_body_cam_front().linear()));
    // The link's delays.
    CHECK(w.link.video_delay_s >= r.video_delay_s.min);
    CHECK(w.link.video_delay_s <= r.video_delay_s.max);
    CHECK(w.link.navdata_delay_s >= r.navdata_delay_s.min);
    CHECK(w.link.navdata_delay_s <= r.navdata_delay_s.max);
    // The drone and its sensors.
    const PlantDeviation& d = w.settings.dynamics.deviation;
    CHECK(std::abs(d.mass_factor - 1.0) <= r.mass);
    for (double f : {d.rotor_drag_factor, d.air_drag_factor}) CHECK(std::abs(f - 1.0) <= r.drag);
    for (double f : {d.motor_lag_factor, d.attitude_lag_factor, d.yaw_lag_factor, d.vertical_lag_factor})
      CHECK(std::abs(f - 1.0) <= r.inner_loop_lag);
    for (double e : d.rotor_efficiency) CHECK(std::abs(e - 1.0) <= r.rotor_thrust);
    CHECK(w.settings.dynamics.battery.start_percent >= r.battery_start_percent.min);
    CHECK(w.settings.dynamics.battery.start_percent <= r.battery_start_percent.max);
    CHECK(w.settings.biases.attitude_rad.cwiseAbs().maxCoeff() <= r.attitude_bias_deg * kDeg);
    CHECK(std::abs(w.settings.biases.velocity_scale - 1.0) <= r.velocity_scale);
    CHECK(std::abs(w.settings.biases.ultrasound_offset_m) <= r.ultrasound_bias_m);
    // Events within the horizon.
    for (const Disturbance& e : w.settings.disturbances) {
      CHECK(e.t_s >= 0);
      CHECK(e.t_s < r.horizon_s);
      lighting += e.kind == Disturbance::Kind::Lighting;
      flicker += e.kind == Disturbance::Kind::Flicker;
      outages += e.kind == Disturbance::Kind::LinkOutage;
      stalls += e.kind == Disturbance::Kind::VideoDropout;
      if (e.kind == Disturbance::Kind::LinkOutage) CHECK(e.duration_s <= r.link_loss_s.max);
      if (e.kind == Disturbance::Kind::Lighting) CHECK(e.exposure_gain >= r.lighting_gain.min);
    }
  }
  // The ranges are used, not just respected; the Poisson processes have their mean rates (±15 %).
  CHECK(largest_offset > 0.9 * r.placement_m);
  CHECK(largest_tilt > 0.9 * r.mounting_tilt_deg * kDeg);
  CHECK(flicker == 300);
  CHECK(lighting == Approx(300 * r.horizon_s / r.lighting_interval_s).epsilon(0.15));
  CHECK(outages == Approx(300 * r.horizon_s / r.link_loss_interval_s).epsilon(0.15));
  CHECK(stalls == Approx(300 * r.horizon_s / r.video_stall_interval_s).epsilon(0.15));
}

TEST_CASE("sim world: a simulated lab in a randomized world reruns bit for bit and flies unlike the nominal one", "[sim][world]") {
  const auto flight = [](const SimWorld& w) {
    SimulatedLab v(w.lab, w.settings, std::make_unique<test::GreyRenderer>());
    v.takeoff(0.2);
    v.advance_to(6.0);
    v.move({0.1, 0.3, 0.1, 0.2}, false, 6.0);
    v.advance_to(8.0);
    return std::pair{v.telemetry(), v.truth()};
  };
  const auto [a_tel, a_truth] = flight(world(WorldMode::Randomized, 5));
  const auto [b_tel, b_truth] = flight(world(WorldMode::Randomized, 5));
  CHECK(a_truth.position_m == b_truth.position_m);
  CHECK(a_truth.yaw_rad == b_truth.yaw_rad);
  CHECK(a_tel.nav.vx_mps == b_tel.nav.vx_mps);
  CHECK(a_tel.nav.altitude_m == b_tel.nav.altitude_m);
  const auto [n_tel, n_truth] = flight(world(WorldMode::Nominal, 5));
  CHECK((a_truth.position_m - n_truth.position_m).norm() > 1e-3);
}

TEST_CASE("sim world: factors kept nominal have the configuration's values, the others the whole world's draw", "[sim][world]") {
  const SimWorld whole = world(WorldMode::Randomized, 21);
  const SimWorld nominal = world(WorldMode::Nominal, 21);
  SECTION("each factor alone") {
    for (WorldFactor f : kWorldFactors) {
      CAPTURE(to_string(f));
      WorldRanges ranges;
      ranges.nominal.insert(f);
      const SimWorld w = world(WorldMode::Randomized, 21, ranges);
      CHECK(w.nominal_factors == ranges.nominal);
      const auto expect = [&](WorldFactor factor, const SimWorld& kept) -> const SimWorld& {
        return factor == f ? kept : whole;
      };
      CHECK(w.settings.dynamics.deviation.mass_factor == expect(WorldFactor::Drone, nominal).settings.dynamics.deviation.mass_factor);
      CHECK(w.settings.dynamics.battery.start_percent == expect(WorldFactor::Drone, nominal).settings.dynamics.battery.start_percent);
      CHECK(w.settings.biases.gyro_radps == expect(WorldFactor::Sensors, nominal).settings.biases.gyro_radps);
      CHECK(same_pose(w.lab.instruments[0].T_world_object, expect(WorldFactor::Placements, nominal).lab.instruments[0].T_world_object));
      CHECK(same_pose(w.lab.T_world_base, expect(WorldFactor::Placements, nominal).lab.T_world_base));
      CHECK(w.placements.size() == expect(WorldFactor::Placements, nominal).placements.size());
      CHECK(same_camera(w.cameras.front, expect(WorldFactor::Lens, nominal).cameras.front));
      CHECK(same_camera(w.cameras.bottom, expect(WorldFactor::Lens, nominal).cameras.bottom));
      CHECK(same_pose(w.mounts.front, expect(WorldFactor::Mounting, nominal).mounts.front));
      CHECK(w.front_tilt_rad == expect(WorldFactor::Mounting, nominal).front_tilt_rad);
      CHECK(w.link.video_delay_s == expect(WorldFactor::Delays, nominal).link.video_delay_s);
      CHECK(w.link.navdata_delay_s == expect(WorldFactor::Delays, nominal).link.navdata_delay_s);
      for (auto kind : {Disturbance::Kind::Lighting, Disturbance::Kind::Flicker})
        CHECK(count_events(w, kind) == count_events(expect(WorldFactor::Lighting, nominal), kind));
      for (auto kind : {Disturbance::Kind::LinkOutage, Disturbance::Kind::VideoDropout})
        CHECK(count_events(w, kind) == count_events(expect(WorldFactor::Link, nominal), kind));
      CHECK(w.lab.teacher.waypoints == expect(WorldFactor::Teacher, nominal).lab.teacher.waypoints);
    }
  }
  SECTION("every factor: the nominal world, mode aside") {
    WorldRanges ranges;
    for (WorldFactor f : kWorldFactors) ranges.nominal.insert(f);
    const SimWorld w = world(WorldMode::Randomized, 21, ranges);
    CHECK(w.mode == WorldMode::Randomized);
    CHECK(w.settings.disturbances.empty());
    CHECK(w.placements.empty());
    CHECK(same_camera(w.cameras.front, nominal.cameras.front));
    CHECK(w.settings.dynamics.deviation.mass_factor == 1.0);
    CHECK(w.lab.teacher.loop);
  }
  SECTION("names") {
    for (WorldFactor f : kWorldFactors) CHECK(parse_world_factor(to_string(f)) == f);
    CHECK_FALSE(parse_world_factor("Lens"));
    CHECK_FALSE(parse_world_factor(""));
  }
}
