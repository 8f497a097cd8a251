#include <catch2/catch.hpp>

#include "control/control_config.hpp"
#include "control/geofence.hpp"
#include "control/request_policy.hpp"
#include "localization/fusion/localization_switch.hpp"
#include "control/safety_monitor.hpp"
#include "core/config_reader.hpp"

using namespace labo;
using namespace labo::control;

TEST_CASE("control: localization switch uses homography near, SLAM far, with hysteresis") {
  fusion::SourceSwitchParameters p;  // far_to_near 1.6 m, near_to_far 2.0 m, hold 0.5 s
  fusion::LocalizationSwitch sw(p);
  fusion::SwitchInputs in;
  in.slam = fusion::SlamState::Good;
  in.target_state = fusion::TrackState::Tracking;
  in.target_distance_m = 2.5;
  for (in.t = 0; in.t < 1.0; in.t += 0.1) sw.update(in);
  CHECK(sw.current() == fusion::FeedbackSource::Slam);
  in.target_distance_m = 1.5;  // near, but must hold 0.5 s first
  in.t = 1.0;
  CHECK(sw.update(in) == fusion::FeedbackSource::Slam);
  in.t = 1.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.target_distance_m = 1.9;  // inside the hysteresis band: stays
  in.t = 2.0;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.target_state = fusion::TrackState::Lost;  // a short drop-out is bridged
  in.t = 2.2;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.t = 2.8;  // lost for 0.6 s: back to SLAM
  CHECK(sw.update(in) == fusion::FeedbackSource::Slam);
  in.slam = fusion::SlamState::Lost;
  in.t = 3.0;
  sw.update(in);
  in.t = 3.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::DeadReckoning);
  in.target_state = fusion::TrackState::Tracking;
  in.target_distance_m = 3.5;  // far, but better than dead reckoning once held 0.5 s
  in.t = 5.0;
  CHECK(sw.update(in) == fusion::FeedbackSource::DeadReckoning);
  in.t = 5.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.slam = fusion::SlamState::Good;  // SLAM back: far, so SLAM once it has been good for 0.5 s
  in.t = 6.0;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.t = 6.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::Slam);
}

TEST_CASE("control: SLAM without a metric scale is no source: a far target is taken instead") {
  fusion::SourceSwitchParameters p;
  fusion::LocalizationSwitch sw(p);
  fusion::SwitchInputs in;
  in.slam = fusion::SlamState::Good;
  in.slam_scaled = false;  // the estimator does not fuse it yet
  for (in.t = 0; in.t < 1.0; in.t += 0.1) sw.update(in);
  CHECK(sw.current() == fusion::FeedbackSource::DeadReckoning);
  in.target_state = fusion::TrackState::Tracking;
  in.target_distance_m = 5.0;
  in.t = 1.0;
  sw.update(in);
  in.t = 1.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
  in.slam_scaled = true;  // scale fixed: far, so SLAM after 0.5 s
  in.t = 2.0;
  sw.update(in);
  in.t = 2.6;
  CHECK(sw.update(in) == fusion::FeedbackSource::Slam);
}

TEST_CASE("control: a dodgy SLAM (not fused) is no source: a tracked target is taken instead") {
  fusion::SourceSwitchParameters p;
  fusion::LocalizationSwitch sw(p);
  fusion::SwitchInputs in;
  in.slam = fusion::SlamState::Good;
  for (in.t = 0; in.t < 1.0; in.t += 0.1) sw.update(in);
  REQUIRE(sw.current() == fusion::FeedbackSource::Slam);
  in.slam = fusion::SlamState::Dodgy;
  in.target_state = fusion::TrackState::Tracking;
  in.target_distance_m = 1.9;  // inside the hysteresis band, not near
  in.t = 1.0;
  CHECK(sw.update(in) == fusion::FeedbackSource::Slam);  // a short dodgy spell is bridged
  in.t = 1.6;
  const fusion::FeedbackSource after = sw.update(in);
  CHECK(after != fusion::FeedbackSource::Slam);
  in.t = 2.2;
  CHECK(sw.update(in) == fusion::FeedbackSource::Homography);
}

TEST_CASE("control: on the way home dead reckoning is tolerated for the grace, then escalates") {
  control::SafetyLimits lim;  // hover after 1 s, land after 8 s
  control::SafetyMonitor m(lim);
  control::SafetyInputs in;
  in.airborne = true;
  in.localization_required = true;
  in.localization_ok = false;
  in.localization_grace_s = 20.0;
  in.t = 0;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.t = 20.5;
  const control::SafetyVerdict tolerated = m.evaluate(in);
  CHECK(tolerated.action == control::SafetyAction::None);
  REQUIRE(tolerated.alerts.size() == 1);
  CHECK_THAT(to_string(tolerated.alerts[0]), Catch::Contains("dead reckoning for 20.5 s"));
  in.t = 21.5;
  CHECK(m.evaluate(in).action == control::SafetyAction::HoldLevel);
  in.t = 28.5;
  CHECK(m.evaluate(in).action == control::SafetyAction::Land);
  in.localization_grace_s = 0;  // elsewhere: the usual 1 s / 8 s
  in.localization_ok = true;
  m.evaluate(in);
  in.localization_ok = false;
  in.t = 30.0;
  m.evaluate(in);
  in.t = 31.1;
  CHECK(m.evaluate(in).action == control::SafetyAction::HoldLevel);
}

TEST_CASE("control: geofence keeps the margin and names the violated bound") {
  const control::Geofence fence({-2, -2, 0}, {2, 2, 2.5}, 0.3);
  CHECK(fence.contains({1.7, 0, 1}));
  CHECK_FALSE(fence.contains({1.8, 0, 1}));
  CHECK_FALSE(fence.contains({0, 0, 2.3}));
  CHECK(fence.contains({0, 0, 0}));  // the floor keeps no margin: landing happens there
  CHECK(fence.violation({0, -5, 1}) == "y = -5.00 m is outside the geofence [-1.70, 1.70] m");
  CHECK(fence.clamp({9, -9, 9}).isApprox(Eigen::Vector3d(1.7, -1.7, 2.2)));
  CHECK_THROWS(Geofence({0, 0, 0}, {0.5, 3, 3}, 0.3));
}

TEST_CASE("control: safety monitor escalates link loss and localization loss over time") {
  control::SafetyLimits lim;
  lim.link_loss_land_s = 2.0;
  control::SafetyMonitor m(lim);
  control::SafetyInputs in;
  in.airborne = true;
  in.link = LinkState::Lost;
  in.t = 0;
  CHECK(m.evaluate(in).action == control::SafetyAction::Hover);
  in.t = 2.1;
  CHECK(m.evaluate(in).action == control::SafetyAction::Land);
  in.link = LinkState::Connected;
  in.battery_percent = 15;
  CHECK(m.evaluate(in).action == control::SafetyAction::ReturnHome);
  in.returning_home = true;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.battery_percent = 5;
  CHECK(m.evaluate(in).action == control::SafetyAction::Land);
}

TEST_CASE("control: safety holds level after a sudden estimate jump, not after smooth motion") {
  control::SafetyLimits lim;  // jump 0.30 m, hold 1 s
  control::SafetyMonitor m(lim);
  control::SafetyInputs in;
  in.airborne = in.flying = true;
  in.velocity_mps = Eigen::Vector3d(1.0, 0, 0);  // flying at 1 m/s: 3.3 cm per tick is no jump
  Eigen::Vector3d p(0, 0, 1);
  for (int i = 0; i < 60; ++i) {
    in.t = i / 30.0;
    p.x() = in.t;
    in.position_m = p;
    REQUIRE(m.evaluate(in).action == control::SafetyAction::None);
  }
  in.t += 1 / 30.0;
  p.x() = in.t + 0.8;  // a wrong fix moved the estimate 0.8 m in one tick
  in.position_m = p;
  const control::SafetyVerdict v = m.evaluate(in);
  CHECK(v.action == control::SafetyAction::HoldLevel);
  REQUIRE_FALSE(v.alerts.empty());
  CHECK_THAT(to_string(v.alerts.back()), Catch::Contains("jumped 0.80 m"));
  CHECK(m.estimate_jumps() == 1);
  const double jumped_at = in.t;
  while (in.t < jumped_at + 0.9) {  // held for estimate_jump_hold_s, the estimate moving smoothly again
    in.t += 1 / 30.0;
    p.x() += 1 / 30.0;
    in.position_m = p;
    REQUIRE(m.evaluate(in).action == control::SafetyAction::HoldLevel);
  }
  in.t = jumped_at + 1.05;
  p.x() += 0.15 * 1.0;
  in.position_m = p;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.flying = false;  // landing or taking off: never held
  in.t += 1 / 30.0;
  p.x() += 2.0;
  in.position_m = p;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
}

TEST_CASE("control: safety climbs when the ultrasound says the surface below is too close") {
  control::SafetyLimits lim;  // 0.35 m, climbing until 0.50 m
  control::SafetyMonitor m(lim);
  control::SafetyInputs in;
  in.airborne = in.flying = true;
  in.ultrasound_m = 1.0;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.ultrasound_m = 0.17;  // over a bench top at instrument height, whatever the estimate says
  const control::SafetyVerdict v = m.evaluate(in);
  CHECK(v.action == control::SafetyAction::Climb);
  CHECK_THAT(to_string(v.alerts.back()), Catch::Contains("0.17 m above the surface below"));
  in.ultrasound_m = 0.45;  // inside the hysteresis: still climbing
  CHECK(m.evaluate(in).action == control::SafetyAction::Climb);
  in.ultrasound_m = 0.55;
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.ultrasound_m = 0.2;  // a climb outranks a return home; a critical battery's landing outranks it
  in.battery_percent = 15;
  CHECK(m.evaluate(in).action == control::SafetyAction::Climb);
  in.battery_percent = 5;
  CHECK(m.evaluate(in).action == control::SafetyAction::Land);
  in.battery_percent = 90;
  in.flying = false;  // taking off or landing: the ground is meant to be near
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  lim.min_clearance_m = 0;  // off
  control::SafetyMonitor off(lim);
  in.flying = true;
  CHECK(off.evaluate(in).action == control::SafetyAction::None);
}

TEST_CASE("control: config section is validated with the key path") {
  auto read = [](const std::string& text) {
    const ConfigDocument doc = ConfigDocument::parse(text, "test.json");
    return read_control_config(doc.root());
  };
  const control::ControlConfig c = read(R"({"gains": {"xy": {"kp": 0.4}}, "mission": {"standoff_m": 0.9}})");
  CHECK(c.gains.xy.kp == 0.4);
  CHECK(c.mission.standoff_m == 0.9);
  CHECK(c.mission.face_distance_m == 1.0);
  CHECK_THROWS_WITH(read(R"({"gains": {"xy": {"kp": -1}}})"), Catch::Contains("gains.xy.kp"));
  CHECK_THROWS_WITH(read(R"({"gains": {"xy": {"kq": 1}}})"), Catch::Contains("kq"));
  CHECK_THROWS_WITH(read(R"({"mission": {"standoff_m": 0.3}})"), Catch::Contains("min_standoff_m"));
  CHECK_THROWS_WITH(read(R"({"mission": {"far_to_near_m": 2.5}})"), Catch::Contains("hysteresis"));
  CHECK(read(R"({"mission": {"face_blind_altitude_m": 2.2}})").mission.face_blind_altitude_m == 2.2);
  CHECK_THROWS_WITH(read(R"({"mission": {"face_blind_altitude_m": 0.1}})"), Catch::Contains("mission.face_blind_altitude_m"));
  CHECK_THROWS_WITH(read(R"({"mission": {"face_blind_altitude_m": "high"}})"), Catch::Contains("face_blind_altitude_m"));
  const control::ControlConfig view = read(R"({"mission": {"detect_max_oblique_deg": 40, "detect_view_distance_m": 2}})");
  CHECK(view.mission.detect_max_oblique_deg == 40.0);
  CHECK(view.mission.detect_view_distance_m == 2.0);
  CHECK_THROWS_WITH(read(R"({"mission": {"detect_max_oblique_deg": 120}})"), Catch::Contains("mission.detect_max_oblique_deg"));
  CHECK_THROWS_WITH(read(R"({"mission": {"detect_view_distance_m": 0.1}})"), Catch::Contains("mission.detect_view_distance_m"));
  CHECK_THROWS_WITH(read(R"({"mission": {"detect_view_distance_m": "far"}})"), Catch::Contains("detect_view_distance_m"));
  CHECK_THROWS_WITH(read(R"({"safety": {"link_loss_land_s": "soon"}})"), Catch::Contains("link_loss_land_s"));
  const control::ControlConfig net = read(R"({"safety": {"min_clearance_m": 0.5, "estimate_jump_m": 0.4, "estimate_jump_hold_s": 2}})");
  CHECK(net.safety.min_clearance_m == 0.5);
  CHECK(net.safety.estimate_jump_m == 0.4);
  CHECK(net.safety.estimate_jump_hold_s == 2.0);
  CHECK_THROWS_WITH(read(R"({"safety": {"min_clearance_m": 3}})"), Catch::Contains("min_clearance_m"));
  CHECK_THROWS_WITH(read(R"({"safety": {"estimate_jump_m": -1}})"), Catch::Contains("estimate_jump_m"));
  CHECK(read(R"({"safety": {"pose_lost_outside_fence_m": 1.5}})").safety.pose_lost_outside_fence_m == 1.5);
  CHECK_THROWS_WITH(read(R"({"safety": {"pose_lost_outside_fence_m": -0.5}})"), Catch::Contains("pose_lost_outside_fence_m"));
  CHECK_THROWS_WITH(read(R"({"safety": {"pose_lost_outside_fence_m": "far"}})"), Catch::Contains("pose_lost_outside_fence_m"));
  CHECK(read(R"({"gains": {"yaw_rate_feedforward": 0.3}})").gains.yaw_rate_feedforward == 0.3);
  CHECK_THROWS_WITH(read(R"({"gains": {"yaw_rate_feedforward": -0.1}})"), Catch::Contains("yaw_rate_feedforward"));
  CHECK_THROWS_WITH(read(R"({"gains": {"yaw_rate_feedforward": "fast"}})"), Catch::Contains("yaw_rate_feedforward"));
  CHECK(read(R"({"safety": {"hold_clearance_m": 0.3}})").safety.hold_clearance_m == 0.3);
  CHECK_THROWS_WITH(read(R"({"safety": {"hold_clearance_m": 1.5}})"), Catch::Contains("safety.hold_clearance_m"));
  CHECK_THROWS_WITH(read(R"({"safety": {"hold_clearance_m": "wide"}})"), Catch::Contains("hold_clearance_m"));
}


#include "control/mission.hpp"
#include "core/camera_model.hpp"
#include "core/frames.hpp"

TEST_CASE("control: the standoff pose puts the panel centre at the image centre at the standoff depth") {
  Eigen::Isometry3d T_world_panel = Eigen::Isometry3d::Identity();
  T_world_panel.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // faces -x: z (into the panel) along +x
  T_world_panel.translation() = Eigen::Vector3d(3.0, 0.5, 1.2);
  const CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
  const Eigen::Vector3d ray = image_centre_ray(k.fx, k.fy, k.cx, k.cy, k.width, k.height);
  const control::PoseTarget t = standoff_target(T_world_panel, 0.8, ray);
  const Eigen::Isometry3d T_cam_panel = (make_pose(t.position, t.yaw) * T_body_cam_front()).inverse() * T_world_panel;
  const Eigen::Vector3d c = T_cam_panel.translation();
  CHECK(c.z() == Approx(0.8));
  CHECK(k.fx * c.x() / c.z() + k.cx == Approx(0.5 * k.width));
  CHECK(k.fy * c.y() / c.z() + k.cy == Approx(0.5 * k.height));
  CHECK(t.yaw == Approx(0.0).margin(1e-12));
}

TEST_CASE("control: an estimate beyond the walls is a lost pose: safety lands, and no mission takes off on it") {
  // The soak's drone, dead reckoned 18 m outside the room across a link cut, took off for the next
  // inspection and flew at full speed towards a set point clamped into the fence, into a wall.
  const Geofence fence(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(3, 3, 2.5), 0.3);  // x, y within +-2.7
  CHECK(fence.horizontal_distance_outside_m(Eigen::Vector3d(1, 1, -0.5)) == 0.0);  // below the floor: not over it
  CHECK(fence.horizontal_distance_outside_m(Eigen::Vector3d(3.0, 3.1, 1)) == Approx(std::hypot(0.3, 0.4)));

  control::SafetyLimits lim;  // pose_lost_outside_fence_m 0.5
  control::SafetyMonitor m(lim);
  control::SafetyInputs in;
  in.airborne = in.flying = true;
  in.outside_fence_m = 0.4;  // a drift near a wall: the fence holds the set point
  CHECK(m.evaluate(in).action == control::SafetyAction::None);
  in.t = 0.1;
  in.outside_fence_m = 0.8;
  const control::SafetyVerdict v = m.evaluate(in);
  CHECK(v.action == control::SafetyAction::Land);
  CHECK_THAT(to_string(v.reason), Catch::Contains("0.80 m outside the geofence: the pose is lost"));
  lim.pose_lost_outside_fence_m = 0;  // off
  control::SafetyMonitor off(lim);
  CHECK(off.evaluate(in).action == control::SafetyAction::None);

  const ControlConfig config;
  fusion::LabGeometry lab;
  RequestContext landed;
  landed.position = Eigen::Vector3d(-15.4, 0.3, 0);
  for (const RequestKind kind : {RequestKind::Takeoff, RequestKind::FindTeacher}) {
    MissionRequest r;
    r.kind = kind;
    const CommandResult c = check_request(r, landed, lab, fence, config);
    INFO(c.reason);
    CHECK_FALSE(c.accepted);
    CHECK_THAT(c.reason, Catch::Contains("estimated place (-15.40, 0.30) m is 12.70 m outside the geofence"));
    CHECK_THAT(c.reason, Catch::Contains("its pose is lost"));
  }
  RequestContext flying = landed;  // in flight the safety monitor lands it; requests are not where that is judged
  flying.phase = FlightPhase::Flying;
  MissionRequest find;
  find.kind = RequestKind::FindTeacher;
  CHECK(check_request(find, flying, lab, fence, config).accepted);
  landed.position = Eigen::Vector3d(2.9, 0.0, 0);  // landed just beyond the fence: flies
  MissionRequest take_off;
  take_off.kind = RequestKind::Takeoff;
  CHECK(check_request(take_off, landed, lab, fence, config).accepted);
}
