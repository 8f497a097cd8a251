// Face-follow of a teacher walking the path of config/lab.json, in its room (y -3..3: the long leg at
// y = -2.4 lies 0.6 m from the wall, outside the follow's wall clearance), with the perception model's
// face. The flight software is told nothing of the walk: the tests move the face, nothing else.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "localization/fusion/lab_pipelines.hpp"
#include "model_flight.hpp"
#include "teacher_walks.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::control;
using namespace labo::bench;

namespace {

fusion::LabGeometry lab_of_config() {
  fusion::LabGeometry lab = model_lab();
  lab.room_min = {-1.5, -3.0, 0.0};
  lab.room_max = {6.5, 3.0, 3.0};
  return lab;
}

struct WalkFlight {
  explicit WalkFlight(TeacherSpec walk = test::lab_path(), control::ControlConfig config = {})
      : lab(lab_of_config()), motion(std::move(walk)), f(std::move(config), lab) {}
  fusion::LabGeometry lab;
  TeacherMotion motion;
  test::ModelFlight f;
  Seconds walk_from = 0;  // the walk's time 0 (it stands at its first waypoint until then)

  TeacherPose teacher() const { return motion.pose(std::max(0.0, f.t - walk_from)); }
  void tick() {
    f.world->T_world_face = teacher().T_world_head * fusion::flip_about_y();
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
  // Ticks until the teacher walks leg A (along +x) between x_min and x_max with the face followed
  // and the drone at the distance (within 5 cm: it comes round the corner behind the teacher).
  bool until_settled_on_leg_a(double x_min, double x_max) {
    for (const double end = f.t + 3 * motion.cycle_s(); f.t < end;) {
      tick();
      const TeacherPose p = teacher();
      const double x = p.T_world_head.translation().x();
      if (p.walking && std::cos(p.heading_rad) > 0.9 && x > x_min && x < x_max && std::abs(depth_error_m()) < 0.05 &&
          f.stack->status().stage == "3 face-follow")
        return true;
    }
    return false;
  }
  double drone_to_teacher_m() const {
    return (f.world->drone.pose().translation() - teacher().T_world_head.translation()).head<2>().norm();
  }
  double depth_error_m() const {
    const Eigen::Vector3d p = ((f.world->drone.pose() * T_body_cam_front()).inverse() * teacher().T_world_head).translation();
    return p.z() - 1.0;
  }
};
}  // namespace

TEST_CASE("control: a correction of the drone's pose estimate is not taken for the teacher's walk") {
  // On dead reckoning over a bare floor the estimator corrects the drone's estimate by about 0.1 m
  // within one tick; the faces placed from it move as much. Wrong: the track reads that as 0.27 m/s of
  // walking, its heading swings and the set point with it. Here the estimate jumps 0.12 m across a
  // straight walk along +x in the middle of the room (clear of the wall clearance, which is fixed in
  // the estimate's frame) once the drone has settled in front of the teacher: in truth it should stay
  // in front.
  TeacherSpec walk = test::lab_path();
  walk.waypoints = {{0.0, -1.0}, {4.5, -1.0}};
  walk.pauses_s = {2.0, 0.0};
  walk.loop = false;
  WalkFlight r{walk};
  r.walk_from = 1e9;  // standing at the start while found
  REQUIRE(r.find_and_settle());
  r.walk_from = r.f.t;
  const auto sideways_m = [&] {
    const TeacherPose p = r.teacher();
    const Eigen::Vector2d across(-std::sin(p.heading_rad), std::cos(p.heading_rad));
    return across.dot((r.f.world->drone.pose().translation() - p.T_world_head.translation()).head<2>());
  };
  // Settled: walking, followed, and within 5 cm of the teacher's line for the last second.
  Seconds settled_since = -1;
  for (const double end = r.f.t + 8.0; r.f.t < end && (settled_since < 0 || r.f.t - settled_since < 1.0);) {
    r.tick();
    const bool on_line = r.teacher().walking && std::abs(sideways_m()) < 0.05 && r.f.stack->status().stage == "3 face-follow";
    if (!on_line) settled_since = -1;
    else if (settled_since < 0) settled_since = r.f.t;
  }
  REQUIRE(settled_since >= 0);
  REQUIRE(r.f.t - settled_since >= 1.0);
  const TeacherPose at_jump = r.teacher();
  const Eigen::Vector2d across(-std::sin(at_jump.heading_rad), std::cos(at_jump.heading_rad));
  const double before = sideways_m();
  r.f.world->estimate_offset = Eigen::Vector3d(0.12 * across.x(), 0.12 * across.y(), 0.0);
  double worst = 0;
  for (const double end = r.f.t + 2.5; r.f.t < end;) {
    r.tick();
    REQUIRE(r.teacher().walking);
    worst = std::max(worst, std::abs(sideways_m()));
  }
  // Before this change: 0.25 m sideways 1.7 s after the jump (0.02 m with it).
  INFO("sideways before the jump " << before << " m, worst after it " << worst << " m");
  CHECK(worst < 0.12);
}

TEST_CASE("control: as the teacher walks the short leg round a corner, the camera turns with the bearing to them") {
  // Going round the corner with the teacher (~0.5 rad/s round them), the yaw loop alone lags the
  // bearing by 0.15-0.3 rad: the face of the teacher walking the 0.5 m leg sits a quarter of a metre
  // off the centre ray. The bearing's rate is fed forward; without it (the feed-forward set to 0) the
  // aim is worse.
  const auto short_leg_aim_rms_rad = [](control::ControlConfig config) {
    WalkFlight r{test::lab_path(), std::move(config)};
    REQUIRE(r.find_and_settle());
    double sum = 0;
    int n = 0;
    for (const double end = r.f.t + 2 * r.motion.cycle_s(); r.f.t < end;) {
      r.tick();
      const TeacherPose p = r.teacher();
      const bool short_leg = p.walking && std::sin(p.heading_rad) > 0.9;  // (4.2, -2.4) -> (4.2, -1.9)
      if (short_leg && r.f.stack->status().stage.rfind("3 face-follow", 0) == 0) {
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

TEST_CASE("control: a face lost for a few frames mid-walk is bridged along the track, not taken for a loss") {
  // At the tracker's limit (~35 degrees of head yaw) the face flickers. Each flicker must not send the
  // mission through Lost, resetting the controller: a loss shorter than 0.25 s while the teacher walks
  // is flown along the coasted track.
  WalkFlight r;
  REQUIRE(r.find_and_settle());
  REQUIRE(r.until_settled_on_leg_a(2.2, 3.4));
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

TEST_CASE("control: teachers walking at 0.3 and 0.7 m/s are both followed at the distance, from the face's motion alone") {
  // The teacher stands, then sets off at the drone at full speed within one frame. Nothing tells the
  // drone when: it learns of the walk from the face's displacement (the track's velocity rises with
  // kVelocityTauS 0.4 s), and the xy loop (kp 0.7, kd 0.4 per m/s, its tilt clipped to half the
  // firmware's 12 degrees: 1 m/s^2 less drag) answers a 0.7 m/s step by losing about 0.45 m of the
  // standoff within the first second and closing it over the next two. Each speed is checked on
  // its set-off (never nearer than 0.65 m: the hull and the body touch at 0.51 m) and on the follow
  // once that gap is closed (from 3 s after the set-off).
  for (const double speed : {0.3, 0.7}) {
    TeacherSpec walk = test::lab_path();
    walk.waypoints = {{0.0, -1.0}, {4.5, -1.0}};
    walk.pauses_s = {2.0, 0.0};
    walk.loop = false;
    walk.speed_mps = speed;
    WalkFlight r{walk};
    r.walk_from = 1e9;  // standing at the start while found
    REQUIRE(r.find_and_settle());
    r.walk_from = r.f.t;
    double sum = 0, nearest = 10;
    int n = 0;
    while (r.f.t < r.walk_from + 2.0 + 4.5 / speed) {
      r.tick();
      nearest = std::min(nearest, r.drone_to_teacher_m());
      if (r.f.t > r.walk_from + 2.0 + 3.0) {  // past the set-off
        sum += r.depth_error_m() * r.depth_error_m();
        ++n;
      }
    }
    const double rms = std::sqrt(sum / std::max(n, 1));
    INFO("at " << speed << " m/s: depth error RMS " << rms << " m, nearest " << nearest << " m, " << r.f.stack->status().stage);
    CHECK(rms < 0.15);
    CHECK(nearest > 0.65);
    CHECK(r.f.stack->status().stage == "3 face-follow");
  }
}

TEST_CASE("control: a teacher who turns their back is gone round until the face is seen again") {
  // Standing, followed from the front; then the teacher turns away within half a second. The face is
  // lost (nothing says which way they turned): the drone goes round the place they stand at, looking
  // at it, until the face comes back into view, and follows it from the front again.
  WalkFlight r;
  const Eigen::Vector3d at(2.0, -0.5, 1.65);
  const auto stand = [&](double heading) {
    // The head's frame (z out of the face, y up, x the subject's left) facing `heading`.
    Eigen::Isometry3d head = Eigen::Isometry3d::Identity();
    head.linear().col(0) = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
    head.linear().col(1) = Eigen::Vector3d::UnitZ();
    head.linear().col(2) = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    head.translation() = at;
    r.f.world->T_world_face = head * fusion::flip_about_y();
  };
  stand(std::numbers::pi);  // looking at the base
  control::MissionRequest req;
  req.kind = control::RequestKind::FindTeacher;
  REQUIRE(r.f.request(req).accepted);
  REQUIRE(r.f.run_until([&] { return r.f.stack->status().stage == "3 face-follow"; }, 120.0));
  r.f.run(5.0);
  const double away = 0.2;  // facing +x, a little to the left
  for (int k = 1; k <= 15; ++k) {
    stand(std::numbers::pi + (away - std::numbers::pi) * k / 15.0);
    r.f.run(1.0 / 30.0);
  }
  bool went_round = false;
  double nearest = 10;
  Seconds found_again = -1;
  for (const double end = r.f.t + 15.0; r.f.t < end && found_again < 0;) {
    r.f.run(1.0 / 30.0);
    const std::string stage = r.f.stack->status().stage;
    went_round = went_round || stage.find("going round") != std::string::npos;
    nearest = std::min(nearest, (r.f.world->drone.pose().translation() - at).head<2>().norm());
    if (went_round && stage == "3 face-follow") found_again = r.f.t;
  }
  INFO("went round " << went_round << ", found again " << found_again << ", nearest " << nearest << " m");
  CHECK(went_round);
  REQUIRE(found_again > 0);
  CHECK(nearest > 0.6);
  r.f.run(5.0);
  const Eigen::Vector2d out = (r.f.world->drone.pose().translation() - at).head<2>();
  CHECK(std::abs(wrap_angle(std::atan2(out.y(), out.x()) - away)) < 0.3);  // in front of them
  // At the distance: the camera (0.2 m ahead of the body's centre) 1 m from the face.
  const Eigen::Vector3d face_in_camera = ((r.f.world->drone.pose() * T_body_cam_front()).inverse() * at);
  CHECK(std::abs(face_in_camera.z() - 1.0) < 0.15);
}

TEST_CASE("control: a teacher walking along a wall is followed at the distance on an estimate that has drifted far") {
  // After a minute of dead reckoning the estimate's drift bound is 1.5 m, and the walls are kept off
  // by it. Wrong: the standoff in front of a teacher walking 0.6 m from the wall was clamped 1.5 m
  // into the room, and the drone watched them from 1.7 m away and 50 degrees off their line of sight
  // (where the real landmarks stop fitting). The face's place shares the estimate's error with every
  // set point made from it, so a standoff no nearer the wall than the face is inside the room.
  TeacherSpec walk = test::lab_path();
  walk.waypoints = {{-0.5, -2.4}, {2.5, -2.4}};  // the standoff 1 m ahead stays clear of the end wall's bound
  walk.pauses_s = {2.0, 0.0};
  walk.loop = false;
  WalkFlight r{walk};
  r.walk_from = 1e9;  // standing at the start while found
  r.f.world->position_sigma_m = 0.1;
  r.f.world->drift_bound_m = 1.5;
  REQUIRE(r.find_and_settle());
  r.walk_from = r.f.t;
  std::vector<double> depth_error, across;
  double nearest_wall = 10;
  for (const double end = r.f.t + 9.0; r.f.t < end;) {
    r.tick();
    const TeacherPose p = r.teacher();
    nearest_wall = std::min(nearest_wall, r.f.world->drone.p.y() + 3.0);
    if (r.f.t - r.walk_from < 4.0) continue;  // set off 2 s ago
    depth_error.push_back(r.depth_error_m());
    across.push_back(r.f.world->drone.p.y() - p.T_world_head.translation().y());
  }
  REQUIRE(depth_error.size() > 100);
  const auto rms = [](const std::vector<double>& v) {
    double s = 0;
    for (double e : v) s += e * e;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  const double worst_across = std::max(-*std::min_element(across.begin(), across.end()), *std::max_element(across.begin(), across.end()));
  INFO("walking: depth error RMS " << rms(depth_error) << " m, worst sideways " << worst_across << " m; drone nearest the wall "
                                   << nearest_wall << " m; stage " << r.f.stack->status().stage);
  // Without the face's place widening the fence: RMS 0.71 m, 1.65 m sideways (with it 0.06 m, 0.25 m).
  CHECK(rms(depth_error) < 0.15);
  CHECK(worst_across < 0.3);
  CHECK(nearest_wall > 0.3);  // the geofence's margin, the hull 0.26 m
}
