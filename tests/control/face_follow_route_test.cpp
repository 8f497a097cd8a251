// Face-follow along the route of config/lab.json, in its room (y -3..3: the long leg at y = -2.4 lies
// 0.6 m from the wall, outside the follow's wall clearance), with the perception model's face.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "localization/fusion/lab_pipelines.hpp"
#include "control/teacher_watch_points.hpp"
#include "model_flight.hpp"
#include "teacher_routes.hpp"

using namespace labo;
using namespace labo::control;

namespace {

fusion::LabGeometry lab_of_config() {
  fusion::LabGeometry lab = model_lab();
  lab.room_min = {-1.5, -3.0, 0.0};
  lab.room_max = {6.5, 3.0, 3.0};
  lab.teacher = test::lab_route();
  return lab;
}

struct RouteFlight {
  explicit RouteFlight(fusion::LabGeometry l = lab_of_config(), control::ControlConfig config = {}) : lab(std::move(l)), f(std::move(config), lab) {}
  fusion::LabGeometry lab;
  TeacherMotion motion{test::walking(lab.teacher)};
  test::ModelFlight f;
  Eigen::Vector3d face_shift = Eigen::Vector3d::Zero();  // the face seen this far from the head's place

  void tick() {
    f.world->T_world_face = Eigen::Translation3d(face_shift) * motion.pose(f.t).T_world_head * fusion::flip_about_y();
    f.run(1.0 / 30.0);
  }
  bool find_and_settle() {
    control::MissionRequest r;
    r.kind = control::RequestKind::FindTeacher;
    if (!f.request(r).accepted) return false;
    for (const double end = f.t + 150; f.t < end;) {
      tick();
      if (f.stack->status().stage == "3 face-follow") break;
    }
    for (const double end = f.t + 5.0; f.t < end;) tick();
    return f.stack->status().stage.rfind("3 face-follow", 0) == 0;
  }
  // Ticks until the teacher has just finished a short leg (standing at the corner before a long one).
  bool until_end_of_short_leg() {
    bool on_short = false;
    for (const double end = f.t + 2 * motion.cycle_s(); f.t < end;) {
      tick();
      const TeacherPose p = motion.pose(f.t);
      if (p.walking && std::abs(std::cos(p.heading_rad)) < 0.1) on_short = true;
      else if (on_short && !p.walking) return true;
    }
    return false;
  }
  // Ticks until the teacher walks leg A (along +x) between x_min and x_max with the face followed.
  bool until_walking_leg_a(double x_min, double x_max) {
    for (const double end = f.t + 3 * motion.cycle_s(); f.t < end;) {
      tick();
      const TeacherPose p = motion.pose(f.t);
      const double x = p.T_world_head.translation().x();
      if (p.walking && std::cos(p.heading_rad) > 0.9 && x > x_min && x < x_max &&
          f.stack->status().stage == "3 face-follow")
        return true;
    }
    return false;
  }
  double drone_to_teacher_m() const {
    return (f.world->drone.pose().translation() - motion.pose(f.t).T_world_head.translation()).head<2>().norm();
  }
  double depth_error_m() const {
    const Eigen::Vector3d p = ((f.world->drone.pose() * T_body_cam_front()).inverse() * motion.pose(f.t).T_world_head).translation();
    return p.z() - 1.0;
  }
  struct LegStart {
    Seconds walking_since = -1;  // when the teacher set off (-1: not within 20 s)
    double nearest_m = 10;       // the drone's nearest approach to the teacher
    double depth_error_at_set_off_m = 0;
    double depth_error_rms_m = 0;  // over the leg's first 4 s
  };
  static bool walking(const TeacherPose& p) { return p.walking; }
  static bool walking_leg_a(const TeacherPose& p) { return p.walking && std::cos(p.heading_rad) > 0.9; }
  // Flies until the teacher has walked 4 s of the leg `on_leg` recognises (by default the next one
  // they walk; at most 20 s); `visible(t, walking_since)` says whether the face can be seen at t
  // (walking_since < 0 while the teacher has not set off), and may note what the drone does meanwhile.
  template <typename Visible, typename OnLeg = bool (*)(const TeacherPose&)>
  LegStart measure_leg_start(Visible visible, OnLeg on_leg = walking) {
    LegStart out;
    double sum = 0;
    int n = 0;
    for (const double end = f.t + 20.0; f.t < end;) {
      tick();
      if (out.walking_since < 0 && on_leg(motion.pose(f.t))) {
        out.walking_since = f.t;
        out.depth_error_at_set_off_m = depth_error_m();
      }
      f.world->face_visible = visible(f.t, out.walking_since);
      out.nearest_m = std::min(out.nearest_m, drone_to_teacher_m());
      if (out.walking_since >= 0) {
        sum += depth_error_m() * depth_error_m();
        ++n;
      }
      if (out.walking_since >= 0 && f.t - out.walking_since > 4.0) break;
    }
    out.depth_error_rms_m = std::sqrt(sum / std::max(n, 1));
    return out;
  }
};

// A leg started in front of the teacher: never nearer than 0.7 m, depth error RMS over its first 4 s
// below 0.3 m.
void check_leg_start_met(const RouteFlight::LegStart& leg) {
  INFO("nearest " << leg.nearest_m << " m, depth error RMS over the leg's first 4 s " << leg.depth_error_rms_m << " m");
  REQUIRE(leg.walking_since > 0);
  CHECK(leg.nearest_m > 0.7);
  CHECK(leg.depth_error_rms_m < 0.3);
}
}  // namespace

TEST_CASE("control: next_long_leg is the route's own leg, not one drawn in from the walls") {
  // The meeting point drawn in 0.2 m from leg A's start (1.2, -2.4) lies within 0.6 m of the short
  // leg's start (1.2, -1.9) too: the leg walked next is still A, 3 m long.
  const std::optional<control::RouteLeg> leg = next_long_leg(test::lab_route(), {1.2, -2.2}, 0.6);
  REQUIRE(leg);
  CHECK(leg->index == 0);
  CHECK(leg->length_m == Approx(3.0));
  CHECK((leg->from - Eigen::Vector2d(1.2, -2.4)).norm() < 1e-12);
  CHECK(leg->along.x() == Approx(1.0));
  CHECK_FALSE(next_long_leg(test::lab_route(), {2.5, -2.4}, 0.6));  // mid-leg: at no corner
}

TEST_CASE("control: metres_short_of_waypoint measures along the leg into a waypoint, only on it") {
  const fusion::TeacherRoute route = test::lab_route();
  // Leg C runs (4.2, -1.9) -> (1.2, -1.9), into waypoint 3.
  CHECK(metres_short_of_waypoint(route, {1.65, -1.9}, 3, 0.25) == Approx(0.45));
  CHECK(metres_short_of_waypoint(route, {1.65, -1.75}, 3, 0.25) == Approx(0.45));  // off the line, within tolerance
  CHECK(metres_short_of_waypoint(route, {1.65, -2.4}, 3, 0.25) < 0);  // on leg A, alongside: not leg C
  CHECK(metres_short_of_waypoint(route, {0.9, -1.9}, 3, 0.25) < 0);   // past its end
  // The loop's closing leg (1.2, -1.9) -> (1.2, -2.4) ends at waypoint 0.
  CHECK(metres_short_of_waypoint(route, {1.2, -2.1}, 0, 0.25) == Approx(0.3));
}

TEST_CASE("control: route_place_before walks the pauses and the short leg between a corner and the next long leg") {
  // Reached (4.2, -2.4) at 0: pause 3 s, the 0.5 m leg to (4.2, -1.9) in 1.25 s, pause 3 s, then leg C.
  const std::optional<control::RouteLeg> leg = next_long_leg(test::lab_route(), {4.2, -2.4}, 0.25);
  REQUIRE(leg);
  CHECK(leg->index == 2);
  CHECK(seconds_to_set_off(test::lab_route(), {4.2, -2.4}, *leg) == Approx(7.25));
  CHECK((route_place_before(test::lab_route(), *leg, 1.0) - Eigen::Vector2d(4.2, -2.4)).norm() < 1e-9);
  CHECK((route_place_before(test::lab_route(), *leg, 3.625) - Eigen::Vector2d(4.2, -2.15)).norm() < 1e-9);
  CHECK((route_place_before(test::lab_route(), *leg, 5.0) - Eigen::Vector2d(4.2, -1.9)).norm() < 1e-9);
  CHECK((route_place_before(test::lab_route(), *leg, 20.0) - Eigen::Vector2d(4.2, -1.9)).norm() < 1e-9);
}

TEST_CASE("control: a face lost as the teacher sets off along the leg by the wall is predicted along the whole leg") {
  // The face lost 0.3 s into leg A, the track still standing (the face's jitter hides 0.1 m of
  // walking). Wrong: the predicted teacher stops after 0.5 m (the short leg's length, taken from the
  // wrong corner) and the drone waits there while the teacher walks on at it.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  REQUIRE(r.until_end_of_short_leg());
  Seconds walking_since = -1;
  double nearest = 10;
  const double hidden_until_walked_s = 5.0;  // 2 m of the 3 m leg
  for (const double end = r.f.t + 20.0; r.f.t < end;) {
    r.tick();
    const TeacherPose p = r.motion.pose(r.f.t);
    if (walking_since < 0 && p.walking) walking_since = r.f.t;
    // Lost as they set off: nothing in the face's track says they walk yet.
    if (walking_since >= 0) r.f.world->face_visible = r.f.t - walking_since > hidden_until_walked_s;
    nearest = std::min(nearest, r.drone_to_teacher_m());
    if (walking_since >= 0 && r.f.t - walking_since > hidden_until_walked_s) break;
  }
  INFO("nearest " << nearest << " m, depth error " << r.depth_error_m() << " m, stage " << r.f.stack->status().stage);
  REQUIRE(walking_since > 0);
  CHECK(nearest > 0.7);                          // hull 0.26 m + body 0.25 m, with margin
  CHECK(std::abs(r.depth_error_m()) < 0.35);     // still in front, near the meeting distance (1.2 m)
}

TEST_CASE("control: a face lost at a corner waits for the teacher pausing there, not ahead of them") {
  // The face lost as the teacher reaches a corner and stands there 3 s turning. Wrong: the prediction
  // walks the next leg from that moment, and the drone waits ahead of a teacher who is not there, far
  // from the face when they set off. Here a square of 3 m legs (90 degree turns, no turn back: the
  // drone follows into the corner).
  fusion::LabGeometry lab = model_lab();  // fence x -0.7..4.7, y -2.7..2.7
  lab.teacher = test::lab_route();
  lab.teacher.waypoints = {{0.5, -1.5}, {3.5, -1.5}, {3.5, 1.5}, {0.5, 1.5}};
  RouteFlight r{lab};
  REQUIRE(r.find_and_settle());
  // Until the teacher stops at a corner while followed.
  bool was_walking = false;
  for (const double end = r.f.t + 2 * r.motion.cycle_s(); r.f.t < end;) {
    r.tick();
    const bool walking = r.motion.pose(r.f.t).walking;
    if (was_walking && !walking && r.f.stack->status().stage == "3 face-follow") break;
    was_walking = walking;
  }
  REQUIRE_FALSE(r.motion.pose(r.f.t).walking);
  // Hidden while they stand and turn, and for the first second of the next leg.
  const auto leg = r.measure_leg_start([](Seconds t, Seconds walking_since) { return walking_since >= 0 && t - walking_since > 1.0; });
  check_leg_start_met(leg);
}

TEST_CASE("control: a face taken up for a moment at the corner keeps the meeting's wait for the teacher to set off") {
  // Met in front of leg C, the drone takes the face up just before the teacher stops at its corner and
  // loses it 0.4 s later. Wrong: with nothing seen walking, the prediction walks leg C at once, 3 s
  // early, and the drone waits too far along it.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  // Until the teacher stands at the corner before a long leg with the drone in front of it, hidden
  // from the end of the short leg on.
  REQUIRE(r.until_end_of_short_leg());
  r.f.world->face_visible = false;
  const Seconds stopped = r.f.t;
  for (const double end = r.f.t + 1.0; r.f.t < end;) r.tick();
  REQUIRE(r.f.stack->status().stage.find("meeting") != std::string::npos);
  // Seen for 0.4 s while standing there, then hidden until 1 s into the leg.
  const auto leg = r.measure_leg_start([stopped](Seconds t, Seconds walking_since) {
    const bool glimpse = t - stopped > 1.0 && t - stopped < 1.4;
    return glimpse || (walking_since >= 0 && t - walking_since > 1.0);
  });
  check_leg_start_met(leg);
}

TEST_CASE("control: a correction of the drone's pose estimate is not taken for the teacher's walk") {
  // On dead reckoning over a bare floor the estimator corrects the drone's estimate by about 0.1 m
  // within one tick; the faces placed from it move as much. Wrong: the track reads that as 0.27 m/s of
  // walking, its heading swings and the set point with it. Here the estimate jumps 0.12 m across a
  // long leg while the teacher walks it (leg C, y = -1.9: the standoff there is clear of the wall
  // clearance, which is fixed in the estimate's frame): the drone, in truth, should stay in front of
  // them.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  // Until the teacher has walked 3 s of leg C (along -x), followed (the drone settled in front).
  Seconds walking_since = -1;
  for (const double end = r.f.t + 2 * r.motion.cycle_s(); r.f.t < end;) {
    r.tick();
    const TeacherPose p = r.motion.pose(r.f.t);
    const bool long_leg = p.walking && std::cos(p.heading_rad) < -0.9;
    if (!long_leg) walking_since = -1;
    else if (walking_since < 0) walking_since = r.f.t;
    if (walking_since >= 0 && r.f.t - walking_since > 3.0 && r.f.stack->status().stage == "3 face-follow") break;
  }
  REQUIRE(r.f.stack->status().stage == "3 face-follow");
  const TeacherPose at_jump = r.motion.pose(r.f.t);
  const Eigen::Vector2d across(-std::sin(at_jump.heading_rad), std::cos(at_jump.heading_rad));
  const auto sideways_m = [&] {
    const TeacherPose p = r.motion.pose(r.f.t);
    return across.dot((r.f.world->drone.pose().translation() - p.T_world_head.translation()).head<2>());
  };
  const double before = sideways_m();
  r.f.world->estimate_offset = Eigen::Vector3d(0.12 * across.x(), 0.12 * across.y(), 0.0);
  double worst = 0;
  for (const double end = r.f.t + 2.5; r.f.t < end;) {
    r.tick();
    REQUIRE(r.motion.pose(r.f.t).walking);
    worst = std::max(worst, std::abs(sideways_m()));
  }
  // Before this change: 0.25 m sideways 1.7 s after the jump (0.02 m with it).
  INFO("sideways before the jump " << before << " m, worst after it " << worst << " m");
  CHECK(std::abs(before) < 0.1);
  CHECK(worst < 0.12);
}

TEST_CASE("control: going round to the next leg, the camera turns with the bearing to the teacher on the short leg") {
  // Going round the corner to meet the teacher in front of leg C (~0.5 rad/s round them), the yaw loop
  // alone lags the bearing by 0.15-0.3 rad: the face of the teacher walking the 0.5 m leg sits a
  // quarter of a metre off the centre ray. The bearing's rate is fed forward; without it (the
  // feed-forward set to 0) the aim is worse.
  const auto short_leg_aim_rms_rad = [](control::ControlConfig config) {
    RouteFlight r{lab_of_config(), std::move(config)};
    REQUIRE(r.find_and_settle());
    double sum = 0;
    int n = 0;
    for (const double end = r.f.t + 2 * r.motion.cycle_s(); r.f.t < end;) {
      r.tick();
      const TeacherPose p = r.motion.pose(r.f.t);
      const bool short_leg = p.walking && std::sin(p.heading_rad) > 0.9;  // (4.2, -2.4) -> (4.2, -1.9)
      if (short_leg && r.f.stack->status().stage.find("meeting") != std::string::npos) {
        const Eigen::Vector3d c = ((r.f.world->drone.pose() * T_body_cam_front()).inverse() * p.T_world_head).translation();
        sum += std::pow(std::atan2(c.x(), c.z()), 2);
        ++n;
      } else if (n > 0) {
        break;
      }
    }
    REQUIRE(n > 20);
    return std::sqrt(sum / n);
  };
  control::ControlConfig without;
  without.gains.yaw_rate_feedforward = 0;
  const double lagging = short_leg_aim_rms_rad(without);
  const double fed_forward = short_leg_aim_rms_rad(control::ControlConfig{});
  INFO("face off the optical axis on the short leg, RMS: " << lagging << " rad without the feed-forward, " << fed_forward << " rad with it");
  CHECK(fed_forward < 0.1);
  CHECK(fed_forward < 0.6 * lagging);
}

TEST_CASE("control: a face first seen for a moment at the end of a leg waits out the short leg before the next long one") {
  // Found late on leg C (walking at (1.2, -1.9), the corner before the 0.5 m short leg to leg A's
  // start) and lost 0.4 s later: too short a look to see them walk in, so the prediction took them
  // for a teacher standing at a corner and walked leg A at once - 7 s early, while by the route they
  // still pause, walk the short leg and pause again. The drone would wait far along leg A and meet them
  // late.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  r.f.world->face_visible = false;
  // Hidden until the search watches the end of leg C and the teacher is 0.45 m from it.
  bool found_late = false;
  for (const double end = r.f.t + 4 * r.motion.cycle_s(); r.f.t < end;) {
    r.tick();
    const TeacherPose p = r.motion.pose(r.f.t);
    const Eigen::Vector3d head = p.T_world_head.translation();
    const bool end_of_leg_c = p.walking && std::cos(p.heading_rad) < -0.9 && head.x() < 1.65 && head.x() > 1.5;
    const bool watching_leg_c = r.f.stack->status().stage.find("watching") != std::string::npos &&
                                r.f.world->drone.pose().translation().x() < 1.0;
    if (end_of_leg_c && watching_leg_c) {
      found_late = true;
      break;
    }
  }
  REQUIRE(found_late);
  const Seconds seen_from = r.f.t;
  // Seen for 0.4 s, then hidden until 1 s into leg A; measured over leg A's first 4 s.
  bool followed = false;
  const RouteFlight::LegStart leg = r.measure_leg_start(
      [&](Seconds t, Seconds leg_a_since) {
        const bool glimpse = t - seen_from < 0.4;
        if (glimpse && r.f.stack->status().stage.rfind("3 face-follow", 0) == 0) followed = true;
        return glimpse || (leg_a_since >= 0 && t - leg_a_since > 1.0);
      },
      RouteFlight::walking_leg_a);
  REQUIRE(followed);  // the glimpse was seen and taken up
  check_leg_start_met(leg);
}

TEST_CASE("control: waypoint_walked_into is the end of the leg walked along, only while walking it") {
  const fusion::TeacherRoute route = test::lab_route();
  // Mid-leg A (+x into waypoint 1), walking along it.
  const std::optional<std::size_t> k = waypoint_walked_into(route, {2.7, -2.35}, {0.4, 0.0}, 0.25, 0.1);
  REQUIRE(k);
  CHECK(*k == 1);
  // Walking back along leg C (-x into waypoint 3), 0.5 m from leg A: leg C, not A.
  const std::optional<std::size_t> c = waypoint_walked_into(route, {2.7, -1.95}, {-0.4, 0.0}, 0.25, 0.1);
  REQUIRE(c);
  CHECK(*c == 3);
  CHECK_FALSE(waypoint_walked_into(route, {2.7, -2.4}, {0.0, 0.0}, 0.25, 0.1));    // standing
  CHECK_FALSE(waypoint_walked_into(route, {2.7, -2.4}, {-0.4, 0.0}, 0.25, 0.1));   // against the leg
  CHECK_FALSE(waypoint_walked_into(route, {2.7, -2.9}, {0.4, 0.0}, 0.25, 0.1));    // off the route
  const std::optional<control::RouteLeg> after = next_long_leg_from(route, 1);  // past the 0.5 m leg: leg C
  REQUIRE(after);
  CHECK(after->index == 2);
  CHECK(after->corner == 1);
}

TEST_CASE("control: a face lost in the middle of a leg is followed on along the route, not held") {
  // The head's sway takes the face past the detector in the middle of a leg. Holding there, the drone
  // would be walked into; it backs off ahead of where the route has them and meets them at the corner.
  for (const double speed : {0.4, 0.5}) {
    fusion::LabGeometry lab = lab_of_config();
    lab.teacher.speed_mps = speed;
    RouteFlight r(lab);
    REQUIRE(r.find_and_settle());
    // Until the teacher is 1.5 m short of leg A's end, walking it, with the face followed.
    REQUIRE(r.until_walking_leg_a(2.7, 1e9));
    // Hidden for the rest of the leg: 1.5 m, 3-3.75 s of walking.
    r.f.world->face_visible = false;
    double nearest = 10, sum = 0;
    int n = 0;
    for (const double end = r.f.t + 1.5 / speed; r.f.t < end;) {
      r.tick();
      nearest = std::min(nearest, r.drone_to_teacher_m());
      sum += r.depth_error_m() * r.depth_error_m();
      ++n;
    }
    const double rms = std::sqrt(sum / std::max(n, 1));
    INFO("speed " << speed << " m/s: nearest " << nearest << " m, depth error RMS while hidden " << rms << " m");
    CHECK(nearest > 0.8);
    CHECK(rms < 0.15);
  }
}

TEST_CASE("control: a teacher met in front of the next leg is followed from their set-off, not after the walk shows") {
  // Met in front of the leg, a drone that waits for the face's velocity (low-passed over 0.4 s, behind
  // the perception delay) to show the walk lets the teacher come too close in the leg's first seconds,
  // where most of the follow's distance error would then lie. The set-off is fed forward from the
  // route's time or from the first 5 cm the face walks along the leg.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  REQUIRE(r.until_end_of_short_leg());
  Seconds set_off = -1;
  for (const double end = r.f.t + 10.0; r.f.t < end && set_off < 0;) {
    r.tick();
    if (r.motion.pose(r.f.t).walking) set_off = r.f.t;
  }
  REQUIRE(set_off > 0);
  REQUIRE(r.f.stack->status().stage == "3 face-follow");
  double sum = 0, nearest = 10;
  int n = 0;
  for (const double end = set_off + 2.0; r.f.t < end;) {
    r.tick();
    sum += r.depth_error_m() * r.depth_error_m();
    nearest = std::min(nearest, r.depth_error_m());
    ++n;
  }
  const double rms = std::sqrt(sum / n);
  INFO("depth error over the leg's first 2 s: RMS " << rms << " m, most negative " << nearest << " m");
  CHECK(rms < 0.1);        // 0.106 m without the feed-forward (the model has no perception delay)
  CHECK(nearest > -0.07);  // -0.093 m without
}

TEST_CASE("control: a face lost for a few frames mid-leg is bridged along the track, not taken for a loss") {
  // At the tracker's limit (~35 degrees of head yaw) the face flickers. Each flicker must not send the
  // mission through Lost and a meeting, resetting the controller: a loss shorter than 0.25 s while
  // the teacher walks a leg is flown along the coasted track.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  REQUIRE(r.until_walking_leg_a(2.2, 2.8));
  // Hidden for 0.2 s: every tick stays in face-follow, and the drone keeps its distance.
  r.f.world->face_visible = false;
  double worst = 0;
  for (const double end = r.f.t + 0.2; r.f.t < end;) {
    r.tick();
    INFO("t " << r.f.t << ": " << r.f.stack->status().stage);
    CHECK(r.f.stack->status().stage == "3 face-follow");
    worst = std::max(worst, std::abs(r.depth_error_m()));
  }
  r.f.world->face_visible = true;
  for (const double end = r.f.t + 1.0; r.f.t < end;) {
    r.tick();
    worst = std::max(worst, std::abs(r.depth_error_m()));
  }
  INFO("worst depth error over the loss and the second after it: " << worst << " m");
  CHECK(r.f.stack->status().stage == "3 face-follow");
  CHECK(worst < 0.15);
  // A longer loss is a loss: the mission says so.
  r.f.world->face_visible = false;
  bool reported_lost = false;
  for (const double end = r.f.t + 0.6; r.f.t < end;) {
    r.tick();
    reported_lost = reported_lost || r.f.stack->status().stage != "3 face-follow";
  }
  CHECK(reported_lost);
}

namespace {
struct SetOffFlown {
  double depth_error_at_set_off_m = 0;
  double depth_error_rms_m = 0;  // over the leg's first 4 s
};
// Followed standing at the start of the next long leg, 1.5 s before the route's set-off (the pause is
// 3 s), the face's place moves 7 cm along the leg and stays there (a head turning at the corner: the
// face sits in front of the turning axis); 0.3 s later the face is lost until 1 s into the leg, or
// stays in view. `moves_m`: the face's place along the leg after each step (0.3 s apart), from
// `before_m` (where it stands, along the leg from the head, while the teacher waits).
SetOffFlown fly_face_moved_at_corner(bool then_lost, std::initializer_list<double> moves_m = {0.07}, double before_m = 0.0) {
  RouteFlight r;
  SetOffFlown out;
  REQUIRE(r.find_and_settle());
  REQUIRE(r.until_end_of_short_leg());
  const std::optional<control::RouteLeg> leg = next_long_leg(r.lab.teacher, r.motion.pose(r.f.t).T_world_head.translation().head<2>(), 0.6);
  REQUIRE(leg);
  r.face_shift.head<2>() = before_m * leg->along;
  for (const double end = r.f.t + 1.5; r.f.t < end;) r.tick();
  REQUIRE(r.f.stack->status().stage == "3 face-follow");
  REQUIRE_FALSE(r.motion.pose(r.f.t).walking);
  for (const double m : moves_m) {
    r.face_shift.head<2>() = (before_m + m) * leg->along;
    for (const double end = r.f.t + 0.3; r.f.t < end;) r.tick();
  }
  r.f.world->face_visible = !then_lost;
  double sum = 0;
  int n = 0;
  Seconds walking_since = -1;
  for (const double end = r.f.t + 10.0; r.f.t < end;) {
    r.tick();
    if (walking_since < 0 && r.motion.pose(r.f.t).walking) {
      walking_since = r.f.t;
      r.face_shift.setZero();  // the head faces the way they walk
      out.depth_error_at_set_off_m = r.depth_error_m();
    }
    if (then_lost) r.f.world->face_visible = walking_since >= 0 && r.f.t - walking_since > 1.0;
    if (walking_since >= 0) {
      sum += r.depth_error_m() * r.depth_error_m();
      ++n;
      if (r.f.t - walking_since > 4.0) break;
    }
  }
  REQUIRE(walking_since > 0);
  out.depth_error_rms_m = std::sqrt(sum / std::max(n, 1));
  INFO("depth error at the set-off " << out.depth_error_at_set_off_m << " m, RMS over the leg's first 4 s "
                                      << out.depth_error_rms_m << " m");
  return out;
}
}  // namespace

TEST_CASE("control: a face that moves a few cm along the next leg and is lost is no set-off for the meeting") {
  // Met in front of leg C and followed standing at its start, the face's place moves a few cm along
  // the leg before the route's set-off and stops; that first move feeds the route's walking speed
  // forward, and the face is lost just after. Wrong: taking it for a teacher walking the leg (the
  // track's velocity is the feed-forward's), the meeting backs off along it at once, and the drone is
  // far from the face when they come.
  const SetOffFlown flown = fly_face_moved_at_corner(true);
  INFO("depth error at the set-off " << flown.depth_error_at_set_off_m << " m, RMS over the leg's first 4 s "
                                      << flown.depth_error_rms_m << " m");
  // The meeting waits 0.2 m beyond the follow distance; the drone, backing off for the 0.3 s the move
  // was fed forward, overshoots it by ~0.15 m. Without the change: 0.67 m, RMS 0.55 m.
  CHECK(flown.depth_error_at_set_off_m < 0.45);  // 0.34 m
  CHECK(flown.depth_error_rms_m < 0.2);          // 0.105 m
}

TEST_CASE("control: a face that moves a few cm along the next leg and stops is no set-off while followed") {
  // The same few cm with the face still in view: the feed-forward it started is confirmed only by the
  // face walking on; run until the face had walked 0.2 m, i.e. until the teacher really set off, it
  // would back the drone off at the route's speed meanwhile.
  const SetOffFlown flown = fly_face_moved_at_corner(false);
  INFO("depth error at the set-off " << flown.depth_error_at_set_off_m << " m, RMS over the leg's first 4 s "
                                      << flown.depth_error_rms_m << " m");
  // Without the change: 0.50 m, RMS 0.186 m (the feed-forward ran from the 5 cm to the set-off).
  CHECK(flown.depth_error_at_set_off_m < 0.42);  // 0.36 m: the meeting's 0.2 m, and 0.5 s fed forward
  CHECK(flown.depth_error_rms_m < 0.15);         // 0.111 m
}

TEST_CASE("control: a head turning at the corner, its face not yet on the next leg, is no set-off when lost") {
  // Followed standing at the corner before leg C, the face's place moves 6.5 cm along the leg (the
  // feed-forward starts) and 6.5 cm more 0.3 s later (confirmed: the head turning on, not a step), and
  // the face is lost, its place still short of the leg's start. Wrong: the track's fed-forward speed
  // read as a teacher walking the leg, the meeting backing off at once, before the set-off. A velocity
  // counts as a walk only with the face's place on the leg.
  const SetOffFlown flown = fly_face_moved_at_corner(true, {0.065, 0.13}, -0.17);
  INFO("depth error at the set-off " << flown.depth_error_at_set_off_m << " m, RMS over the leg's first 4 s "
                                      << flown.depth_error_rms_m << " m");
  CHECK(flown.depth_error_at_set_off_m < 0.45);
  CHECK(flown.depth_error_rms_m < 0.2);
}

TEST_CASE("control: a face lost walking into a corner and seen again on the way times the set-off from the walk seen") {
  // The face lost half a metre short of the end of leg C, taken up again for 0.4 s on the way in (too
  // short for a walk spell) and lost at the corner. Wrong: timing the set-off along leg A from the end
  // of the last walk spell plus the rest of the way from where the face was *last* seen, at the
  // corner, counts the way walked meanwhile twice: the set-off predicted early, the drone backs off
  // ahead of a teacher who still stands.
  RouteFlight r;
  REQUIRE(r.find_and_settle());
  // Until the teacher walks leg C (-x, y = -1.9) 0.65 m short of its end (1.2, -1.9), followed.
  bool on_leg_c = false;
  for (const double end = r.f.t + 3 * r.motion.cycle_s(); r.f.t < end;) {
    r.tick();
    const TeacherPose p = r.motion.pose(r.f.t);
    const double x = p.T_world_head.translation().x();
    if (p.walking && std::cos(p.heading_rad) < -0.9 && x > 1.8 && x < 1.9 && r.f.stack->status().stage == "3 face-follow") {
      on_leg_c = true;
      break;
    }
  }
  REQUIRE(on_leg_c);
  // Hidden for 0.6 s, seen for 0.4 s on the way in, then hidden until 1 s into leg A.
  const Seconds hidden_at = r.f.t;
  bool seen_on_the_way = false;
  const RouteFlight::LegStart leg = r.measure_leg_start(
      [&](Seconds t, Seconds leg_a_since) {
        const bool on_the_way = t - hidden_at > 0.6 && t - hidden_at < 1.0;
        if (on_the_way && r.f.stack->status().stage == "3 face-follow") seen_on_the_way = true;
        return on_the_way || (leg_a_since >= 0 && t - leg_a_since > 1.0);
      },
      RouteFlight::walking_leg_a);
  REQUIRE(seen_on_the_way);
  REQUIRE(leg.walking_since > 0);
  const double depth_error_at_set_off = leg.depth_error_at_set_off_m, rms = leg.depth_error_rms_m;
  INFO("depth error at leg A's set-off " << depth_error_at_set_off << " m, RMS over its first 4 s " << rms << " m");
  // The meeting waits 0.2 m beyond the follow distance. Without the change: 0.46 m, RMS 0.365 m.
  CHECK(depth_error_at_set_off < 0.38);  // 0.30 m
  CHECK(rms < 0.2);                      // 0.105 m
}
