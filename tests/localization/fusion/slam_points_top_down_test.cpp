// The SLAM map seen from above (localization/fusion/slam_points_top_down.hpp): placed in the world,
// one point per grid cell, inside the room, bounded; snapshots that readers hold are never written.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <set>

#include "localization/fusion/slam_points_top_down.hpp"

using namespace labo::fusion;

namespace {

const Eigen::AlignedBox3d kRoom(Eigen::Vector3d(-1.5, -3, 0), Eigen::Vector3d(6.5, 3, 3));

std::vector<Eigen::Vector3d> grid_of_points(double step_m, double x0, double x1, double y0, double y1, double z) {
  std::vector<Eigen::Vector3d> points;
  for (double x = x0; x < x1; x += step_m)
    for (double y = y0; y < y1; y += step_m) points.emplace_back(x, y, z);
  return points;
}

}  // namespace

TEST_CASE("SLAM points from above: one point per occupied cell, each a point of the map") {
  // 2 cm spacing over 1 m x 0.5 m: 50 x 25 = 1250 points in 10 x 5 cells of 10 cm.
  const auto points = grid_of_points(0.02, 0.001, 1.0, 0.001, 0.5, 1.0);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;
  std::vector<Eigen::Vector2f> out;
  decimate_top_down(points, kRoom, {.cell_m = 0.10, .max_points = 1500}, cells, out);
  // The kept box starts 0.3 m outside the room: cell edges at x = -1.8 + k * 0.1 and y = -3.3 + k * 0.1,
  // 1 mm from the points nearest to them.
  CHECK(out.size() == 10 * 5);
  std::set<std::pair<int, int>> seen;
  for (const Eigen::Vector2f& p : out) {
    const auto cell = std::pair{static_cast<int>(std::floor((p.x() + 1.8) / 0.1)), static_cast<int>(std::floor((p.y() + 3.3) / 0.1))};
    CHECK(seen.insert(cell).second);  // no two in one cell
    CHECK(p.x() >= 0.0f);
    CHECK(p.x() < 1.0f);
  }
}

TEST_CASE("SLAM points from above: at most max_points, spread over the occupied cells") {
  const auto points = grid_of_points(0.05, -1.4, 6.4, -2.9, 2.9, 1.2);  // the whole room, every 5 cm
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;
  std::vector<Eigen::Vector2f> out;
  decimate_top_down(points, kRoom, {.cell_m = 0.10, .max_points = 400}, cells, out);
  CHECK(out.size() <= 400);
  CHECK(out.size() >= 300);
  // Spread: both ends of the room are represented, not only the first cells in order.
  float min_x = 1e9f, max_x = -1e9f;
  for (const auto& p : out) {
    min_x = std::min(min_x, p.x());
    max_x = std::max(max_x, p.x());
  }
  CHECK(min_x < -1.0f);
  CHECK(max_x > 6.0f);
}

TEST_CASE("SLAM points from above: points far outside the room and non-finite points are dropped") {
  const std::vector<Eigen::Vector3d> points = {{1, 1, 1}, {30, 1, 1}, {1, -12, 1}, {1, 1, 40}, {std::nan(""), 0, 0},
                                               {6.7, 0, 1}};  // 0.2 m beyond the wall: kept (margin 0.3 m)
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;
  std::vector<Eigen::Vector2f> out;
  decimate_top_down(points, kRoom, {}, cells, out);
  REQUIRE(out.size() == 2);
}

TEST_CASE("SLAM points from above: the map is placed in the world with the estimator's similarity") {
  SlamPointsTopDown top_down(kRoom);
  // A map whose unit is 2 m, turned 90 degrees about z and moved 1 m along x.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  REQUIRE(top_down.update({{1.0, 0.0, 0.5}}, R, 2.0, Eigen::Vector3d(1, 0, 0), 7));
  const auto snapshot = top_down.latest();
  REQUIRE(snapshot);
  REQUIRE(snapshot->xy_world.size() == 1);
  CHECK(snapshot->xy_world[0].x() == Approx(1.0).margin(1e-6));
  CHECK(snapshot->xy_world[0].y() == Approx(2.0).margin(1e-6));
  CHECK(snapshot->map_id == 7);
  CHECK(snapshot->revision == 1);
}

TEST_CASE("SLAM points from above: a snapshot a reader holds is never rewritten, and with all held the refresh waits") {
  SlamPointsTopDown top_down(kRoom);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  REQUIRE(top_down.update({{1, 1, 1}}, I, 1.0, Eigen::Vector3d::Zero(), 1));
  const auto first = top_down.latest();  // a reader keeps the first
  REQUIRE(top_down.update({{2, 2, 1}}, I, 1.0, Eigen::Vector3d::Zero(), 1));
  const auto second = top_down.latest();
  REQUIRE(top_down.update({{3, 3, 1}}, I, 1.0, Eigen::Vector3d::Zero(), 1));
  const auto third = top_down.latest();
  CHECK(first->xy_world[0].x() == 1.0f);  // untouched while held
  CHECK(second->xy_world[0].x() == 2.0f);
  // Every snapshot of the pool is held: nothing is overwritten, the latest stays.
  CHECK_FALSE(top_down.update({{4, 4, 1}}, I, 1.0, Eigen::Vector3d::Zero(), 1));
  CHECK(top_down.latest() == third);
  CHECK(first->xy_world[0].x() == 1.0f);
}
