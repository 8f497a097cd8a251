#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <algorithm>
#include <set>

#include "control/flight_stack.hpp"
#include "control/level_hold.hpp"
#include "control/take_off_and_scale.hpp"
#include "tests/control/model_flight.hpp"

using namespace labo;
using namespace labo::control;
using labo::test::ModelFlight;

namespace {
control::MissionRequest req(control::RequestKind kind) {
  control::MissionRequest r;
  r.kind = kind;
  return r;
}
control::MissionRequest inspect(const std::string& id, double hold_s = 3.0, double standoff = 0) {
  control::MissionRequest r = req(control::RequestKind::Inspect);
  r.instrument_id = id;
  r.hold_s = hold_s;
  r.standoff_m = standoff;
  return r;
}
control::MissionRequest go(double x, double y, double z, double yaw = 0) {
  control::MissionRequest r = req(control::RequestKind::Goto);
  r.target << x, y, z, yaw;
  return r;
}
void take_off(ModelFlight& f) {
  REQUIRE(f.request(req(control::RequestKind::Takeoff)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Flying; }, 8.0));
}
// Flies an inspect mission of the oscilloscope until stage 3 holds at the standoff.
void reach_standoff_hold(ModelFlight& f, double hold_s) {
  REQUIRE(f.request(inspect("oscilloscope", hold_s)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage.find("holding") != std::string::npos; }, 90.0));
}
// As with real vision, SLAM is lost next to the panel: the hold settles on the homography alone.
void hold_at_standoff_without_slam(ModelFlight& f) {
  reach_standoff_hold(f, 60.0);
  f.world->slam_available = false;
  f.run(4.0);
}
}  // namespace

TEST_CASE("control: inspect runs stages 1-6 in order and ends on the platform") {
  ModelFlight f;
  REQUIRE(f.request(inspect("oscilloscope", 3.0)).accepted);
  std::vector<int> stages;
  double standoff_error = 1e9, centre_offset = 1e9;
  bool saw_homography = false;
  const bool ended = f.run_until([&] {
    const control::FlightStatus s = f.stack->status();
    if (s.stage_index > 0 && (stages.empty() || stages.back() != s.stage_index)) stages.push_back(s.stage_index);
    if (s.source == fusion::FeedbackSource::Homography) saw_homography = true;
    if (s.stage.find("holding") != std::string::npos) {
      const Eigen::Isometry3d T_cam_obj =
          (f.world->drone.pose() * T_body_cam_front()).inverse() * f.lab.instruments[0].T_world_object;
      standoff_error = std::abs(T_cam_obj.translation().z() - 0.80);
      const CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
      const Eigen::Vector3d c = T_cam_obj.translation();
      const double u = k.fx * c.x() / c.z() + k.cx, v = k.fy * c.y() / c.z() + k.cy;
      centre_offset = std::hypot(u - 0.5 * k.width, v - 0.5 * k.height) / k.width;
    }
    return s.mission == "idle";
  }, 120.0);
  REQUIRE(ended);
  INFO(f.stack->status().last_event);
  CHECK(f.stack->status().last_event.find("succeeded") != std::string::npos);
  CHECK(stages == std::vector<int>{1, 2, 3, 4, 5, 6});
  CHECK(saw_homography);
  CHECK(standoff_error < 0.05);
  CHECK(centre_offset < 0.05);
  CHECK(f.stack->status().phase == control::FlightPhase::Landed);
  CHECK(f.world->drone.p.head<2>().norm() < 0.10);
  CHECK_FALSE(f.world->drone.crashed);
}

TEST_CASE("control: a second inspection after a landing, and one after a find-teacher, fly as the first") {
  ModelFlight f;
  // Flies one inspection to its end; whether the panel's homography drove the estimate on the way and
  // whether the face was asked for meanwhile.
  const auto inspect_once = [&](bool& saw_homography, bool& face_focused) {
    saw_homography = face_focused = false;
    REQUIRE(f.request(inspect("oscilloscope", 2.0)).accepted);
    REQUIRE(f.run_until([&] {
      const control::FlightStatus s = f.stack->status();
      saw_homography = saw_homography || s.source == fusion::FeedbackSource::Homography;
      face_focused = face_focused || f.world->focus.face;
      return s.mission == "idle";
    }, 120.0));
    INFO(f.stack->status().last_event);
    CHECK(f.stack->status().last_event.find("succeeded") != std::string::npos);
    CHECK(f.stack->status().phase == control::FlightPhase::Landed);
  };
  bool homography = false, face = false;
  inspect_once(homography, face);
  CHECK(homography);
  // The landing looked for the platform; the next inspection must watch the panel again.
  CHECK_FALSE(f.world->focus.platform);
  inspect_once(homography, face);
  CHECK(homography);
  CHECK_FALSE(face);

  REQUIRE(f.request(req(control::RequestKind::FindTeacher)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage == "3 face-follow"; }, 60.0));
  REQUIRE(f.world->focus.face);
  REQUIRE(f.request(req(control::RequestKind::Land)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Landed; }, 20.0));
  CHECK_FALSE(f.world->focus.face);  // no face front-end running for nobody
  inspect_once(homography, face);
  CHECK(homography);
  CHECK_FALSE(face);
}

TEST_CASE("control: a panel seen too obliquely from the base is searched for from a viewpoint on its normal") {
  fusion::LabGeometry lab = bench::model_lab();
  fusion::PlanarTarget side;  // on the side wall, facing -y, 39 degrees off the line from the base
  side.id = "side_panel";
  side.name = "Side panel";
  side.T_world_object.linear() << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // x along the wall, y down, z into it (+y)
  side.T_world_object.translation() = Eigen::Vector3d(2.0, 2.5, 1.0);
  side.width_m = 0.3;
  side.height_m = 0.2;
  lab.instruments.push_back(side);
  // Angle between the panel's outward normal (-y) and the line from the panel to the drone.
  const auto oblique_deg = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d from = (p - side.T_world_object.translation()).head<2>();
    return std::acos(std::clamp(-from.y() / from.norm(), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  };
  REQUIRE(oblique_deg(Eigen::Vector3d::Zero()) > 35.0);
  ModelFlight f({}, lab);
  REQUIRE(f.request(inspect("side_panel", 2.0)).accepted);
  bool flew_to_view = false, searched_before_view = false;
  double oblique_at_detection = -1;
  const bool ended = f.run_until([&] {
    const control::FlightStatus s = f.stack->status();
    // The stage line never says it searches from the base before it sets off for the viewpoint.
    searched_before_view = searched_before_view || (!flew_to_view && s.stage.find("searching for") != std::string::npos);
    flew_to_view = flew_to_view || s.stage.find("flying to a viewpoint in front of 'side_panel'") != std::string::npos;
    if (flew_to_view && oblique_at_detection < 0 && s.stage.find("searching for") != std::string::npos)
      oblique_at_detection = oblique_deg(f.world->drone.p);
    return s.mission == "idle";
  }, 150.0);
  REQUIRE(ended);
  INFO(f.stack->status().last_event);
  CHECK(f.stack->status().last_event.find("succeeded") != std::string::npos);
  CHECK(flew_to_view);
  CHECK_FALSE(searched_before_view);
  CHECK(oblique_at_detection >= 0);
  CHECK(oblique_at_detection < 31.0);  // searched from where the panel faces the camera within 30 degrees
  CHECK_FALSE(f.world->drone.crashed);

  // A panel facing the base is searched for from where the drone is.
  ModelFlight g({}, lab);
  REQUIRE(g.request(inspect("oscilloscope", 2.0)).accepted);
  bool viewpoint = false;
  REQUIRE(g.run_until([&] {
    viewpoint = viewpoint || g.stack->status().stage.find("viewpoint") != std::string::npos;
    return g.stack->status().stage_index == 3;
  }, 60.0));
  CHECK_FALSE(viewpoint);
}

TEST_CASE("control: a map still without a scale flies the vertical manoeuvre again, kMaxRounds times in all") {
  // Counts the up legs of stage 1: one when SLAM fixes its scale, kMaxRounds when it never does.
  const auto up_legs = [](bool slam_available) {
    ModelFlight f;
    f.world->slam_available = slam_available;
    REQUIRE(f.request(inspect("oscilloscope", 3.0)).accepted);
    int ups = 0;
    bool was_up = false;
    const bool stage_2 = f.run_until([&] {
      const bool up = f.stack->status().stage.find("scale manoeuvre (up") != std::string::npos;
      if (up && !was_up) ++ups;
      was_up = up;
      return f.stack->status().stage_index >= 2;
    }, 120.0);
    CHECK(stage_2);
    return ups;
  };
  CHECK(up_legs(true) == 1);
  REQUIRE(control::TakeOffAndScale::kMaxRounds > 1);
  CHECK(up_legs(false) == control::TakeOffAndScale::kMaxRounds);
}

TEST_CASE("control: losing the instrument in stage 3 triggers re-detection, not a push forward") {
  ModelFlight f;
  reach_standoff_hold(f, 20.0);
  f.world->instrument_visible = false;
  REQUIRE(f.run_until([&] { return f.stack->status().stage.find("re-detecting") != std::string::npos; }, 2.0));
  const double x_at_loss = f.world->drone.p.x();
  f.run(3.0);
  CHECK(f.world->drone.p.x() < x_at_loss + 0.05);  // the panel is at +x: no approach while blind
  CHECK(f.stack->status().stage_index == 3);
  f.world->instrument_visible = true;
  CHECK(f.run_until([&] { return f.stack->status().stage.find("holding") != std::string::npos; }, 20.0));
}

TEST_CASE("control: an approach left on dead reckoning re-detects before the safety hover pauses it") {
  ModelFlight f;
  REQUIRE(f.request(inspect("oscilloscope", 5.0)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage.find("approaching") != std::string::npos; }, 90.0));
  REQUIRE(f.stack->status().source == fusion::FeedbackSource::Slam);
  // SLAM lost, the panel tracked one frame in two: the loss timer never runs 0.5 s, the switch never
  // sees the 0.5 s of unbroken tracking it needs, so the estimate is left on dead reckoning. Staying in
  // the approach meant the safety hover after 1 s, which pauses the mission: stuck until it lands.
  f.world->slam_available = false;
  int tick = 0;
  bool held_by_safety = false;
  const bool redetecting = f.run_until([&] {
    f.world->instrument_visible = tick++ % 2 == 0;
    for (const std::string& a : f.stack->status().safety_alerts) held_by_safety |= a.find("hovering") != std::string::npos;
    return f.stack->status().stage.find("re-detecting") != std::string::npos;
  }, 3.0);
  INFO("stage " << f.stack->status().stage << ", source " << to_string(f.stack->status().source));
  CHECK(redetecting);
  CHECK_FALSE(held_by_safety);
  f.world->instrument_visible = true;  // steady again: the inspection goes on
  CHECK(f.run_until([&] { return f.stack->status().stage.find("holding") != std::string::npos; }, 20.0));
}

TEST_CASE("control: a vertical push out of the panel's view is undone at the standoff's altitude, not by backing off") {
  ModelFlight f;
  hold_at_standoff_without_slam(f);
  REQUIRE(f.stack->status().source == fusion::FeedbackSource::Homography);
  const Eigen::Vector4d hold = *f.stack->status().desired;
  const Eigen::Vector3d hold_position = f.world->drone.p;
  // Held 0.35 m up (the model's climb response is 0.3 s, the firmware's 1.25 s: the model would be back
  // before the loss counts): the panel is below the view, the estimate knows the altitude.
  const double pushed_at = f.t;
  REQUIRE(f.run_until([&] {
    const double rise = std::min(0.35, 0.7 * (f.t - pushed_at));  // up at 0.7 m/s, then held there
    f.world->drone.p.z() = hold_position.z() + rise;
    f.world->drone.v.z() = rise < 0.35 ? 0.7 : 0.0;
    return f.stack->status().stage.find("re-detecting") != std::string::npos;
  }, 3.0));
  double farthest_set_point = 0;
  bool held_by_safety = false;
  const bool back = f.run_until([&] {
    const control::FlightStatus s = f.stack->status();
    if (s.desired) farthest_set_point = std::max(farthest_set_point, (s.desired->head<3>() - hold.head<3>()).norm());
    for (const std::string& a : s.safety_alerts) held_by_safety |= a.find("hovering") != std::string::npos;
    return s.stage.find("holding") != std::string::npos && (f.world->drone.p - hold.head<3>()).norm() < 0.1;
  }, 10.0);
  INFO("stage " << f.stack->status().stage << ", source " << to_string(f.stack->status().source) << ", "
                << (f.world->drone.p - hold.head<3>()).transpose() << " from the set point");
  CHECK(back);
  CHECK(farthest_set_point < 0.05);  // the set point stayed the standoff (the back-off moved it 0.4 m)
  // Re-detection waits for the panel to drive the estimate again: no safety hold on dead reckoning.
  CHECK_FALSE(held_by_safety);
}

TEST_CASE("control: a re-detected panel turns the back-off into the approach before the source switches") {
  ModelFlight f;
  hold_at_standoff_without_slam(f);
  const Eigen::Vector4d hold = *f.stack->status().desired;
  f.world->instrument_visible = false;  // lost at the standoff's altitude: back off
  REQUIRE(f.run_until([&] { return f.stack->status().stage.find("re-detecting") != std::string::npos; }, 2.0));
  f.run(1.0);
  REQUIRE((f.stack->status().desired->head<3>() - hold.head<3>()).norm() > 0.3);  // backing off
  f.world->instrument_visible = true;
  f.run(0.2);  // seen, not yet the source (source_hold_s 0.5 s)
  CHECK(f.stack->status().stage.find("re-detecting") != std::string::npos);
  CHECK((f.stack->status().desired->head<3>() - hold.head<3>()).norm() < 0.05);  // heading back already
  CHECK(f.run_until([&] { return f.stack->status().stage.find("holding") != std::string::npos; }, 10.0));
}

TEST_CASE("control: the localization source switches with hysteresis near the instrument") {
  ModelFlight f;
  REQUIRE(f.request(inspect("oscilloscope", 2.0)).accepted);
  std::vector<fusion::FeedbackSource> seq;
  f.run_until([&] {
    const fusion::FeedbackSource s = f.stack->status().source;
    if (seq.empty() || seq.back() != s) seq.push_back(s);
    return f.stack->status().stage_index >= 5;
  }, 90.0);
  // dead reckoning before SLAM, SLAM far, homography near, SLAM again on the way home, no chattering.
  REQUIRE(seq.size() >= 3);
  CHECK(std::count(seq.begin(), seq.end(), fusion::FeedbackSource::Homography) == 1);
  CHECK(seq.size() <= 5);
}

TEST_CASE("control: requests are refused with the reason") {
  ModelFlight f;
  auto refused = [&](const control::MissionRequest& r, const std::string& why) {
    const control::CommandResult c = f.request(r);
    INFO(to_string(r.kind) << ": " << c.reason);
    CHECK_FALSE(c.accepted);
    CHECK(c.reason.find(why) != std::string::npos);
  };
  // Landed: commands that need flight.
  refused(go(1, 0, 1), "needs flight");
  refused(req(control::RequestKind::Land), "needs flight");
  refused(req(control::RequestKind::Hover), "needs flight");
  refused(req(control::RequestKind::ReturnHome), "needs flight");
  refused(req(control::RequestKind::StopFaceFollow), "no face-follow");
  refused(inspect("multimeter"), "unknown instrument 'multimeter' (known: oscilloscope)");
  refused(inspect("oscilloscope", 3.0, 0.2), "below the safe minimum");
  refused(inspect("oscilloscope", -1.0), "hold time");
  refused(inspect("oscilloscope", std::numeric_limits<double>::quiet_NaN()), "finite");

  take_off(f);
  refused(req(control::RequestKind::Takeoff), "already");
  refused(go(9, 0, 1), "outside the geofence");
  refused(go(1, 0, 5), "z = 5.00 m is outside the geofence");
  refused(go(std::numeric_limits<double>::quiet_NaN(), 0, 1), "finite");
  refused(go(1, 0, std::numeric_limits<double>::infinity()), "finite");
  control::MissionRequest far = req(control::RequestKind::MoveBy);
  far.target << 20, 0, 0, 0;
  refused(far, "outside the geofence");

  REQUIRE(f.request(inspect("oscilloscope", 5.0)).accepted);
  f.run(1.0);
  refused(inspect("oscilloscope"), "mission 'inspect' is running");
  refused(req(control::RequestKind::FindTeacher), "mission 'inspect' is running");
  refused(go(1, 0, 1), "mission 'inspect' is running");
  CHECK(f.stack->status().last_event.find("refused") != std::string::npos);
  // Abort commands are accepted while a mission runs.
  CHECK(f.request(req(control::RequestKind::Hover)).accepted);
  CHECK(f.stack->status().mission == "idle");

  // In emergency only a new take-off is accepted; once down, without a link, nothing takes off.
  REQUIRE(f.request(req(control::RequestKind::EmergencyStop)).accepted);
  f.run(0.1);
  refused(go(1, 0, 1), "emergency");
  refused(inspect("oscilloscope"), "emergency");
  f.run(1.5);
  REQUIRE(f.stack->status().phase == control::FlightPhase::Landed);
  f.stack->on_link_state(LinkState::Lost, f.t);
  refused(req(control::RequestKind::Takeoff), "no link");
  refused(req(control::RequestKind::FindTeacher), "no link");
}

TEST_CASE("control: goto and move-by fly to the target and hold it") {
  ModelFlight f;
  take_off(f);
  REQUIRE(f.request(go(2.0, -1.0, 1.2, 0.5)).accepted);
  f.run(12.0);
  CHECK((f.world->drone.p - Eigen::Vector3d(2.0, -1.0, 1.2)).norm() < 0.1);
  CHECK(std::abs(wrap_angle(f.world->drone.yaw - 0.5)) < 0.05);
  control::MissionRequest by = req(control::RequestKind::MoveBy);
  by.target << 1.0, 0.0, 0.0, 0.0;  // 1 m forward along yaw 0.5
  REQUIRE(f.request(by).accepted);
  f.run(10.0);
  CHECK((f.world->drone.p - Eigen::Vector3d(2.0 + std::cos(0.5), -1.0 + std::sin(0.5), 1.2)).norm() < 0.1);
}

TEST_CASE("control: emergency stop always works") {
  ModelFlight f;
  REQUIRE(f.request(inspect("oscilloscope")).accepted);
  f.run(12.0);
  const control::CommandResult c = f.request(req(control::RequestKind::EmergencyStop));
  CHECK(c.accepted);
  f.run(1.0 / 30.0);
  CHECK(f.last.action == control::FlightOutput::Action::Emergency);
  CHECK(f.stack->status().phase == control::FlightPhase::Emergency);
  CHECK(f.stack->status().mission == "idle");
  // Also while landed, and twice.
  CHECK(f.request(req(control::RequestKind::EmergencyStop)).accepted);
}

TEST_CASE("control: link loss: hover, then land after the configured time") {
  control::ControlConfig cfg;
  cfg.safety.link_loss_land_s = 2.0;
  ModelFlight f(cfg);
  take_off(f);
  f.stack->on_link_state(LinkState::Lost, f.t);
  f.run(1.0);
  CHECK(f.last.action == control::FlightOutput::Action::Hover);
  CHECK_FALSE(f.stack->status().safety_alerts.empty());
  f.run(1.5);
  CHECK(f.stack->status().phase == control::FlightPhase::Landing);
  CHECK(f.last.action == control::FlightOutput::Action::Land);  // repeated while the link is down
  f.stack->on_link_state(LinkState::Connected, f.t);
  CHECK(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Landed; }, 10.0));
}

TEST_CASE("control: low battery returns home and lands, critical battery lands at once") {
  ModelFlight f;
  take_off(f);
  REQUIRE(f.request(go(2.0, 1.0, 1.2)).accepted);
  f.run(6.0);
  f.world->drone.battery = 15;
  f.run(0.2);
  CHECK(f.stack->status().mission == "return_home");
  CHECK(f.stack->status().last_event.find("battery") != std::string::npos);
  CHECK(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Landed; }, 60.0));
  CHECK(f.world->drone.p.head<2>().norm() < 0.1);

  ModelFlight g;
  take_off(g);
  g.world->drone.battery = 5;
  g.run(0.2);
  CHECK(g.stack->status().phase == control::FlightPhase::Landing);
}

TEST_CASE("control: localization lost too long: hover, then land") {
  control::ControlConfig cfg;
  cfg.safety.localization_lost_hover_s = 0.5;
  cfg.safety.localization_lost_land_s = 3.0;
  ModelFlight f(cfg);
  REQUIRE(f.request(inspect("oscilloscope", 30.0)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage_index == 3; }, 60.0));
  f.world->slam_available = false;
  f.world->instrument_visible = false;
  const double z_before = f.world->drone.p.z();
  f.run(1.0);
  // A level hold, not the firmware's hover: altitude and yaw stay controlled.
  CHECK(f.last.action == control::FlightOutput::Action::Move);
  bool hovering_alert = false;
  for (const auto& a : f.stack->status().safety_alerts) hovering_alert |= a.find("hovering") != std::string::npos;
  CHECK(hovering_alert);
  f.world->drone.push({0, 0, 0.5}, 0);  // pushed up while holding: the hold brings it back
  f.run(2.0);
  CHECK(std::abs(f.world->drone.p.z() - z_before) < 0.15);
  f.run(0.5);
  CHECK(f.stack->status().phase == control::FlightPhase::Landing);
  CHECK(f.stack->status().last_event.find("localization lost") != std::string::npos);
}

TEST_CASE("control: a bad altitude estimate cannot fly the drone into the floor: safety climbs on the ultrasound") {
  ModelFlight f;
  take_off(f);
  REQUIRE(f.request(go(1.0, 0.0, 1.0)).accepted);
  f.run(6.0);
  REQUIRE(std::abs(f.world->drone.p.z() - 1.0) < 0.1);
  // The estimate now says 0.9 m higher than the truth: the z controller descends towards the floor.
  f.world->estimate_offset = Eigen::Vector3d(0, 0, 0.9);
  f.run(0.1);
  bool held = false, climbed = false;
  double lowest = 10;
  for (int i = 0; i < 300; ++i) {  // 10 s
    f.run(1.0 / 30.0);
    for (const auto& a : f.stack->status().safety_alerts) {
      held |= a.find("jumped") != std::string::npos;
      climbed |= a.find("climbing") != std::string::npos;
    }
    lowest = std::min(lowest, f.world->drone.p.z());
  }
  CHECK(held);     // the 0.9 m jump first held the drone level for a second
  CHECK(climbed);  // then the ultrasound stopped the descent
  CHECK(lowest > 0.25);
  CHECK(f.stack->status().phase == control::FlightPhase::Flying);
}

TEST_CASE("control: a level hold keeps the altitude and yaw of the set point, braking on the velocity") {
  const control::PoseControlGains g;
  fusion::PoseEstimate pose;
  pose.valid = true;
  pose.T_world_body = make_pose({1.0, 0.0, 1.5}, 0.3);  // 0.5 m above the hold, 0.3 rad off its yaw
  pose.velocity_world = Eigen::Vector3d(0.6, 0.0, 0.0);  // drifting along +x
  const MoveCommand c = level_hold_command(pose, 1.0, 0.0, g);
  CHECK(c.gaz < -0.2);       // descends
  CHECK(c.yaw_rate < -0.3);  // turns back
  // Braking against +x (world) with the body turned 0.3 rad: mostly pitch back, a little roll.
  CHECK(c.pitch < -0.1);
  CHECK(std::hypot(c.pitch, c.roll) <= g.max_tilt_command + 1e-9);
  const MoveCommand up = climb_command(pose, g);
  CHECK(up.gaz > 0.3);
  CHECK(up.yaw_rate == 0.0);
  CHECK(up.pitch < -0.1);
}

TEST_CASE("control: return home lands on the platform from anywhere") {
  ModelFlight f;
  take_off(f);
  REQUIRE(f.request(go(3.0, -2.0, 1.0)).accepted);
  f.run(10.0);
  REQUIRE(f.request(req(control::RequestKind::ReturnHome)).accepted);
  std::set<int> stages;
  REQUIRE(f.run_until([&] {
    stages.insert(f.stack->status().stage_index);
    return f.stack->status().phase == control::FlightPhase::Landed;
  }, 60.0));
  CHECK(stages.count(1) == 1);
  CHECK(stages.count(2) == 1);
  CHECK(stages.count(3) == 1);
  CHECK(f.world->drone.p.head<2>().norm() < 0.10);
}

TEST_CASE("control: the landing centres on the platform as the camera sees it, not on its placement in the world") {
  // The estimator's placement of the platform leans on the lab file and the map as well: 8 cm off
  // here. The camera's own offset from the body is what the drone must centre on.
  ModelFlight f;
  f.world->platform_placement_error = Eigen::Vector3d(0.08, -0.05, 0.0);
  take_off(f);
  REQUIRE(f.request(go(2.0, -1.0, 1.0)).accepted);
  f.run(8.0);
  REQUIRE(f.request(req(control::RequestKind::ReturnHome)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Landed; }, 60.0));
  CHECK(f.world->drone.p.head<2>().norm() < 0.03);
}

// The estimate 0.7 m off along the heading when the drone comes home: above the base as estimated
// the bottom camera (+-0.4 m along the heading at the return altitude) does not see the platform. The
// search around the base finds it, and the landing centres on it as seen.
TEST_CASE("control: the platform not in view above the base: the search around it finds it") {
  ModelFlight f;
  take_off(f);
  REQUIRE(f.request(go(2.0, -1.0, 1.0)).accepted);
  f.run(8.0);
  f.world->estimate_offset = Eigen::Vector3d(0.7, 0.0, 0.0);
  REQUIRE(f.request(req(control::RequestKind::ReturnHome)).accepted);
  bool searched = false;
  REQUIRE(f.run_until([&] {
    searched = searched || f.stack->status().stage.find("searching around the base") != std::string::npos;
    return f.stack->status().phase == control::FlightPhase::Landed;
  }, 90.0));
  INFO(f.stack->status().last_mission_result);
  CHECK(searched);
  CHECK(f.stack->status().last_mission_result.rfind("succeeded", 0) == 0);
  CHECK(f.world->drone.p.head<2>().norm() < 0.05);
}

namespace {

// Out to (2, -1) and home again until the drone hovers above the platform, its estimate off by
// `offset` from the moment it heads home.
void fly_home_to_centring(ModelFlight& f, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  take_off(f);
  REQUIRE(f.request(go(2.0, -1.0, 1.0)).accepted);
  f.run(8.0);
  f.world->estimate_offset = offset;
  REQUIRE(f.request(req(control::RequestKind::ReturnHome)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage == "5 platform: hovering above its centre"; }, 90.0));
}

// On to the landing: whether the platform was searched for again on the way.
bool land_noting_a_new_search(ModelFlight& f) {
  bool searched_again = false;
  REQUIRE(f.run_until([&] {
    searched_again = searched_again || f.stack->status().stage.rfind("5 platform: searching", 0) == 0;
    return f.stack->status().phase == control::FlightPhase::Landed;
  }, 90.0));
  return searched_again;
}

}  // namespace

// The estimator's platform fixes move its pose right after the platform is first seen (seed 76 of the
// randomized campaign: 0.5 m in a second) and the bottom camera's tracker may lose the platform in
// the jerk that follows. The centre target moves with the estimate's correction: kept in the old
// frame, it pointed 0.5 m beside the platform, the drone flew there and landed there.
TEST_CASE("control: the estimate corrected while centring on the platform: the target moves with it") {
  ModelFlight f;
  fly_home_to_centring(f, Eigen::Vector3d(0.7, 0.0, 0.0));
  f.world->estimate_offset = Eigen::Vector3d::Zero();
  f.world->platform_visible = false;
  f.run(2.0);
  f.world->platform_visible = true;
  const bool searched_again = land_noting_a_new_search(f);
  INFO(f.stack->status().last_mission_result);
  CHECK_FALSE(searched_again);
  CHECK(f.stack->status().last_mission_result.rfind("succeeded", 0) == 0);
  CHECK(f.world->drone.p.head<2>().norm() < 0.05);
}

// The platform as seen jitters by more than landing_centre_tolerance_m (a bottom camera off its
// calibration): the tolerance widens over platform_settle_timeout_s, and the drone lands when it is
// nearly centred, before the timeout, rather than from wherever the timeout finds it.
TEST_CASE("control: a platform seen jittering beyond the centring tolerance: landed nearly centred before the timeout") {
  ModelFlight f;
  fly_home_to_centring(f);
  const double centring_from = f.t;
  double side = 1;
  double last_flip = f.t;
  REQUIRE(f.run_until([&] {
    if (f.t - last_flip >= 0.25) {
      side = -side;
      last_flip = f.t;
    }
    f.world->platform_seen_shift_m = Eigen::Vector3d(0.045 * side, 0, 0);
    return f.stack->status().stage.rfind("5 platform", 0) != 0;
  }, 30.0));
  const double centring_s = f.t - centring_from;
  f.world->platform_seen_shift_m.setZero();
  REQUIRE(f.run_until([&] { return f.stack->status().phase == control::FlightPhase::Landed; }, 30.0));
  INFO(f.stack->status().last_mission_result << "; centring took " << centring_s << " s");
  CHECK(centring_s > 2.0);   // not at once: 3 cm is not met
  CHECK(centring_s < 11.0);  // before platform_settle_timeout_s (12 s)
  CHECK(f.stack->status().last_mission_result.find("not settled") == std::string::npos);
  CHECK(f.world->drone.p.head<2>().norm() < 0.06);
}

// A drift the estimate did not see (the drone pushed 0.6 m while the platform was out of view): the
// drone holds the platform's place as estimated, the platform is not below it, and it searches again.
TEST_CASE("control: the platform lost while centring, the estimate unaware: searched again, landed on it") {
  ModelFlight f;
  fly_home_to_centring(f);
  f.world->platform_visible = false;
  f.world->drone.p.x() += 0.6;
  f.world->estimate_offset.x() -= 0.6;
  f.run(0.5);
  f.world->platform_visible = true;
  const bool searched_again = land_noting_a_new_search(f);
  INFO(f.stack->status().last_mission_result);
  CHECK(searched_again);
  CHECK(f.stack->status().last_mission_result.rfind("succeeded", 0) == 0);
  CHECK(f.world->drone.p.head<2>().norm() < 0.05);
}

// Nowhere in sight: every look of the pattern, back above the base, landed there; the result says so.
TEST_CASE("control: the platform seen nowhere around the base: landed at the estimated base, reported") {
  ModelFlight f;
  f.world->platform_visible = false;
  take_off(f);
  REQUIRE(f.request(go(2.0, -1.0, 1.0)).accepted);
  f.run(8.0);
  REQUIRE(f.request(req(control::RequestKind::ReturnHome)).accepted);
  double farthest_m = 0;
  REQUIRE(f.run_until([&] {
    if (f.stack->status().stage.rfind("5 platform", 0) == 0) farthest_m = std::max(farthest_m, f.world->drone.p.head<2>().norm());
    return f.stack->status().phase == control::FlightPhase::Landed;
  }, 120.0));
  const std::string result = f.stack->status().last_mission_result;
  INFO(result);
  CHECK_THAT(result, Catch::Contains("landing platform not found above the base nor 6 looks around it"));
  CHECK(f.world->drone.p.head<2>().norm() < 0.15);
  // The pattern's corners are 1.0 m from the base: it looked there and went no farther.
  CHECK(farthest_m > 0.9);
  CHECK(farthest_m < 1.2);
}

TEST_CASE("control: find teacher searches, follows the face and stops on request") {
  ModelFlight f;
  REQUIRE(f.request(req(control::RequestKind::FindTeacher)).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage == "3 face-follow"; }, 60.0));
  f.run(8.0);
  auto face_in_cam = [&]() -> Eigen::Vector3d {
    return ((f.world->drone.pose() * T_body_cam_front()).inverse() * f.world->T_world_face).translation();
  };
  CHECK(std::abs(face_in_cam().z() - 1.0) < 0.1);
  const CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
  CHECK(std::abs(k.fx * face_in_cam().x() / face_in_cam().z() + k.cx - 0.5 * k.width) < 0.1 * k.width);
  // The teacher walks at 0.5 m/s along y for 2 s: the drone follows.
  double worst = 0;
  for (int i = 0; i < 60; ++i) {
    f.world->T_world_face.translation().y() += 0.5 / 30.0;
    f.run(1.0 / 30.0);
  }
  f.run(6.0);
  worst = std::abs(face_in_cam().z() - 1.0);
  CHECK(worst < 0.1);
  REQUIRE(f.request(req(control::RequestKind::StopFaceFollow)).accepted);
  f.run(0.1);
  CHECK(f.stack->status().mission == "idle");
  CHECK(f.stack->status().phase == control::FlightPhase::Flying);
}
