#include <catch2/catch.hpp>

#include "control/head_range.hpp"

using namespace labo;
using namespace labo::control;

namespace {
// A head 1.2 m ahead of a camera over it, the posed faces having been seen at 1.65 m.
const Eigen::Vector3d kCamera(0, 0, 2.0);
const Eigen::Vector3d kHead(1.2, 0.3, 1.65);

HeadRange learnt(double face_z_m) {
  HeadRange range;
  for (int i = 0; i < 40; ++i) range.learn({0.5 * i, 0, face_z_m + (i % 2 ? 0.02 : -0.02)});
  return range;
}

// The head seen on its true ray at `scale` times its distance.
Eigen::Vector3d read_at(double scale) { return kCamera + scale * (kHead - kCamera); }
}  // namespace

TEST_CASE("control: a followed head's distance comes from the face's height when its patch has drifted") {
  const HeadRange range = learnt(1.65);
  REQUIRE(range.face_height_m() == Approx(1.65).margin(0.005));
  for (const double scale : {0.5, 1.8, 3.0}) {
    const Eigen::Vector3d placed = range.place(kCamera, read_at(scale), 10.0);
    INFO("read at " << scale << " times the distance, placed " << placed.transpose());
    CHECK((placed - kHead).norm() < 0.15);
    // On the ray it was seen on: only the distance changes.
    CHECK((placed - kCamera).normalized().dot((kHead - kCamera).normalized()) == Approx(1.0).margin(1e-9));
  }
  // Just after a posed face the patch's scale is still right, and weighs as much as the height.
  const Eigen::Vector3d fresh = range.place(kCamera, read_at(1.0), 0.0);
  CHECK((fresh - kHead).norm() < 0.01);
}

TEST_CASE("control: a followed head's distance is the patch's where its height says nothing") {
  SECTION("no posed face yet") {
    const HeadRange range;
    CHECK(range.place(kCamera, read_at(1.8), 10.0) == read_at(1.8));
  }
  SECTION("the camera at the face's height: a level ray") {
    const HeadRange range = learnt(2.0);
    CHECK(range.place(kCamera, Eigen::Vector3d(1.5, 0.0, 2.01), 10.0) == Eigen::Vector3d(1.5, 0.0, 2.01));
  }
  SECTION("the head seen below a camera flying under the face's height") {
    // The teacher sat down, or the head is someone else's: the height would place it behind the camera.
    const HeadRange range = learnt(2.3);
    CHECK(range.place(kCamera, read_at(1.0), 10.0) == read_at(1.0));
  }
}
