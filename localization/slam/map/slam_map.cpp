#include "localization/slam/map/slam_map.hpp"

#include <algorithm>

namespace labo::slam {

int SlamMap::add_keyframe(Keyframe kf) {
  kf.id = static_cast<int>(keyframes_.size());
  kf.point_of_feature.resize(kf.frame.size(), kNoPoint);
  keyframes_.push_back(std::move(kf));
  return keyframes_.back().id;
}

PointId SlamMap::add_point(MapPoint p) {
  p.id = next_point_id_++;
  for (const Observation& o : p.observations) {
    keyframes_[static_cast<std::size_t>(o.keyframe)].point_of_feature[static_cast<std::size_t>(o.feature)] = p.id;
  }
  const PointId id = p.id;
  points_.emplace(id, std::move(p));
  return id;
}

void SlamMap::add_observation(PointId id, int keyframe, int feature) {
  auto it = points_.find(id);
  if (it == points_.end()) return;
  auto& slot = keyframes_[static_cast<std::size_t>(keyframe)].point_of_feature[static_cast<std::size_t>(feature)];
  if (slot != kNoPoint || it->second.observed_by(keyframe) >= 0) return;
  slot = id;
  it->second.observations.push_back({keyframe, feature});
}

void SlamMap::remove_observation(PointId id, int keyframe) {
  auto it = points_.find(id);
  if (it == points_.end()) return;
  auto& obs = it->second.observations;
  for (auto o = obs.begin(); o != obs.end(); ++o) {
    if (o->keyframe == keyframe) {
      keyframes_[static_cast<std::size_t>(keyframe)].point_of_feature[static_cast<std::size_t>(o->feature)] = kNoPoint;
      obs.erase(o);
      break;
    }
  }
  if (obs.size() < 2) remove_point(id);
}

void SlamMap::remove_point(PointId id) {
  auto it = points_.find(id);
  if (it == points_.end()) return;
  for (const Observation& o : it->second.observations) {
    auto& slot = keyframes_[static_cast<std::size_t>(o.keyframe)].point_of_feature[static_cast<std::size_t>(o.feature)];
    if (slot == id) slot = kNoPoint;
  }
  points_.erase(it);
}

void SlamMap::merge_point(PointId keep, PointId drop) {
  if (keep == drop) return;
  auto k = points_.find(keep);
  auto d = points_.find(drop);
  if (k == points_.end() || d == points_.end()) return;
  for (const Observation& o : d->second.observations) {
    auto& slot = keyframes_[static_cast<std::size_t>(o.keyframe)].point_of_feature[static_cast<std::size_t>(o.feature)];
    if (slot == drop) slot = kNoPoint;
    if (k->second.observed_by(o.keyframe) >= 0) continue;
    slot = keep;
    k->second.observations.push_back(o);
  }
  d->second.observations.clear();
  points_.erase(d);
}

void SlamMap::record_correction(std::vector<Similarity3> keyframe_correction) {
  ++generation_;
  corrections_.push_back({generation_, std::move(keyframe_correction)});
  constexpr std::size_t kKept = 32;  // adjustments record corrections too
  if (corrections_.size() > kKept) corrections_.erase(corrections_.begin());
}

std::vector<const MapCorrection*> SlamMap::corrections_since(int generation) const {
  std::vector<const MapCorrection*> out;
  for (const MapCorrection& c : corrections_) {
    if (c.generation > generation) out.push_back(&c);
  }
  return out;
}

void SlamMap::clear() {
  keyframes_.clear();
  points_.clear();
  next_point_id_ = 0;
  loop_edges_.clear();
  corrections_.clear();
  down_map_.reset();
  ++generation_;  // whoever tracked the old map must not carry a pose over
}

std::vector<int> SlamMap::covisible(int keyframe, int count) const {
  std::vector<int> out;
  for (const auto& [kf, n] : covisible_counts(keyframe, count)) out.push_back(kf);
  return out;
}

std::vector<std::pair<int, int>> SlamMap::covisible_counts(int keyframe, int count) const {
  std::map<int, int> shared;
  for (PointId id : keyframes_[static_cast<std::size_t>(keyframe)].point_of_feature) {
    const MapPoint* p = point(id);
    if (!p) continue;
    for (const Observation& o : p->observations) {
      if (o.keyframe != keyframe) ++shared[o.keyframe];
    }
  }
  std::vector<std::pair<int, int>> ranked(shared.begin(), shared.end());
  std::sort(ranked.begin(), ranked.end(), [](auto a, auto b) { return a.second != b.second ? a.second > b.second : a.first < b.first; });
  if (static_cast<int>(ranked.size()) > count) ranked.resize(static_cast<std::size_t>(std::max(0, count)));
  return ranked;
}

std::vector<int> SlamMap::nearest(const Eigen::Isometry3d& T_cam_map, int count) const {
  const Eigen::Vector3d c = T_cam_map.inverse().translation();
  const Eigen::Vector3d axis = T_cam_map.linear().row(2).transpose();
  std::vector<std::pair<double, int>> ranked;
  for (const Keyframe& kf : keyframes_) {
    const double cos_angle = axis.dot(kf.optical_axis());
    if (cos_angle < 0.3) continue;
    // Distance plus a penalty for looking elsewhere (1 map unit per radian, roughly).
    ranked.emplace_back((kf.center() - c).norm() + std::acos(std::clamp(cos_angle, -1.0, 1.0)), kf.id);
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<int> out;
  for (const auto& [d, id] : ranked) {
    if (static_cast<int>(out.size()) >= count) break;
    out.push_back(id);
  }
  return out;
}

}  // namespace labo::slam
