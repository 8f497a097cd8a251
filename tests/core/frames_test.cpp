#include <catch2/catch.hpp>
#include <numbers>
#include <random>

#include "core/frames.hpp"

using namespace labo;

namespace {
Eigen::Isometry3d random_pose(std::mt19937& rng) {
  std::uniform_real_distribution<double> a(-3.0, 3.0), t(-5.0, 5.0), p(-1.4, 1.4);
  return make_pose({t(rng), t(rng), t(rng)}, a(rng), p(rng), a(rng));
}
}  // namespace

TEST_CASE("frames: composition chains T_a_b * T_b_c and checks the frames") {
  std::mt19937 rng(7);
  const FramedTransform T_world_body(FrameId::world(), FrameId::body(), random_pose(rng));
  const FramedTransform T_body_cam(FrameId::body(), FrameId::cam_front(), T_body_cam_front());
  const FramedTransform T_cam_obj(FrameId::cam_front(), FrameId::object(2), random_pose(rng));
  const FramedTransform T_world_obj = T_world_body * T_body_cam * T_cam_obj;
  CHECK(T_world_obj.to() == FrameId::world());
  CHECK(T_world_obj.from() == FrameId::object(2));
  const Eigen::Vector3d p_obj(0.1, 0.2, 0.0);
  const Eigen::Vector3d direct = T_world_body.apply(T_body_cam.apply(T_cam_obj.apply(p_obj)));
  CHECK((T_world_obj.apply(p_obj) - direct).norm() < 1e-12);
  CHECK_THROWS_WITH(T_world_body * T_cam_obj,
                    Catch::Contains("cannot compose T_world_body with T_cam_front_object:2"));
}

TEST_CASE("frames: inversion gives the identity and swaps the frames") {
  std::mt19937 rng(3);
  for (int i = 0; i < 100; ++i) {
    const FramedTransform T(FrameId::world(), FrameId::map(), random_pose(rng));
    const FramedTransform I = T * T.inverse();
    CHECK(I.to() == FrameId::world());
    CHECK(I.from() == FrameId::world());
    CHECK(I.T().matrix().isIdentity(1e-9));
  }
}

TEST_CASE("frames: yaw-pitch-roll round trip") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> a(-3.1, 3.1), p(-1.5, 1.5);
  for (int i = 0; i < 200; ++i) {
    const double yaw = a(rng), pitch = p(rng), roll = a(rng);
    const Eigen::Vector3d ypr = ypr_from_rotation(rotation_from_ypr(yaw, pitch, roll));
    CHECK(ypr.x() == Approx(yaw).margin(1e-9));
    CHECK(ypr.y() == Approx(pitch).margin(1e-9));
    CHECK(ypr.z() == Approx(roll).margin(1e-9));
  }
}

TEST_CASE("frames: angles wrap to the half-open range from -pi to pi") {
  CHECK(wrap_angle(3 * std::numbers::pi) == Approx(-std::numbers::pi));
  CHECK(wrap_angle(-0.5) == Approx(-0.5));
  CHECK(wrap_angle(2 * std::numbers::pi + 0.25) == Approx(0.25));
  CHECK(wrap_angle(-7.0) == Approx(-7.0 + 2 * std::numbers::pi));
}

TEST_CASE("frames: the front camera looks forward, the bottom camera looks down") {
  const Eigen::Isometry3d front = T_body_cam_front();
  CHECK((front.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm() < 1e-12);
  CHECK((front.linear() * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitZ()).norm() < 1e-12);  // image down = body down
  CHECK(front.linear().determinant() == Approx(1.0));
  const Eigen::Isometry3d bottom = T_body_cam_bottom();
  CHECK((bottom.linear() * Eigen::Vector3d::UnitZ() + Eigen::Vector3d::UnitZ()).norm() < 1e-12);
  CHECK((bottom.linear() * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitX()).norm() < 1e-12);  // image top = front
  CHECK(bottom.linear().determinant() == Approx(1.0));
}
