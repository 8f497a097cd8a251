#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/frames.hpp"
#include "localization/slam/module/loop_closer.hpp"
#include "localization/slam/optimize/pose_graph.hpp"
#include "localization/slam/optimize/sim3_solver.hpp"

using namespace labo;
using namespace labo::slam;

namespace {

// A short loop built directly as a map (no rendering, so the test is quick): 62 keyframes, two per
// second, on a circle in a 6 x 5 m room looking outwards at textured walls; the last keyframes come
// back over the first ones. The map drifted like a monocular map does: keyframe k and the points it
// created are off by a similarity growing along the loop (drift_at), and the returning keyframes made
// their own, drifted, copies of the points the first keyframes mapped.
struct DriftedLoop {
  SlamMap map;
  std::vector<Eigen::Isometry3d> truth;  // T_cam_map of each keyframe, undrifted
  int last = -1;
};

// Drift of keyframe k and of the points it creates: none over the first 10 keyframes (where the loop
// will land), growing along the middle of the loop, and the full 6 deg, 0.15 m, 4 % from keyframe 50
// on (the returning keyframes). Neighbouring keyframes differ by little, as in a real map, and the
// two ends of the loop are each rigid, so the loop measurement itself is exact.
Similarity3 drift_at(int k) {
  const double fraction = std::clamp((k - 10) / 40.0, 0.0, 1.0);
  Similarity3 D;
  D.R = Eigen::AngleAxisd(fraction * 6.0 * M_PI / 180.0, Eigen::Vector3d(0.2, 0.1, 1.0).normalized()).toRotationMatrix();
  D.t = fraction * Eigen::Vector3d(0.15, -0.08, 0.03);
  D.scale = 1.0 + 0.04 * fraction;
  return D;
}

Descriptor random_descriptor(std::mt19937& rng) {
  Descriptor d;
  for (auto& b : d) b = static_cast<std::uint8_t>(rng() & 0xff);
  return d;
}

void build_drifted_loop(const IdealCamera& camera, DriftedLoop& out) {
  std::mt19937 rng(42);
  // Physical points on the four walls (x in [0, 6], y in [0, 5], z in [0, 2.5]).
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> world;
  std::vector<Descriptor> descriptors;
  for (int i = 0; i < 2400; ++i) {
    const int wall = i % 4;
    const double a = u(rng), z = 2.5 * u(rng);
    const Eigen::Vector3d p = wall == 0 ? Eigen::Vector3d(6 * a, 0, z)
                              : wall == 1 ? Eigen::Vector3d(6 * a, 5, z)
                              : wall == 2 ? Eigen::Vector3d(0, 5 * a, z)
                                          : Eigen::Vector3d(6, 5 * a, z);
    world.push_back(p);
    descriptors.push_back(random_descriptor(rng));
  }
  const int keyframes = 62, loop_length = 56;  // keyframes 56..61 revisit 0..5
  std::vector<PointId> point_of_world(world.size(), kNoPoint);
  std::normal_distribution<double> pixel_noise(0.0, 0.3);
  for (int k = 0; k < keyframes; ++k) {
    const double phi = 2 * M_PI * k / loop_length;
    const Eigen::Isometry3d T_world_cam =
        make_pose(Eigen::Vector3d(3 + 1.0 * std::cos(phi), 2.5 + 0.8 * std::sin(phi), 1.2), phi) * T_body_cam_front();
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    out.truth.push_back(T_cam_world);
    const Similarity3 D = drift_at(k);
    Keyframe kf;
    kf.t = 0.5 * k;
    kf.T_cam_map = (Similarity3::from_rigid(T_cam_world) * D.inverse()).rigid_pose();
    cv::Mat small = cv::Mat::zeros(23, 40, CV_32F);
    std::vector<std::size_t> seen;
    for (std::size_t i = 0; i < world.size(); ++i) {
      const Eigen::Vector3d pc = T_cam_world * world[i];
      // Only the middle of the view (+-20 deg) is matched: points are shared by a few neighbouring
      // keyframes, so that each stretch of the map is consistent with the keyframes that see it.
      if (pc.z() < 0.3 || std::abs(pc.x()) > 0.36 * pc.z() || !camera.visible(pc, 8.0)) continue;
      const Eigen::Vector2d px = *camera.project(pc);
      Feature f;
      f.px = px + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng));
      f.image_px = f.px.cast<float>();
      f.level = 0;
      Descriptor d = descriptors[i];
      d[static_cast<std::size_t>(rng() % 32)] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      kf.frame.features.push_back(f);
      kf.frame.descriptors.push_back(d);
      small.at<float>(std::clamp(static_cast<int>(px.y() / 16), 0, 22), std::clamp(static_cast<int>(px.x() / 16), 0, 39)) += 1.0f;
      seen.push_back(i);
    }
    cv::GaussianBlur(small, small, cv::Size(5, 5), 1.0);
    small -= cv::mean(small)[0];
    kf.small_image = small;
    const int id = out.map.add_keyframe(std::move(kf));
    // Points: created by the first keyframe that sees them; the returning keyframes (after the loop)
    // create their own copies instead of finding the old ones (the drift hid them).
    const bool returning = k >= loop_length;
    for (std::size_t f = 0; f < seen.size(); ++f) {
      const std::size_t i = seen[f];
      const PointId existing = point_of_world[i];
      const MapPoint* p = out.map.point(existing);
      const bool reuse = p && (!returning || p->reference_keyframe >= loop_length);
      if (reuse) {
        out.map.add_observation(existing, id, static_cast<int>(f));
        continue;
      }
      MapPoint mp;
      mp.p_map = D * world[i];
      mp.descriptor = descriptors[i];
      mp.observations = {{id, static_cast<int>(f)}};
      mp.reference_keyframe = id;
      mp.reference_level = 0;
      mp.reference_distance = (T_cam_world * world[i]).norm() * D.scale;
      point_of_world[i] = out.map.add_point(std::move(mp));
    }
  }
  out.last = keyframes - 1;
}

// Error of the relative pose between two keyframes against the truth, with the map's scale at the
// older one (where the map is undrifted): translation (m) and rotation (deg).
std::pair<double, double> relative_error(const DriftedLoop& loop, int a, int b) {
  const Eigen::Isometry3d est = loop.map.keyframes()[static_cast<std::size_t>(a)].T_cam_map *
                                loop.map.keyframes()[static_cast<std::size_t>(b)].T_cam_map.inverse();
  const Eigen::Isometry3d truth = loop.truth[static_cast<std::size_t>(a)] * loop.truth[static_cast<std::size_t>(b)].inverse();
  const Eigen::Isometry3d err = truth.inverse() * est;
  return {err.translation().norm(), Eigen::AngleAxisd(err.linear()).angle() * 180.0 / M_PI};
}

}  // namespace

TEST_CASE("slam loop closure: a drifted loop is detected and corrected, duplicates fused") {
  const IdealCamera camera(PinholeCamera::ardrone2_front());
  DriftedLoop loop;
  build_drifted_loop(camera, loop);
  const auto [t_before, r_before] = relative_error(loop, loop.last, 5);
  INFO("before: " << t_before * 100 << " cm, " << r_before << " deg");
  REQUIRE(t_before > 0.05);
  REQUIRE(r_before > 3.0);
  const std::size_t points_before = loop.map.points().size();

  LoopCloser closer(camera, loop.map, LoopSettings{});
  const LoopReport report = closer.process(loop.last);
  REQUIRE(report.detected);
  CHECK(report.corrected);
  CHECK(report.loop <= 5);
  INFO("loop keyframe " << report.loop << ", inliers " << report.inliers << ", confirmed " << report.confirmed << ", correction " << report.correction_rotation_deg << " deg, scale " << report.correction_scale << ", moved " << report.correction_translation);
  CHECK(std::abs(report.correction_scale - 1.0 / 1.04) < 0.01);
  const auto [t_after, r_after] = relative_error(loop, loop.last, 5);
  INFO("after: " << t_after * 100 << " cm, " << r_after << " deg");
  CHECK(t_after < 0.01);
  CHECK(r_after < 0.3);
  // Keyframes in the middle of the loop moved towards the truth as well (the pose graph spread the
  // correction), and the returning keyframes' duplicate points were merged into the old ones.
  CHECK(relative_error(loop, 40, 0).first < 0.6 * t_before);
  CHECK(report.points_fused > 50);
  CHECK(loop.map.points().size() < points_before);
  CHECK(loop.map.generation() == 1);
  REQUIRE(loop.map.loop_edges().size() == 1);
  // The recorded correction carries a pose seen from the last keyframe onto the corrected map.
  const auto corrections = loop.map.corrections_since(0);
  REQUIRE(corrections.size() == 1);
  CHECK(corrections[0]->keyframe_correction.size() == loop.map.keyframes().size());

  SECTION("a second pass over the closed loop finds it consistent") {
    const LoopReport again = closer.process(loop.last);
    CHECK_FALSE(again.corrected);
    CHECK(loop.map.generation() == 1);
  }
}

TEST_CASE("slam loop closure: nothing happens without an old enough keyframe or with closure off") {
  const IdealCamera camera(PinholeCamera::ardrone2_front());
  DriftedLoop loop;
  build_drifted_loop(camera, loop);
  LoopSettings settings;
  settings.min_gap_s = 100.0;  // the loop is 30 s long
  CHECK_FALSE(LoopCloser(camera, loop.map, settings).process(loop.last).detected);
  settings = {};
  settings.enabled = false;
  CHECK_FALSE(LoopCloser(camera, loop.map, settings).process(loop.last).detected);
  CHECK(loop.map.generation() == 0);
}

TEST_CASE("slam pose graph: a loop edge pulls a chain back and fixed nodes stay") {
  // A chain of 10 nodes along x, each edge measured as a unit step; a loop edge says node 9 is at the
  // position of node 0 rotated... here simply: node 9 must be 8 units from node 0, not 9.
  PoseGraph graph;
  for (int k = 0; k < 10; ++k) {
    Similarity3 S;
    S.t = Eigen::Vector3d(-k, 0, 0);  // map -> camera: camera k at x = k
    graph.nodes[k] = S;
  }
  for (int k = 1; k < 10; ++k) graph.edges.push_back({k, k - 1, graph.nodes[k] * graph.nodes[k - 1].inverse(), 1.0});
  Similarity3 loop_measured;
  loop_measured.t = Eigen::Vector3d(-8, 0, 0);
  graph.edges.push_back({9, 0, loop_measured, 10.0});
  graph.fixed.insert(0);
  REQUIRE(optimize_pose_graph(graph).solved);
  CHECK(graph.nodes[0].t.norm() < 1e-9);
  const double x9 = graph.nodes[9].inverse().t.x();
  CHECK(x9 < 8.3);
  CHECK(x9 > 7.9);
  // The error is spread: node 5 moved back too, by about half the correction.
  const double x5 = graph.nodes[5].inverse().t.x();
  CHECK(x5 < 4.9);
  CHECK(x5 > 4.2);
}

TEST_CASE("slam pose graph: without a fixed node nothing is solved") {
  PoseGraph graph;
  graph.nodes[0] = Similarity3{};
  graph.nodes[1] = Similarity3{};
  graph.edges.push_back({1, 0, Similarity3{}, 1.0});
  CHECK_FALSE(optimize_pose_graph(graph).solved);
}

TEST_CASE("slam sim3 solver: recovers a known similarity from point pairs with outliers") {
  const IdealCamera camera(PinholeCamera::ardrone2_front());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Similarity3 G;
  G.R = Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()).toRotationMatrix();
  G.t = Eigen::Vector3d(0.2, -0.1, 0.05);
  G.scale = 0.95;
  // Both keyframes look along +z at points 2-3 m away; the old keyframe is 0.3 m to the side.
  const Eigen::Isometry3d T_current = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_old = Eigen::Isometry3d::Identity();
  T_old.translation() = Eigen::Vector3d(-0.3, 0, 0);
  std::vector<Sim3Pair> pairs;
  for (int i = 0; i < 80; ++i) {
    const Eigen::Vector3d current(u(rng), 0.5 * u(rng), 2.5 + 0.5 * u(rng));
    Eigen::Vector3d old = G * current;
    if (i % 4 == 0) old += Eigen::Vector3d(0.3 * u(rng), 0.3 * u(rng), 0.3);  // a wrong match
    const auto px_current = camera.project(T_current * current);
    const auto px_old = camera.project(T_old * (G * current));
    REQUIRE(px_current);
    REQUIRE(px_old);
    pairs.push_back({current, old, *px_current, *px_old, 1.0, 1.0});
  }
  const auto estimate = solve_sim3(camera, pairs, T_current, T_old);
  REQUIRE(estimate);
  CHECK(estimate->inliers.size() >= 58);
  CHECK(estimate->inliers.size() <= 62);
  CHECK(std::abs(estimate->old_from_current.scale - 0.95) < 1e-3);
  CHECK(Eigen::AngleAxisd(estimate->old_from_current.R.transpose() * G.R).angle() < 1e-3);
  CHECK((estimate->old_from_current.t - G.t).norm() < 1e-3);
}
