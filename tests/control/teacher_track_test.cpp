#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "control/teacher_track.hpp"
#include "core/frames.hpp"

using namespace labo;
using namespace labo::control;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// A face at `p` looking towards world heading `looking` (control's convention: z into the face).
Eigen::Isometry3d face_at(const Eigen::Vector3d& p, double looking) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d into(-std::cos(looking), -std::sin(looking), 0.0);
  T.linear().col(2) = into;
  T.linear().col(1) = Eigen::Vector3d::UnitZ();
  T.linear().col(0) = Eigen::Vector3d::UnitZ().cross(into);
  T.translation() = p;
  return T;
}
}  // namespace

TEST_CASE("control: a walking teacher's heading is the walking direction, not the swaying head's") {
  control::TeacherTrack track;
  const double walk = 0.3;  // rad: walking a little left of +x
  const Eigen::Vector3d v(0.4 * std::cos(walk), 0.4 * std::sin(walk), 0.0);
  double worst = 0;
  for (int k = 0; k <= 300; ++k) {  // 10 s at 30 Hz, the head swaying +-35 deg over 7 s
    const double t = k / 30.0;
    const Eigen::Isometry3d face = face_at(Eigen::Vector3d(1, 2, 1.65) + v * t, walk + 35 * kDeg * std::sin(2 * std::numbers::pi * t / 7));
    if (k == 0) track.reset(face, t);
    else track.update(face, t);
    if (t > 3) worst = std::max(worst, std::abs(wrap_angle(track.heading() - walk)));
  }
  CHECK(track.walking());
  CHECK(worst < 3 * kDeg);
  CHECK((track.velocity() - v).norm() < 0.05);
  CHECK(std::abs(facing_heading(track.T_world_upright_face(track.heading())) - track.heading()) < 1e-9);
}

TEST_CASE("control: a teacher turning on the spot is followed by where the face looks") {
  control::TeacherTrack track;
  const Eigen::Vector3d p(4.2, -2.4, 1.65);
  track.reset(face_at(p, 0.0), 0.0);
  for (int k = 1; k <= 90; ++k) track.update(face_at(p, std::numbers::pi / 2 * k / 90.0), k / 30.0);  // 90 deg in 3 s
  for (int k = 91; k <= 150; ++k) track.update(face_at(p, std::numbers::pi / 2), k / 30.0);         // then still
  CHECK_FALSE(track.walking());
  CHECK(std::abs(track.heading() - std::numbers::pi / 2) < 5 * kDeg);
  CHECK((track.position() - p).norm() < 1e-6);
}

TEST_CASE("control: a lost teacher coasts along the last motion, a route prediction places them") {
  control::TeacherTrack track;
  const Eigen::Vector3d v(0.5, 0.0, 0.0);
  for (int k = 0; k <= 90; ++k) {
    const Eigen::Isometry3d face = face_at(Eigen::Vector3d(0, 0, 1.6) + v * (k / 30.0), 0.0);
    if (k == 0) track.reset(face, 0.0);
    else track.update(face, k / 30.0);
  }
  const Eigen::Vector3d before = track.position();
  track.coast(0.5);
  CHECK((track.position() - before - 0.5 * track.velocity()).norm() < 1e-9);
  CHECK(track.position().x() > before.x() + 0.2);
  track.place({2.0, -1.0}, std::numbers::pi);
  CHECK(track.position().head<2>().isApprox(Eigen::Vector2d(2.0, -1.0)));
  CHECK(track.position().z() == Approx(1.6).margin(0.01));  // the face's height is kept
  CHECK_FALSE(track.walking());
  CHECK(std::abs(std::abs(track.heading()) - std::numbers::pi) < 1e-9);
}

TEST_CASE("control: a sustained walk is remembered after the teacher stops, the pose's jitter is no walk") {
  control::TeacherTrack track;
  const Eigen::Vector3d start(4.2, -2.4, 1.65);
  track.reset(face_at(start, std::numbers::pi / 2), 0.0);
  // Standing, the face's place jittering by 3 cm frame to frame (seeded): no sustained walk.
  std::uint32_t state = 12345;
  const auto jitter = [&] {
    state = state * 1664525u + 1013904223u;
    return 0.03 * (static_cast<double>(state >> 8) / double(1u << 24) - 0.5) * 2.0;
  };
  int k = 1;
  for (; k <= 90; ++k) track.update(face_at(start + Eigen::Vector3d(jitter(), jitter(), 0), std::numbers::pi / 2), k / 30.0);
  CHECK_FALSE(track.last_walk().seen);
  // 1.25 s along +y at 0.4 m/s (the short leg), then standing at its end.
  const Seconds walk_start = k / 30.0;
  for (; k <= 90 + 38; ++k) track.update(face_at(start + Eigen::Vector3d(0, 0.4 * (k / 30.0 - walk_start), 0), std::numbers::pi / 2), k / 30.0);
  const Eigen::Vector3d end = track.position();
  for (; k <= 90 + 38 + 30; ++k) track.update(face_at(end, std::numbers::pi / 2), k / 30.0);
  const control::TeacherTrack::WalkSpell& w = track.last_walk();
  REQUIRE(w.seen);
  CHECK(w.direction.y() > 0.95);
  CHECK(w.to > w.from + control::TeacherTrack::kSustainedWalkS);
  CHECK(w.to < (90 + 38 + 30) / 30.0 - 0.3);  // ended when they stopped, not now
  CHECK_FALSE(track.walking());
}

TEST_CASE("control: a face taken up again after a route prediction keeps the predicted walk") {
  control::TeacherTrack track;
  track.reset(face_at({1.2, -2.4, 1.65}, 0.0), 0.0);
  // Predicted walking the leg along +x at 0.4 m/s; the face found again 0.5 m along it.
  track.place({1.6, -2.4}, 0.0, {0.4, 0.0});
  track.resume(face_at({1.7, -2.4, 1.65}, 0.3), 2.0);
  CHECK(track.walking());
  CHECK((track.velocity() - Eigen::Vector3d(0.4, 0, 0)).norm() < 1e-9);
  CHECK(track.position().x() == Approx(1.7));
  // Predicted standing: taken up standing, the heading held until they walk.
  track.place({1.2, -2.4}, 0.0);
  track.resume(face_at({1.2, -2.4, 1.65}, 0.8), 3.0);
  track.update(face_at({1.2, -2.4, 1.65}, 0.8), 3.0 + 1.0 / 30.0);
  CHECK_FALSE(track.walking());
  CHECK(std::abs(track.heading()) < 1e-9);
}
