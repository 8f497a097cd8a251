#include "localization/slam/module/loop_closer.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <unordered_map>

#include "localization/slam/optimize/pose_graph.hpp"
#include "localization/slam/optimize/pose_optimizer.hpp"
#include "localization/slam/optimize/se3.hpp"
#include "localization/slam/optimize/sim3_solver.hpp"

namespace labo::slam {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The keyframe whose correction a point follows: its reference keyframe, else its first observer.
int anchor_keyframe(const MapPoint& p, std::size_t keyframes) {
  if (p.reference_keyframe >= 0 && static_cast<std::size_t>(p.reference_keyframe) < keyframes) return p.reference_keyframe;
  return p.observations.empty() ? -1 : p.observations.front().keyframe;
}

double median_depth(const SlamMap& map, const Keyframe& kf) {
  std::vector<double> depths;
  for (PointId id : kf.point_of_feature) {
    if (const MapPoint* p = map.point(id)) depths.push_back((kf.T_cam_map * p->p_map).z());
  }
  if (depths.empty()) return 1.0;
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
  return std::max(1e-6, depths[depths.size() / 2]);
}

}  // namespace

LoopCloser::LoopCloser(const IdealCamera& camera, SlamMap& map, const LoopSettings& settings)
    : camera_(camera), map_(map), settings_(settings), matcher_(camera, settings.levels, settings.level_scale) {}

double LoopCloser::sigma(int level) const { return std::pow(settings_.level_scale, level); }

std::vector<int> LoopCloser::old_neighbourhood(int loop, double before_t) const {
  std::vector<int> out{loop};
  for (int k : map_.covisible(loop, 10)) {
    if (map_.keyframes()[static_cast<std::size_t>(k)].t <= before_t) out.push_back(k);
  }
  return out;
}

bool LoopCloser::is_old_point(const MapPoint& p, double before_t) const {
  const int a = anchor_keyframe(p, map_.keyframes().size());
  return a >= 0 && map_.keyframes()[static_cast<std::size_t>(a)].t <= before_t;
}

std::vector<SearchCandidate> LoopCloser::old_points(int loop, double before_t) const {
  std::vector<SearchCandidate> out;
  std::set<PointId> seen;
  for (int k : old_neighbourhood(loop, before_t)) {
    for (PointId id : map_.keyframes()[static_cast<std::size_t>(k)].point_of_feature) {
      const MapPoint* p = map_.point(id);
      if (p && is_old_point(*p, before_t) && seen.insert(id).second) out.push_back(candidate_of(*p));
    }
  }
  return out;
}

LoopReport LoopCloser::process(int kf) {
  LoopReport report;
  report.current = kf;
  if (!settings_.enabled) return report;
  const std::optional<Detection> d = detect(kf);
  if (!d) return report;
  report.detected = true;
  report.loop = d->loop;
  report.inliers = d->inliers;
  report.confirmed = d->confirmed;
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  const Eigen::Vector3d c = key.center();
  report.correction_translation = (d->old_from_current * c - c).norm();
  report.correction_rotation_deg = Eigen::AngleAxisd(d->old_from_current.R).angle() * kRadToDeg;
  report.correction_scale = d->old_from_current.scale;
  const bool significant = report.correction_rotation_deg > settings_.min_rotation_deg ||
                           report.correction_translation > settings_.min_translation_ratio * median_depth(map_, key) ||
                           std::abs(report.correction_scale - 1.0) > settings_.min_scale_change;
  if (significant) {
    correct(kf, *d);
    report.corrected = true;
  }
  report.points_fused = fuse(kf, *d);
  return report;
}

std::optional<LoopCloser::Detection> LoopCloser::detect(int kf) const {
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  const double before_t = key.t - settings_.min_gap_s;
  std::vector<std::pair<double, int>> ranked;
  for (const Keyframe& k : map_.keyframes()) {
    if (k.t > before_t || k.small_image.size() != key.small_image.size() || k.small_image.empty()) continue;
    ranked.emplace_back(cv::norm(k.small_image, key.small_image, cv::NORM_L2SQR), k.id);
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<int> candidates;
  for (const auto& [score, id] : ranked) {
    if (static_cast<int>(candidates.size()) >= settings_.candidates) break;
    candidates.push_back(id);
  }
  // An old keyframe that already shares points with the new one (tracking found the old map) is a
  // candidate too, whatever its image looks like.
  for (const auto& [k, shared] : map_.covisible_counts(kf, 20)) {
    if (map_.keyframes()[static_cast<std::size_t>(k)].t <= before_t) {
      if (std::find(candidates.begin(), candidates.end(), k) == candidates.end()) candidates.push_back(k);
      break;
    }
  }
  std::optional<Detection> best;
  for (int loop : candidates) {
    std::optional<Detection> d = try_candidate(kf, loop);
    if (d && (!best || d->confirmed > best->confirmed)) best = d;
  }
  return best;
}

std::optional<LoopCloser::Detection> LoopCloser::try_candidate(int kf, int loop) const {
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  const Keyframe& old = map_.keyframes()[static_cast<std::size_t>(loop)];
  const double before_t = key.t - settings_.min_gap_s;
  auto is_old = [&](const MapPoint& p) { return is_old_point(p, before_t); };
  std::vector<int> old_features;
  for (std::size_t g = 0; g < old.frame.size(); ++g) {
    const MapPoint* p = map_.point(old.point_of_feature[g]);
    if (p && is_old(*p)) old_features.push_back(static_cast<int>(g));
  }
  if (static_cast<int>(old_features.size()) < settings_.min_inliers) return std::nullopt;
  // 3D-3D pairs: a new keyframe's (drifted) point and the old point its feature matches.
  std::vector<Sim3Pair> pairs;
  for (std::size_t f = 0; f < key.frame.size(); ++f) {
    const MapPoint* current = map_.point(key.point_of_feature[f]);
    if (!current || is_old(*current)) continue;
    int best = 257, second = 257, best_g = -1;
    for (int g : old_features) {
      const Feature& fo = old.frame.features[static_cast<std::size_t>(g)];
      if (std::abs(fo.level - key.frame.features[f].level) > 2) continue;
      const int d = hamming(key.frame.descriptors[f], old.frame.descriptors[static_cast<std::size_t>(g)]);
      if (d < best) {
        second = best;
        best = d;
        best_g = g;
      } else if (d < second) {
        second = d;
      }
    }
    if (best_g < 0 || best > settings_.max_hamming || best > 0.8 * second) continue;
    const Feature& fo = old.frame.features[static_cast<std::size_t>(best_g)];
    const MapPoint* old_point = map_.point(old.point_of_feature[static_cast<std::size_t>(best_g)]);
    pairs.push_back({current->p_map, old_point->p_map, key.frame.features[f].px, fo.px, sigma(key.frame.features[f].level),
                     sigma(fo.level)});
  }
  Sim3SolverSettings solver;
  solver.min_inliers = settings_.min_inliers;
  const std::optional<Sim3Estimate> estimate = solve_sim3(camera_, pairs, key.T_cam_map, old.T_cam_map, solver);
  if (!estimate) return std::nullopt;

  // Confirmation: with the corrected pose, the old neighbourhood's points must be found in the new
  // keyframe in numbers (a chance alignment of a few pairs would not predict them).
  std::vector<SearchCandidate> candidates = old_points(loop, before_t);
  const Eigen::Isometry3d corrected = (Similarity3::from_rigid(key.T_cam_map) * estimate->old_from_current.inverse()).rigid_pose();
  matcher_.project_candidates(candidates, corrected);
  std::vector<int> which(candidates.size());
  for (std::size_t i = 0; i < which.size(); ++i) which[i] = static_cast<int>(i);
  FeatureGrid grid(camera_.ideal_min(), camera_.ideal_max(), 24.0);
  grid.build(key.frame);
  std::vector<SearchMatch> matches;
  matcher_.search(candidates, which, key.frame, grid, 4.0, 0, settings_.max_hamming, matches);
  if (static_cast<int>(matches.size()) < settings_.min_confirmed) return std::nullopt;
  // The pose in the old map from all those points (hundreds, against the few tens of 3D-3D pairs):
  // rotation and position of the correction; the pairs' depth ratios give its scale.
  std::vector<PoseObservation> observations;
  for (const SearchMatch& m : matches) {
    const Feature& f = key.frame.features[static_cast<std::size_t>(m.feature)];
    observations.push_back({candidates[static_cast<std::size_t>(m.candidate)].p_map, f.px, sigma(f.level), true});
  }
  Eigen::Isometry3d T_old_frame = corrected;
  const int confirmed = optimize_pose(camera_, observations, T_old_frame);
  if (confirmed < settings_.min_confirmed) return std::nullopt;
  std::vector<double> ratios;
  for (int i : estimate->inliers) {
    const Sim3Pair& p = pairs[static_cast<std::size_t>(i)];
    const double z_drift = (key.T_cam_map * p.current_point).z(), z_old = (T_old_frame * p.old_point).z();
    if (z_drift > 1e-6 && z_old > 1e-6) ratios.push_back(z_old / z_drift);
  }
  if (ratios.size() < 3) return std::nullopt;
  std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2), ratios.end());
  const double g = ratios[ratios.size() / 2];
  // S_current in the old map = (1/g) * T_old_frame; G = S^-1 * T_current.
  const Similarity3 S{1.0 / g, T_old_frame.linear(), T_old_frame.translation() / g};
  return Detection{loop, S.inverse() * Similarity3::from_rigid(key.T_cam_map), static_cast<int>(estimate->inliers.size()), confirmed};
}

void LoopCloser::correct(int kf, const Detection& d) {
  const std::vector<Keyframe>& kfs = map_.keyframes();
  const double before_t = kfs[static_cast<std::size_t>(kf)].t - settings_.min_gap_s;
  std::map<int, Similarity3> before;
  for (const Keyframe& k : kfs) before[k.id] = Similarity3::from_rigid(k.T_cam_map);
  // The new keyframe's recent neighbourhood moves with it; the old neighbourhood of the loop
  // keyframe is where it lands.
  std::set<int> window{kf};
  for (int k : map_.covisible(kf, 10)) {
    if (kfs[static_cast<std::size_t>(k)].t > before_t && k > d.loop) window.insert(k);
  }
  const std::vector<int> landing = old_neighbourhood(d.loop, before_t);
  PoseGraph graph;
  graph.nodes = before;
  for (int k : window) graph.nodes[k] = before[k] * d.old_from_current.inverse();
  // The loop keyframe and everything before it are the reference the loop is closed onto.
  for (const Keyframe& k : kfs) {
    if (k.id <= d.loop) graph.fixed.insert(k.id);
  }
  // Edges measured before the correction hold the map's local shape. Covisibility across the loop
  // (points of the old map found again by the window before this closure) was measured with the drift:
  // the loop edges replace it.
  auto relative = [&](int i, int j) { return before[i] * before[j].inverse(); };
  const double gap = settings_.min_gap_s;
  for (const Keyframe& k : kfs) {
    if (k.id > 0) graph.edges.push_back({k.id, k.id - 1, relative(k.id, k.id - 1), 1.0});
    for (const auto& [n, shared] : map_.covisible_counts(k.id, 10)) {
      if (n >= k.id - 1 || shared < settings_.covisibility_edge_points) continue;
      const bool across = std::abs(k.t - kfs[static_cast<std::size_t>(n)].t) > gap;
      if (across && (window.count(k.id) || window.count(n))) continue;
      graph.edges.push_back({k.id, n, relative(k.id, n), 1.0});
    }
  }
  for (const LoopEdge& e : map_.loop_edges()) graph.edges.push_back({e.current, e.loop, e.measured, settings_.loop_edge_weight});
  for (int k : window) {
    for (int o : landing) graph.edges.push_back({k, o, graph.nodes[k] * graph.nodes[o].inverse(), settings_.loop_edge_weight});
  }
  const LoopEdge loop_edge{kf, d.loop, graph.nodes[kf] * graph.nodes[d.loop].inverse()};
  if (!optimize_pose_graph(graph).solved) return;

  // G_k = S_k^-1 * T_k: what the correction does to things attached to keyframe k.
  std::vector<Similarity3> correction(kfs.size());
  for (const Keyframe& k : kfs) correction[static_cast<std::size_t>(k.id)] = graph.nodes[k.id].inverse() * before.at(k.id);
  std::unique_lock lock(map_.mutex());
  for (Keyframe& k : map_.keyframes_mutable()) k.T_cam_map = graph.nodes[k.id].rigid_pose();
  for (auto& [id, p] : map_.points_mutable()) {
    const int a = anchor_keyframe(p, kfs.size());
    if (a < 0) continue;
    const Similarity3& G = correction[static_cast<std::size_t>(a)];
    p.p_map = G * p.p_map;
    p.reference_distance *= G.scale;
  }
  map_.add_loop_edge(loop_edge);
  map_.record_correction(std::move(correction));
}

int LoopCloser::fuse(int kf, const Detection& d) {
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  const double before_t = key.t - settings_.min_gap_s;
  auto is_old = [&](const MapPoint& p) { return is_old_point(p, before_t); };
  std::vector<SearchCandidate> candidates = old_points(d.loop, before_t);
  std::vector<int> targets{kf};
  for (int k : map_.covisible(kf, settings_.fuse_keyframes)) {
    if (map_.keyframes()[static_cast<std::size_t>(k)].t > before_t) targets.push_back(k);
  }
  struct Decision {
    int keyframe, feature;
    PointId old_point;
  };
  std::vector<Decision> decisions;
  std::vector<int> which(candidates.size());
  for (std::size_t i = 0; i < which.size(); ++i) which[i] = static_cast<int>(i);
  std::vector<SearchMatch> matches;
  for (int k : targets) {
    const Keyframe& target = map_.keyframes()[static_cast<std::size_t>(k)];
    matcher_.project_candidates(candidates, target.T_cam_map);
    FeatureGrid grid(camera_.ideal_min(), camera_.ideal_max(), 24.0);
    grid.build(target.frame);
    matcher_.search(candidates, which, target.frame, grid, 3.0, 0, settings_.max_hamming, matches);
    for (const SearchMatch& m : matches) decisions.push_back({k, m.feature, candidates[static_cast<std::size_t>(m.candidate)].id});
  }
  int fused = 0;
  std::unique_lock lock(map_.mutex());
  for (const Decision& dec : decisions) {
    const MapPoint* old_point = map_.point(dec.old_point);
    if (!old_point) continue;
    const PointId current = map_.keyframes()[static_cast<std::size_t>(dec.keyframe)].point_of_feature[static_cast<std::size_t>(dec.feature)];
    if (current == dec.old_point) continue;
    if (current == kNoPoint) {
      if (old_point->observed_by(dec.keyframe) < 0) {
        map_.add_observation(dec.old_point, dec.keyframe, dec.feature);
        ++fused;
      }
      continue;
    }
    const MapPoint* duplicate = map_.point(current);
    if (!duplicate || is_old(*duplicate)) continue;
    map_.merge_point(dec.old_point, current);
    ++fused;
  }
  return fused;
}

}  // namespace labo::slam
