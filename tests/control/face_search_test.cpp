// Find-teacher's search and the standoff it follows, from the face alone: the tests move the face
// the model perception sees; the flight software is told nothing of where the teacher walks.
#include <catch2/catch.hpp>
#include <cmath>
#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "control/face_search_viewpoints.hpp"
#include "control/face_standoff.hpp"
#include "localization/fusion/lab_pipelines.hpp"
#include "drone/sim/teacher_motion.hpp"
#include "model_flight.hpp"
#include "teacher_walks.hpp"

using namespace labo;
using namespace labo::sim;
using namespace labo::control;
using namespace labo::bench;
using labo::test::turn_back_path;

namespace {
control::MissionRequest find_teacher() {
  control::MissionRequest r;
  r.kind = control::RequestKind::FindTeacher;
  return r;
}
// Asks for the teacher and flies until their face is followed.
void start_following(test::ModelFlight& f) {
  REQUIRE(f.request(find_teacher()).accepted);
  REQUIRE(f.run_until([&] { return f.stack->status().stage == "3 face-follow"; }, 120.0));
}

// The teacher turns their back where they stand: from now on only the head is followed (the front
// end's position_only).
void turn_away_seen_by_the_head(test::ModelWorld& world) {
  world.face_head_only = true;
  world.T_world_face.linear() = world.T_world_face.linear() * Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY());
}
}  // namespace

TEST_CASE("control: search viewpoints cover the free floor, keep off the benches and are toured nearest first") {
  const control::Geofence fence({-1.5, -3.0, 0.0}, {6.5, 3.0, 3.0}, 0.3);  // x -1.2..6.2, y -2.7..2.7
  estimation::SurfaceMap surfaces;
  surfaces.add({{5.7, -2.2}, {6.5, 1.2}, 0.9});  // config/lab.json's east bench
  surfaces.add({{2.2, -0.3}, {2.8, 0.3}, 0.8});  // a table in the middle of the room
  const std::vector<Eigen::Vector3d> v = face_search_viewpoints(fence, surfaces, 1.6, 2.5, 0.6);
  // A 3 x 3 grid of 2.47 x 1.8 m cells (centres x 0.03, 2.5, 4.97; y -1.8, 0, 1.8); the centre one,
  // over the table, is dropped.
  CHECK(v.size() == 8);
  for (const Eigen::Vector3d& p : v) {
    INFO(p.transpose());
    CHECK(fence.contains(p));
    CHECK(p.z() == 1.6);
    CHECK(surfaces.unambiguous_height(p.head<2>(), 0.6) == std::optional<double>(0.0));
  }
  // Every point of the free floor is within the detector's reach (2.5 m) of a viewpoint.
  for (double x = -1.2; x <= 6.2; x += 0.2) {
    for (double y = -2.7; y <= 2.7; y += 0.2) {
      double nearest = 10;
      for (const Eigen::Vector3d& p : v) nearest = std::min(nearest, (p.head<2>() - Eigen::Vector2d(x, y)).norm());
      INFO(x << ", " << y);
      CHECK(nearest < 2.5);
    }
  }
  const std::vector<Eigen::Vector3d> tour = tour_from({6.0, 2.5, 1.0}, v);
  REQUIRE(tour.size() == v.size());
  for (std::size_t i = 1; i + 1 < tour.size(); ++i)  // each leg to the nearest one left
    for (std::size_t j = i + 1; j < tour.size(); ++j)
      CHECK((tour[i] - tour[i - 1]).head<2>().norm() <= (tour[j] - tour[i - 1]).head<2>().norm() + 1e-9);
}

TEST_CASE("control: the face standoff is turned into the fence and reached around the teacher") {
  const control::Geofence fence({-1.5, -3.0, 0.0}, {6.5, 3.0, 3.0}, 0.3);  // y >= -2.7
  const Eigen::Vector3d face(1.2, -2.4, 1.65);
  // The teacher faces the wall (-y): the standoff 1 m in front of them is behind the fence.
  const control::PoseTarget behind{{1.2, -3.4, 1.65}, std::numbers::pi / 2};
  const control::PoseTarget in = follow_standoff(behind, face, {1.2, -1.4, 1.65}, fence, std::numbers::pi);
  CHECK(fence.contains(in.position));
  CHECK((in.position - face).norm() == Approx(1.0));
  CHECK((in.position - face).y() >= -0.3 - 1e-9);
  CHECK((in.position - face).y() < -0.3 + 0.1);  // the smallest turn that brings it in
  // The teacher turned round: the standoff on the far side is approached 60 degrees at a time.
  const control::PoseTarget far_side{{2.2, -1.0, 1.65}, std::numbers::pi};
  const Eigen::Vector3d drone(0.2, -1.0, 1.65), centre(1.2, -1.0, 1.65);
  const control::PoseTarget step = follow_standoff(far_side, centre, drone, fence, std::numbers::pi / 3);
  const double lead = std::atan2((step.position - centre).y(), (step.position - centre).x());
  CHECK(std::abs(std::abs(lead) - 2 * std::numbers::pi / 3) < 1e-9);  // 180 - 60 degrees from +x
  CHECK((step.position - centre).norm() == Approx(1.0));
}

TEST_CASE("control: going round the teacher keeps to the side inside the fence") {
  const control::Geofence fence({-1.5, -3.0, 0.0}, {6.5, 3.0, 3.0}, 0.3);  // y >= -2.7
  const Eigen::Vector3d face(1.2, -2.4, 1.65);
  for (const double side : {-1e-6, 1e-6}) {  // the teacher turned round: either way is as short
    const control::PoseTarget ahead{{2.2, -2.4 + side, 1.65}, std::numbers::pi};
    const control::PoseTarget step = follow_standoff(ahead, face, {0.2, -2.4, 1.65}, fence, std::numbers::pi / 3);
    CHECK(fence.contains(step.position));
    CHECK(step.position.y() > -2.4);  // round the north side, not clamped against the wall behind
  }
}

TEST_CASE("control: find teacher sweeps where it is, then from viewpoints over the floor, until it finds the face") {
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3
  test::ModelFlight f({}, lab);
  // The teacher stands in a corner of the room looking into it, out of the perception's 4 m from the
  // base: the sweep at the base cannot find them.
  const Eigen::Vector3d teacher(4.2, 2.3, 1.65);
  f.world->T_world_face = facing_base(teacher);
  REQUIRE(f.request(find_teacher()).accepted);
  std::vector<std::string> stages;
  REQUIRE(f.run_until([&] {
    if (stages.empty() || stages.back() != f.stack->status().stage) stages.push_back(f.stack->status().stage);
    return f.stack->status().stage == "3 face-follow";
  }, 120.0));
  const auto first = [&](const std::string& prefix) {
    const auto it = std::find_if(stages.begin(), stages.end(), [&](const std::string& s) { return s.rfind(prefix, 0) == 0; });
    return it - stages.begin();
  };
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(stages.size());
  CHECK(first("1 init: scale manoeuvre") < first("2 search: yaw sweep where the drone is"));  // SLAM gets its scale first
  CHECK(first("2 search: yaw sweep where the drone is") < first("2 search: moving to viewpoint"));  // here first
  CHECK(first("2 search: moving to viewpoint") < n);  // then on over the floor
  f.run(8.0);
  const Eigen::Vector3d p = ((f.world->drone.pose() * T_body_cam_front()).inverse() * f.world->T_world_face).translation();
  CHECK(std::abs(p.z() - 1.0) < 0.1);
}

TEST_CASE("control: a search planned on an unsure estimate is planned again over the floor once the estimate firms") {
  // After a minute on dead reckoning the drift bound (2 m) leaves one viewpoint in the middle of the
  // room, out of the detector's reach of a teacher by a wall. Wrong: the tour went on sweeping there
  // after SLAM had found its map again.
  const fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3
  // The stage line as the drone first sets off for a viewpoint, and the tour's size it names.
  const auto first_move = [&](bool firms_in_first_sweep) {
    test::ModelFlight f({}, lab);
    f.world->face_visible = false;
    f.world->position_sigma_m = 0.1;
    f.world->drift_bound_m = 2.0;
    REQUIRE(f.request(find_teacher()).accepted);
    REQUIRE(f.run_until([&] { return f.stack->status().stage == "2 search: yaw sweep where the drone is"; }, 120.0));
    if (firms_in_first_sweep) f.world->drift_bound_m = 0.0;  // SLAM found its map in the sweep
    std::string moving;
    REQUIRE(f.run_until([&] {
      const std::string stage = f.stack->status().stage;
      if (stage.rfind("2 search: moving to viewpoint", 0) == 0) moving = stage;
      return !moving.empty();
    }, 30.0));
    const auto slash = moving.rfind('/');
    REQUIRE(slash != std::string::npos);
    return std::pair{moving, std::stoi(moving.substr(slash + 1))};
  };
  const auto [firmed, firmed_tour] = first_move(true);
  const auto [unsure, unsure_tour] = first_move(false);
  INFO("firmed: '" << firmed << "'; still unsure: '" << unsure << "'");
  CHECK(firmed_tour >= 4);
  CHECK(unsure_tour <= 2);
}

TEST_CASE("control: a teacher turning back at each end of their walk is followed round and along it, from the face alone") {
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3: fence y >= -2.7, x <= 4.7
  const TeacherMotion motion(turn_back_path());
  test::ModelFlight f({}, lab);
  const auto walk = [&](double seconds) {
    for (const double end = f.t + seconds; f.t < end;) {
      f.world->T_world_face = motion.pose(f.t).T_world_head * fusion::flip_about_y();
      f.run(1.0 / 30.0);
    }
  };
  REQUIRE(f.request(find_teacher()).accepted);
  bool following = false;
  for (const double end = f.t + 120; f.t < end && !following;) {
    walk(1.0 / 30.0);
    following = f.stack->status().stage == "3 face-follow";
  }
  REQUIRE(following);
  // Two rounds of the path (2 x 23.5 s): each long leg is walked after a turn back at a corner.
  int went_round = 0, ticks = 0, followed = 0;
  bool was_round = false;
  std::vector<double> error;
  double nearest = 10;
  // Settled first: the face may be found 2 m away with the teacher walking off (the drone reaches
  // eye height early and may find the face on a leg, not at its end), and closing that gap is the
  // approach, not the follow.
  const auto depth_error = [&] {
    const Eigen::Vector3d p =
        ((f.world->drone.pose() * T_body_cam_front()).inverse() * motion.pose(f.t).T_world_head).translation();
    return std::abs(p.z() - 1.0);
  };
  walk(3.0);
  for (const double end = f.t + 10.0; f.t < end && depth_error() > 0.15;) walk(1.0 / 30.0);
  for (const double end = f.t + 2 * motion.cycle_s(); f.t < end;) {
    walk(1.0 / 30.0);
    const bool round = f.stack->status().stage.find("going round") != std::string::npos;
    went_round += round && !was_round;
    was_round = round;
    ++ticks;
    const bool following_face = f.stack->status().stage == "3 face-follow";
    followed += following_face;
    const TeacherPose teacher = motion.pose(f.t);
    const Eigen::Vector3d p =
        ((f.world->drone.pose() * T_body_cam_front()).inverse() * teacher.T_world_head).translation();
    nearest = std::min(nearest, (f.world->drone.pose().translation() - teacher.T_world_head.translation()).head<2>().norm());
    // Followed along a long leg (not the 0.5 m ones, where the standoff would be behind the fence or
    // round them).
    const Eigen::Vector2d along(std::cos(teacher.heading_rad), std::sin(teacher.heading_rad));
    if (following_face && teacher.walking && std::abs(along.x()) > 0.9) error.push_back(p.z() - 1.0);
  }
  double sum = 0;
  for (double e : error) sum += e * e;
  const double rms = std::sqrt(sum / static_cast<double>(error.size()));
  const double followed_fraction = static_cast<double>(followed) / ticks;
  INFO("went round " << went_round << " times, face followed " << followed_fraction << " of the time, distance error RMS "
                     << rms << " m over " << error.size() << " ticks followed along a long leg, nearest " << nearest << " m");
  // The face alone shows nothing of a teacher who turned their back: each turn back loses it for a
  // while, and it is found again going round or searching.
  CHECK(went_round >= 1);
  CHECK(followed_fraction > 0.5);
  CHECK(rms < 0.3);
  CHECK(nearest > 0.51);  // never into the teacher (hull 0.26 m + body 0.25 m)
}

TEST_CASE("control: a face lost at a corner: the drone keeps clear of a teacher who sets off towards it unseen") {
  // The face lost just as the teacher sets off on the next leg towards the drone, and out of the
  // detector's reach (head sway) while they walk. Wrong: the drone holds and the teacher walks into it.
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3
  const TeacherMotion motion(turn_back_path());
  test::ModelFlight f({}, lab);
  const auto tick = [&] {
    f.world->T_world_face = motion.pose(f.t).T_world_head * fusion::flip_about_y();
    f.run(1.0 / 30.0);
  };
  REQUIRE(f.request(find_teacher()).accepted);
  bool following = false;
  for (const double end = f.t + 120; f.t < end && !following;) {
    tick();
    following = f.stack->status().stage == "3 face-follow";
  }
  REQUIRE(following);
  for (const double end = f.t + 5.0; f.t < end;) tick();
  const auto on_long_leg = [&](const TeacherPose& p) { return p.walking && std::abs(std::cos(p.heading_rad)) > 0.9; };
  // Wait for a short leg, then for the long leg after it; hide the face 0.3 s into it (the head swayed
  // away as they set off) until they have walked 2.5 s of it.
  for (const double end = f.t + motion.cycle_s(); f.t < end && !(motion.pose(f.t).walking && !on_long_leg(motion.pose(f.t)));) tick();
  REQUIRE_FALSE(on_long_leg(motion.pose(f.t)));
  double nearest = 10;
  Seconds long_leg_since = -1;
  const double hidden_until_walked_s = 2.5;
  for (const double end = f.t + 30.0; f.t < end;) {
    tick();
    const TeacherPose p = motion.pose(f.t);
    if (long_leg_since < 0 && on_long_leg(p)) long_leg_since = f.t;
    if (long_leg_since >= 0) f.world->face_visible = f.t - long_leg_since < 0.3 || f.t - long_leg_since > hidden_until_walked_s;
    nearest = std::min(nearest, (f.world->drone.pose().translation() - p.T_world_head.translation()).head<2>().norm());
    if (long_leg_since >= 0 && f.t - long_leg_since > hidden_until_walked_s + 3.0) break;
  }
  INFO("nearest " << nearest << " m, stage " << f.stack->status().stage);
  REQUIRE(long_leg_since > 0);
  CHECK(nearest > 0.6);  // hull 0.26 m + body 0.25 m, with margin
  // In view again, the face is found again and followed.
  bool found_again = f.stack->status().stage == "3 face-follow";
  for (const double end = f.t + 30.0; f.t < end && !found_again;) {
    tick();
    found_again = f.stack->status().stage == "3 face-follow";
  }
  CHECK(found_again);
}

TEST_CASE("control: a lost face is gone round clear of the walls by the estimate's uncertainty and drift") {
  // Going round a lost face is flown blind, on an estimate that may be tenths of a metre off (navdata
  // odometry without SLAM). Wrong: the standoff swept round at 0.8 m/s to the geofence's edge, and the
  // drone, 0.2 m off its estimate and carried on by the set point's velocity, hit the wall.
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3; geofence margin 0.3
  test::ModelFlight f({}, lab);
  // The teacher stands 1.4 m from the south wall facing north; the drone finds and follows them.
  const double heading = std::numbers::pi / 2;
  Eigen::Isometry3d T_world_head = Eigen::Isometry3d::Identity();
  T_world_head.linear().col(0) = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
  T_world_head.linear().col(1) = Eigen::Vector3d::UnitZ();
  T_world_head.linear().col(2) = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
  T_world_head.translation() = Eigen::Vector3d(1.0, -1.6, 1.6);
  f.world->T_world_face = T_world_head * fusion::flip_about_y();
  start_following(f);
  f.run(5.0);
  // The face lost (they turned away) and the estimate unsure: 0.15 m at 1 sigma, and dead reckoning
  // may have drifted 0.2 m.
  f.world->face_visible = false;
  f.world->position_sigma_m = 0.15;
  f.world->drift_bound_m = 0.2;
  const double inset = 0.3 + 2 * 0.15 + 0.2;
  double nearest_wall = 10, nearest_wall_set_point = 10;
  bool went_round = false;
  for (const double end = f.t + 20.0; f.t < end;) {
    f.run(0.1);
    const control::FlightStatus s = f.stack->status();
    if (s.stage.find("going round") == std::string::npos || !s.desired) continue;
    went_round = true;
    const Eigen::Vector3d p = s.desired->head<3>();
    nearest_wall_set_point = std::min({nearest_wall_set_point, p.x() + 1.0, 5.0 - p.x(), p.y() + 3.0, 3.0 - p.y()});
    const Eigen::Vector3d d = f.world->drone.p;
    nearest_wall = std::min({nearest_wall, d.x() + 1.0, 5.0 - d.x(), d.y() + 3.0, 3.0 - d.y()});
  }
  INFO("set point nearest the walls " << nearest_wall_set_point << " m; the drone " << nearest_wall << " m");
  REQUIRE(went_round);
  CHECK(nearest_wall_set_point > inset - 1e-6);
  // Braking before the bound: 0.10-0.18 m past it (the xy integral, at the bound where the set point
  // stands still, adds the rest); 0.33 m without.
  CHECK(nearest_wall > inset - 0.2);
}

TEST_CASE("control: a lost face is gone round over the teacher's head, and the search flies over it to its viewpoints") {
  // Blind, the drone cannot know where a teacher who walked on from the lost place went: going round
  // that place at face height, it flew into a teacher standing on the circle; following the lost
  // face's motion at face height, into a teacher who had turned and walked at it; and coming down to
  // sweep where it lost them, into a teacher walking past unseen (randomized tuning seed 1002). Over
  // their head it cannot; it comes down to face height only to sweep at the search's viewpoints, and
  // to follow a face it sees.
  fusion::LabGeometry lab = model_lab();
  test::ModelFlight f({}, lab);
  const double blind_z = control::MissionParameters{}.face_blind_altitude_m;
  REQUIRE(blind_z > 1.8 + 0.1);  // the default clears a standing adult's head (eyes at ~1.65 m)
  start_following(f);
  f.run(5.0);
  CHECK(std::abs(f.world->drone.p.z() - 1.6) < 0.15);  // following at face height
  f.world->face_visible = false;
  bool coasted = false, went_round = false, swept_where_lost = false, repositioned = false, swept_at_viewpoint = false;
  double highest_coast_set_point = 0, highest_going_round = 0, lowest_set_point_moving = 10;
  double lowest_sweeping_where_lost = 10, viewpoint_sweep_set_point_z = 0;
  int viewpoint_sweep_ticks = 0;
  for (const double end = f.t + 60.0; f.t < end && viewpoint_sweep_ticks < 10;) {
    f.run(0.1);
    const control::FlightStatus s = f.stack->status();
    if (!s.desired) continue;
    const double set_z = (*s.desired)(2);
    if (s.stage.find("following its motion") != std::string::npos) {
      coasted = true;
      highest_coast_set_point = std::max(highest_coast_set_point, set_z);
    } else if (s.stage.find("going round") != std::string::npos) {
      went_round = true;
      highest_going_round = std::max(highest_going_round, f.world->drone.p.z());
      lowest_set_point_moving = std::min(lowest_set_point_moving, set_z);
    } else if (s.stage.find("yaw sweep over the teacher's head") != std::string::npos) {
      swept_where_lost = true;
      lowest_sweeping_where_lost = std::min(lowest_sweeping_where_lost, f.world->drone.p.z());
    } else if (s.stage.find("moving to viewpoint") != std::string::npos) {
      repositioned = true;
      lowest_set_point_moving = std::min(lowest_set_point_moving, set_z);
    } else if (s.stage.find("yaw sweep at viewpoint") != std::string::npos) {
      swept_at_viewpoint = true;
      ++viewpoint_sweep_ticks;
      viewpoint_sweep_set_point_z = set_z;
    }
  }
  INFO("highest set point following the lost face's motion " << highest_coast_set_point << " m; drone's highest going round "
                                                               << highest_going_round << " m; lowest set point moving blind " << lowest_set_point_moving
                                                               << " m; drone's lowest sweeping where the face was lost " << lowest_sweeping_where_lost
                                                               << " m; sweep at a viewpoint at " << viewpoint_sweep_set_point_z << " m");
  REQUIRE(coasted);
  REQUIRE(went_round);
  REQUIRE(swept_where_lost);
  REQUIRE(repositioned);
  REQUIRE(swept_at_viewpoint);
  CHECK(highest_coast_set_point > blind_z - 0.1);
  CHECK(highest_going_round > blind_z - 0.1);
  CHECK(lowest_set_point_moving > blind_z - 0.1);  // a step-limited set point starts a little below it
  CHECK(lowest_sweeping_where_lost > blind_z - 0.1);
  CHECK(viewpoint_sweep_set_point_z == Approx(1.6));
}

TEST_CASE("control: a teacher seen by the head alone is followed from farther out, over the head, on the same side") {
  // The teacher turns their back and walks away along +x; only the head is followed (the front end's
  // position_only). Wrong: the drone swings round to their front across their path, or follows at
  // face height and follow distance on a distance read from the head's patch, which drifts.
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3
  test::ModelFlight f({}, lab);
  f.world->T_world_face = test::facing_base({1.5, 0.0, 1.6});
  REQUIRE(f.request(find_teacher()).accepted);
  bool following = false;
  for (const double end = f.t + 120; f.t < end && !following;) {
    f.run(1.0 / 30.0);
    following = f.stack->status().stage == "3 face-follow";
  }
  REQUIRE(following);
  for (const double end = f.t + 8.0; f.t < end;) f.run(1.0 / 30.0);
  const Eigen::Vector3d start_face = f.world->T_world_face.translation();
  const Eigen::Vector3d drone_start = f.world->drone.pose().translation();
  const Eigen::Vector3d side = (drone_start - start_face).normalized();
  // Turned away and walking away from the drone at 0.4 m/s for 5 s, seen by the head only.
  turn_away_seen_by_the_head(*f.world);
  const Eigen::Vector3d walk = -0.4 * Eigen::Vector3d(side.x(), side.y(), 0.0).normalized();
  double nearest = 10, stage_face_follow = 0, ticks = 0;
  for (const double end = f.t + 5.0; f.t < end;) {
    f.world->T_world_face.translation() += walk / 30.0;
    f.run(1.0 / 30.0);
    const Eigen::Vector3d d = f.world->drone.pose().translation() - f.world->T_world_face.translation();
    nearest = std::min(nearest, d.head<2>().norm());
    stage_face_follow += f.stack->status().stage == "3 face-follow";
    ++ticks;
  }
  const Eigen::Vector3d d = f.world->drone.pose().translation() - f.world->T_world_face.translation();
  INFO("nearest " << nearest << " m, at the end " << d.transpose() << ", stage " << f.stack->status().stage);
  CHECK(stage_face_follow / ticks > 0.95);           // still following: the teacher is seen
  CHECK(nearest > 0.9);
  CHECK(d.head<2>().norm() == Approx(1.5).margin(0.25));  // follow distance + 0.5 m
  CHECK(d.head<2>().normalized().dot(side.head<2>().normalized()) > 0.9);  // the side it was on
  CHECK(f.world->drone.pose().translation().z() > 1.85);  // over the head (blind altitude 2 m)
}

TEST_CASE("control: a teacher standing in the middle of the room on a long dead reckoning is not flown into") {
  // After two minutes of dead reckoning the drift bound is over 2 m: the follow's fence, inset by it,
  // shrinks to a box half a metre across in the middle of the room (each axis keeps 0.1 of its
  // extent), and a teacher standing there has every set point of that box within 0.4 m of their face.
  // Wrong: the standoff clamped into the box, the drone flown into the teacher (randomized tuning seeds
  // 1001 and 1003: the drift bound 2.4-3.8 m, the set point 0.2 m behind the face, and 0.3 m in front
  // of a teacher walking at the drone). The face is measured from the drone's camera, so its distance
  // from the drone holds whatever the estimate's drift.
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3; geofence margin 0.3
  test::ModelFlight f({}, lab);
  f.world->T_world_face = test::facing_base({2.0, 0.1, 1.6});  // the room's middle, looking west
  start_following(f);
  f.run(5.0);
  f.world->position_sigma_m = 0.39;
  f.world->altitude_sigma_m = 0.03;
  f.world->drift_bound_m = 2.36;
  const double walk_mps = GENERATE(0.0, 0.5);  // standing, or walking at the drone for 2 s (tuning seed 1003)
  double nearest = 10, following = 0, ticks = 0;
  for (const double end = f.t + 10.0; f.t < end;) {
    if (f.t < end - 8.0) f.world->T_world_face.translation().x() -= walk_mps / 30.0;
    f.run(1.0 / 30.0);
    nearest = std::min(nearest, (f.world->drone.pose().translation() - f.world->T_world_face.translation()).head<2>().norm());
    following += f.stack->status().stage == "3 face-follow";
    ++ticks;
  }
  INFO("walking at " << walk_mps << " m/s: nearest " << nearest << " m; following " << following / ticks << " of the time; drone at "
                  << f.world->drone.pose().translation().transpose());
  CHECK(nearest > 0.6);  // the hull's 0.26 m and a body's 0.25 m touch at 0.51 m; standing, 0.12 m without the rule
  CHECK(following / ticks > 0.95);
}

TEST_CASE("control: a followed head whose patch reads it far is followed at the distance its height gives") {
  // The teacher stands turned away; only the head is followed, and its patch's scale has drifted: it
  // reads the head 1.8 times as far as it is (tuning seed 1002 read 1.3 m at 0.3-0.6 m). The height
  // the posed faces were seen at and the ray down to the head from over it give the distance. Wrong:
  // the drone closes in to 0.8 m where it means to keep 1.5 m.
  fusion::LabGeometry lab = model_lab();
  test::ModelFlight f({}, lab);
  f.world->T_world_face = test::facing_base({1.5, 0.0, 1.6});
  start_following(f);
  f.run(8.0);
  turn_away_seen_by_the_head(*f.world);
  double nearest = 10, farthest_late = 0;
  const double drift_from = f.t;
  for (const double end = f.t + 12.0; f.t < end;) {
    // The patch's scale drifts over the first 4 s (the template adapting as the head turns).
    f.world->head_range_scale = 1.0 + 0.8 * std::min(1.0, (f.t - drift_from) / 4.0);
    f.run(1.0 / 30.0);
    const double d = (f.world->drone.pose().translation() - f.world->T_world_face.translation()).head<2>().norm();
    nearest = std::min(nearest, d);
    if (end - f.t < 4.0) farthest_late = std::max(farthest_late, d);
  }
  const double d = (f.world->drone.pose().translation() - f.world->T_world_face.translation()).head<2>().norm();
  INFO("distance at the end " << d << " m, nearest " << nearest << " m, farthest over the last 4 s " << farthest_late
                              << " m, stage " << f.stack->status().stage);
  CHECK(f.stack->status().stage == "3 face-follow");
  CHECK(d == Approx(1.5).margin(0.25));  // follow distance + 0.5 m, the head alone
  CHECK(nearest > 0.85);  // it followed at 1 m before
  CHECK(farthest_late < 1.8);
}

TEST_CASE("control: a teacher who walks at the drone near a wall: the drone stops short of the wall") {
  // The drone backs away from a teacher walking at it, towards the south wall; the teacher stops 0.6 m
  // from the wall and the face is lost on the way (turned out of the detector's reach). Wrong: the
  // standoff was held at the follow's bound, turned round the teacher, but fed forward at the
  // teacher's speed: the drone flew on past its set point at 1 m/s, through the wall (the soak's
  // crash into wall_ymin).
  const double walk_mps = GENERATE(0.4, 0.7);
  fusion::LabGeometry lab = model_lab();  // room x -1..5, y -3..3; geofence margin 0.3
  test::ModelFlight f({}, lab);
  const double heading = -std::numbers::pi / 2;  // looking south, at the drone
  const auto face_at = [&](double y) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear().col(0) = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
    T.linear().col(1) = Eigen::Vector3d::UnitZ();
    T.linear().col(2) = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    T.translation() = Eigen::Vector3d(1.0, y, 1.6);
    return T * fusion::flip_about_y();
  };
  double y = 1.0;
  f.world->T_world_face = face_at(y);
  start_following(f);
  f.run(5.0);
  const double lost_at_y = -1.8, stop_at_y = -2.4;
  double nearest_wall = 10;
  bool lost = false;
  for (const double end = f.t + 15.0; f.t < end;) {
    y = std::max(stop_at_y, y - walk_mps / 30.0);
    f.world->T_world_face = face_at(y);
    lost = lost || y <= lost_at_y;
    f.world->face_visible = !lost;
    f.run(1.0 / 30.0);
    const Eigen::Vector3d d = f.world->drone.p;
    nearest_wall = std::min({nearest_wall, d.x() + 1.0, 5.0 - d.x(), d.y() + 3.0, 3.0 - d.y()});
  }
  INFO("walking at " << walk_mps << " m/s: the drone came " << nearest_wall << " m from a wall");
  REQUIRE(lost);
  // The hull's radius is 0.26 m; the geofence keeps the estimate 0.3 m from the walls. Fed forward
  // at the teacher's speed, the drone reached -0.33 m (through the wall) at 0.7 m/s; now 0.35.
  CHECK(nearest_wall > 0.3);
}

TEST_CASE("control: on a long dead reckoning a head-only teacher is still followed over the head, not at its height") {
  // After a minute of dead reckoning the estimate's horizontal sigma is ~0.4 m, its altitude's (the
  // ultrasound) a few centimetres. Wrong: the fence's top inset by the horizontal sigma, the drone
  // following at 1.8 m, level with the head it passes (randomized seed 9, nominal seed 6: into it).
  fusion::LabGeometry lab = model_lab();
  test::ModelFlight f({}, lab);
  f.world->T_world_face = test::facing_base({1.5, 0.0, 1.6});
  start_following(f);
  f.run(5.0);
  f.world->position_sigma_m = 0.44;
  f.world->altitude_sigma_m = 0.03;
  turn_away_seen_by_the_head(*f.world);
  for (const double end = f.t + 5.0; f.t < end;) f.run(1.0 / 30.0);
  const Eigen::Vector3d drone = f.world->drone.pose().translation(), head = f.world->T_world_face.translation();
  const double below = drone.z() - head.z(), distance = (drone - head).head<2>().norm();
  INFO("stage " << f.stack->status().stage << ", drone at " << drone.transpose() << ": " << below << " m over the face, "
                << distance << " m from it");
  CHECK(f.stack->status().stage == "3 face-follow");
  // Over the head's top (1.42 m, level with the head, with the old clearance), and not so high that
  // the head leaves the bottom of the image (0.39 of the range below the camera's axis).
  CHECK(below > 0.15);
  CHECK(below < 0.39 * distance);
}
