// The tracker's measurements against the truth: a map made of one keyframe of the synthetic room
// whose points sit exactly on the walls (ray-box intersection), tracked in a second view. With the
// patch alignment (match/patch_aligner) the matched points are measured closer to their true
// projections, and the pose comes out closer to the truth, than from the FAST corners alone.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "core/frames.hpp"
#include "bench/slam/synthetic_room.hpp"
#include "localization/slam/feature/feature_extractor.hpp"
#include "localization/slam/match/patch_aligner.hpp"
#include "localization/slam/module/frame_tracker.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/optimize/se3.hpp"
#include "slam_test_helpers.hpp"

namespace labo::slam {

using bench::SyntheticRoom;
using bench::SyntheticRoomSpec;

namespace {

struct TrackedView {
  double rms_px = 0;          // measured - true projection, distorted level-0 pixels
  double translation_cm = 0;  // pose error
  double rotation_deg = 0;
  int matches = 0;
  int refined = 0;
};

TrackedView track_second_view(bool patch_refinement) {
  const PinholeCamera real = PinholeCamera::ardrone2_front();
  const IdealCamera camera(real);
  const SyntheticRoom room(real);
  ExtractorSettings extractor_settings;
  FeatureExtractor extractor(camera, extractor_settings);
  FeatureGrid grid(camera.ideal_min(), camera.ideal_max(), 24.0);

  // Keyframe: 2.5 m from the panel's wall; the frame: 0.12 m to the side, 4 deg turned, 3 deg pitched.
  const Eigen::Isometry3d T_world_key = make_pose({5.5, 3.0, 1.3}, 0.0, 0.0, 0.0) * T_body_cam_front();
  const Eigen::Isometry3d T_world_frame = make_pose({5.45, 2.88, 1.36}, 4.0 * M_PI / 180, 3.0 * M_PI / 180, 0.0) * T_body_cam_front();

  SlamMap map;
  Keyframe key;
  key.T_cam_map = T_world_key.inverse();
  extractor.extract(room.render(T_world_key, 1), key.frame);
  for (const cv::Mat& level : extractor.pyramid()) key.pyramid.push_back(level.clone());
  const int k = map.add_keyframe(std::move(key));
  const Keyframe& kf = map.keyframes()[static_cast<std::size_t>(k)];
  for (std::size_t i = 0; i < kf.frame.size(); ++i) {
    const Feature& f = kf.frame.features[i];
    const Eigen::Vector3d ray = T_world_key.linear() * camera.bearing(f.px);
    MapPoint p;
    p.p_map = testing::hit_wall(room.spec(), T_world_key.translation(), ray);
    p.descriptor = kf.frame.descriptors[i];
    p.observations = {{k, static_cast<int>(i)}};
    p.reference_keyframe = k;
    p.reference_level = f.level;
    p.reference_distance = (p.p_map - T_world_key.translation()).norm();
    map.add_point(std::move(p));
  }

  FrameFeatures frame;
  extractor.extract(room.render(T_world_frame, 2), frame);
  grid.build(frame);
  TrackerSettings settings;
  settings.patch_refinement = patch_refinement;
  FrameTracker tracker(camera, settings);
  // A prior off by 2 cm and 0.5 deg, as a motion model's.
  const Eigen::Isometry3d truth = T_world_frame.inverse();
  Eigen::Matrix<double, 6, 1> twist;
  twist << 0.02, -0.01, 0.01, 0.005, -0.006, 0.004;
  const TrackOutcome out = tracker.track(map, frame, grid, extractor.pyramid(), se3_exp(twist) * truth, k, true);
  REQUIRE(out.pose_valid);

  TrackedView view;
  double sum_sq = 0;
  for (std::size_t i = 0; i < out.matches.size(); ++i) {
    const auto projected = real.project(truth * map.point(out.matches[i].second)->p_map);
    REQUIRE(projected);
    sum_sq += (out.match_image_px[i] - *projected).squaredNorm();
  }
  view.matches = static_cast<int>(out.matches.size());
  view.refined = out.refined;
  view.rms_px = std::sqrt(sum_sq / std::max(1, view.matches));
  const Eigen::Isometry3d error = out.T_cam_map * truth.inverse();
  view.translation_cm = 100 * (out.T_cam_map.inverse().translation() - T_world_frame.translation()).norm();
  view.rotation_deg = rotation_angle(error) * 180 / M_PI;
  return view;
}

// Distance of a point to the nearest face of the room's box.
double off_wall(const SyntheticRoomSpec& room, const Eigen::Vector3d& p) {
  double d = 1e9;
  for (int axis = 0; axis < 3; ++axis) {
    d = std::min({d, std::abs(p[axis] - room.min_corner[axis]), std::abs(p[axis] - room.max_corner[axis])});
  }
  return d;
}

struct NewPoints {
  double median_off_wall_cm = 0;  // median: a few mismatched points are far off either way
  int count = 0;
};

// Keyframe A (true pose, its points exactly on the walls) and keyframe B, 0.25 m to the side (true
// pose, no points): the mapper re-measures A's points in B and triangulates B's other corners
// against A. How far from the walls do the new points land?
NewPoints map_second_keyframe(bool patch_refinement) {
  const PinholeCamera real = PinholeCamera::ardrone2_front();
  const IdealCamera camera(real);
  const SyntheticRoom room(real);
  FeatureExtractor extractor(camera, ExtractorSettings{});
  const Eigen::Isometry3d T_world_a = make_pose({5.3, 3.1, 1.3}, 0.0) * T_body_cam_front();
  const Eigen::Isometry3d T_world_b = make_pose({5.3, 2.85, 1.33}, 2.0 * M_PI / 180) * T_body_cam_front();
  SlamMap map;
  MapperSettings settings;
  settings.threaded = false;
  settings.global_ba = false;
  settings.loop.enabled = false;
  settings.patch_refinement = patch_refinement;
  LocalMapper mapper(camera, map, settings);
  Keyframe a;
  a.T_cam_map = T_world_a.inverse();
  extractor.extract(room.render(T_world_a, 3), a.frame);
  for (const cv::Mat& level : extractor.pyramid()) a.pyramid.push_back(level.clone());
  const int ka = map.add_keyframe(std::move(a));
  const Keyframe& kfa = map.keyframes()[static_cast<std::size_t>(ka)];
  for (std::size_t i = 0; i < kfa.frame.size(); i += 2) {  // half the corners hold points
    const Feature& f = kfa.frame.features[i];
    MapPoint p;
    p.p_map = testing::hit_wall(room.spec(), T_world_a.translation(), T_world_a.linear() * camera.bearing(f.px));
    p.descriptor = kfa.frame.descriptors[i];
    p.observations = {{ka, static_cast<int>(i)}};
    p.reference_keyframe = ka;
    p.reference_level = f.level;
    p.reference_distance = (p.p_map - T_world_a.translation()).norm();
    map.add_point(std::move(p));
  }
  const std::size_t before = map.points().size();
  std::vector<PointId> old_ids;
  for (const auto& [id, p] : map.points()) old_ids.push_back(id);
  Keyframe b;
  b.t = 1.0;
  b.T_cam_map = T_world_b.inverse();
  extractor.extract(room.render(T_world_b, 4), b.frame);
  for (const cv::Mat& level : extractor.pyramid()) b.pyramid.push_back(level.clone());
  b.point_of_feature.assign(b.frame.size(), kNoPoint);
  mapper.enqueue(std::move(b));
  NewPoints out;
  std::vector<double> off;
  for (const auto& [id, p] : map.points()) {
    if (std::find(old_ids.begin(), old_ids.end(), id) != old_ids.end()) continue;
    off.push_back(off_wall(room.spec(), p.p_map));
  }
  REQUIRE(map.points().size() > before);
  out.count = static_cast<int>(off.size());
  std::nth_element(off.begin(), off.begin() + static_cast<long>(off.size() / 2), off.end());
  out.median_off_wall_cm = 100 * off[off.size() / 2];
  return out;
}

}  // namespace

TEST_CASE("slam mapper: patch alignment puts new points closer to the walls") {
  const NewPoints corners = map_second_keyframe(false);
  const NewPoints aligned = map_second_keyframe(true);
  INFO("corners: " << corners.count << " new points, " << corners.median_off_wall_cm << " cm off the walls (median); aligned: "
                   << aligned.count << " new points, " << aligned.median_off_wall_cm << " cm");
  REQUIRE(corners.count > 50);
  REQUIRE(aligned.count > 50);
  CHECK(aligned.median_off_wall_cm < 0.7 * corners.median_off_wall_cm);
}

TEST_CASE("slam tracker: patch alignment measures points closer to the truth than the corners") {
  const TrackedView corners = track_second_view(false);
  const TrackedView aligned = track_second_view(true);
  INFO("corners: " << corners.matches << " matches, " << corners.rms_px << " px, " << corners.translation_cm << " cm, "
                   << corners.rotation_deg << " deg; aligned: " << aligned.matches << " matches (" << aligned.refined
                   << " refined), " << aligned.rms_px << " px, " << aligned.translation_cm << " cm, " << aligned.rotation_deg << " deg");
  REQUIRE(corners.matches > 100);
  REQUIRE(aligned.matches > 100);
  CHECK(aligned.refined > aligned.matches * 8 / 10);
  CHECK(aligned.rms_px < 0.6 * corners.rms_px);
  CHECK(aligned.translation_cm < corners.translation_cm);
}

TEST_CASE("slam patch aligner: refuses a flat patch and a source without images") {
  const PinholeCamera real = PinholeCamera::ardrone2_front();
  const IdealCamera camera(real);
  PatchAligner aligner(camera);
  std::vector<cv::Mat> flat;
  for (int l = 0; l < 4; ++l) {
    const double s = std::pow(1.5, l);
    flat.push_back(cv::Mat(static_cast<int>(std::lround(360 / s)), static_cast<int>(std::lround(640 / s)), CV_8U, cv::Scalar(128)));
  }
  const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d p(0.1, 0.05, 2.0);
  const Eigen::Vector2d px = *real.project(p);
  CHECK_FALSE(aligner.align({&flat, T, px, 1}, p, flat, T, px));
  CHECK_FALSE(aligner.align({nullptr, T, px, 1}, p, flat, T, px));
  const std::vector<cv::Mat> none;
  CHECK_FALSE(aligner.align({&flat, T, px, 1}, p, none, T, px));
}

}  // namespace labo::slam
