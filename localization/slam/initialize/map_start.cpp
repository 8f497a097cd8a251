#include "localization/slam/initialize/map_start.hpp"

#include <algorithm>
#include <mutex>

namespace labo::slam {

namespace {

void add_initial_keyframes_and_points(const InitialMap& init, Keyframe reference, Keyframe current, SlamMap& map) {
  std::unique_lock lock(map.mutex());
  const std::optional<Eigen::Vector3d> reference_down_cam = reference.down_cam, current_down_cam = current.down_cam;
  reference.t = init.reference_t;
  reference.frame = init.reference;
  const int k0 = map.add_keyframe(std::move(reference));
  current.T_cam_map = init.T_current_reference;
  const int k1 = map.add_keyframe(std::move(current));
  // The map's gravity direction from the first keyframe's attitude (its camera frame is the map's);
  // global adjustments refine it with every keyframe's.
  if (reference_down_cam) map.set_down_map(*reference_down_cam);
  else if (current_down_cam) map.set_down_map(init.T_current_reference.linear().transpose() * *current_down_cam);
  const Eigen::Vector3d c0 = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < init.points.size(); ++i) {
    MapPoint p;
    p.p_map = init.points[i];
    const auto [f0, f1] = init.matches[i];
    p.descriptor = init.reference.descriptors[static_cast<std::size_t>(f0)];
    p.observations = {{k0, f0}, {k1, f1}};
    p.reference_keyframe = k0;
    p.reference_level = init.reference.features[static_cast<std::size_t>(f0)].level;
    p.reference_distance = (init.points[i] - c0).norm();
    map.add_point(std::move(p));
  }
}

void set_median_depth_to_one(SlamMap& map) {
  std::unique_lock lock(map.mutex());
  std::vector<double> depths;
  for (const auto& [id, p] : map.points()) depths.push_back(p.p_map.z());
  if (depths.empty()) return;
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
  const double s = depths[depths.size() / 2] > 1e-9 ? 1.0 / depths[depths.size() / 2] : 1.0;
  for (auto& [id, p] : map.points_mutable()) {
    p.p_map *= s;
    p.reference_distance *= s;
  }
  for (auto& kf : map.keyframes_mutable()) kf.T_cam_map.translation() *= s;
}

}  // namespace

void start_map(const InitialMap& init, Keyframe reference, Keyframe current, SlamMap& map, LocalMapper& mapper) {
  add_initial_keyframes_and_points(init, std::move(reference), std::move(current), map);
  mapper.adjust_initial_map();
  set_median_depth_to_one(map);
}

}  // namespace labo::slam
