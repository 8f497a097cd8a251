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
Eigen::Isometry3d face_at(const Eigen::Vector3d& p, double looking) { return upright_face_pose(p, looking); }
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
  // A face seen standing cannot tell a glance from a turn until it has lasted longer than a glance:
  // the turn is followed at once to within the sway's band (0.4 rad), and the rest slowly.
  control::TeacherTrack track;
  const Eigen::Vector3d p(4.2, -2.4, 1.65);
  track.reset(face_at(p, 0.0), 0.0);
  for (int k = 1; k <= 90; ++k) track.update(face_at(p, std::numbers::pi / 2 * k / 90.0), k / 30.0);  // 90 deg in 3 s
  for (int k = 91; k <= 150; ++k) track.update(face_at(p, std::numbers::pi / 2), k / 30.0);         // then still 2 s
  CHECK_FALSE(track.walking());
  CHECK(std::abs(track.heading() - std::numbers::pi / 2) < 0.4);
  for (int k = 151; k <= 600; ++k) track.update(face_at(p, std::numbers::pi / 2), k / 30.0);        // and 15 s more
  CHECK(std::abs(track.heading() - std::numbers::pi / 2) < 5 * kDeg);
  CHECK((track.position() - p).norm() < 1e-6);
}

TEST_CASE("control: a standing teacher's swaying head does not swing the heading") {
  // Standing, the head sways +-35 degrees over 7 s about where the body faces: followed, the drone
  // swings 0.6 m sideways at 1 m. The heading stays within half the sway (the part of it beyond
  // the band is followed, as a turn would be).
  control::TeacherTrack track;
  const Eigen::Vector3d p(2.0, -1.0, 1.65);
  const double body = 0.5;
  double worst = 0;
  for (int k = 0; k <= 600; ++k) {
    const double t = k / 30.0;
    const Eigen::Isometry3d face = face_at(p, body + 35 * kDeg * std::sin(2 * std::numbers::pi * t / 7));
    if (k == 0) track.reset(face, t);
    else track.update(face, t);
    if (t > 7) worst = std::max(worst, std::abs(wrap_angle(track.heading() - body)));
  }
  INFO("worst heading error after the first sway " << worst / kDeg << " deg");
  CHECK_FALSE(track.walking());
  CHECK(worst < 17.5 * kDeg);
}

TEST_CASE("control: a lost teacher coasts along the last motion, then stands") {
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
  track.stop();
  const Eigen::Vector3d stopped = track.position();
  track.coast(1.0);
  CHECK_FALSE(track.walking());
  CHECK((track.position() - stopped).norm() < 1e-12);
}

TEST_CASE("control: the teacher's walking speed is measured from the faces, whatever it is") {
  // Nothing tells the track how fast the teacher walks: 0.3 and 0.7 m/s (the simulated teacher's
  // range), with the face's place jittering 2 cm frame to frame (seeded), are both measured within
  // 0.05 m/s after 2 s; standing with the same jitter is no walk.
  for (const double speed : {0.0, 0.3, 0.7}) {
    control::TeacherTrack track;
    std::uint32_t state = 12345;
    const auto jitter = [&] {
      state = state * 1664525u + 1013904223u;
      return 0.02 * (static_cast<double>(state >> 8) / double(1u << 24) - 0.5) * 2.0;
    };
    const Eigen::Vector3d v(0.0, speed, 0.0);
    double worst = 0;
    for (int k = 0; k <= 150; ++k) {
      const double t = k / 30.0;
      const Eigen::Isometry3d face = face_at(Eigen::Vector3d(1 + jitter(), jitter(), 1.6) + v * t, std::numbers::pi / 2);
      if (k == 0) track.reset(face, t);
      else track.update(face, t);
      if (t > 2.0) worst = std::max(worst, (track.velocity() - v).norm());
    }
    INFO("walking at " << speed << " m/s: worst velocity error after 2 s " << worst << " m/s");
    CHECK(worst < (speed == 0.0 ? control::TeacherTrack::kWalkingMps : 0.05));
    CHECK(track.walking() == (speed > 0));
  }
}

TEST_CASE("control: a teacher followed by the head alone keeps their heading and is measured walking away") {
  // Seen face on walking +x, then turned round and walking -x (away from a drone on the +x side) with
  // only the head followed: the place and the walk are measured, the heading is the last face's, so
  // the standoff stays on the drone's side instead of swinging round across the teacher's path.
  control::TeacherTrack track;
  const Eigen::Vector3d p(3, -1.9, 1.65);
  track.reset(face_at(p, 0.0), 0.0);
  for (int k = 1; k <= 30; ++k) track.update(face_at(p, 0.0), k / 30.0);
  const double heading = track.heading();
  const Eigen::Vector3d v(-0.4, 0, 0);
  for (int k = 31; k <= 120; ++k) track.update_position(p + v * ((k - 30) / 30.0), k / 30.0);
  CHECK(track.walking());
  CHECK((track.velocity() - v).norm() < 0.05);
  CHECK((track.position() - (p + v * 3.0)).norm() < 0.05);
  CHECK(track.heading() == Approx(heading).margin(1e-9));
  CHECK(std::abs(track.heading_rate()) < 1e-6);
}
