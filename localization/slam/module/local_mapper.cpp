#include "localization/slam/module/local_mapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "localization/slam/initialize/two_view_geometry.hpp"
#include "localization/slam/optimize/bundle_adjuster.hpp"

namespace labo::slam {
namespace {
constexpr double kChi2 = 5.991;
}

LocalMapper::LocalMapper(const IdealCamera& camera, SlamMap& map, const MapperSettings& settings)
    : camera_(camera),
      map_(map),
      settings_(settings),
      matcher_(camera, settings.levels, settings.level_scale),
      aligner_(camera),
      loop_closer_(camera, map, settings.loop) {
  if (settings_.threaded) thread_ = std::thread([this] { worker(); });
}

LocalMapper::~LocalMapper() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    abort_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

double LocalMapper::sigma(int level) const { return std::pow(settings_.level_scale, level); }

std::optional<Eigen::Vector2d> LocalMapper::align(const Keyframe& source, int source_feature, const Eigen::Vector3d& p_map,
                                                  const Keyframe& target, int target_feature) {
  if (!settings_.patch_refinement || source_feature < 0 || source.pyramid.empty() || target.pyramid.empty()) return std::nullopt;
  const Feature& fs = source.frame.features[static_cast<std::size_t>(source_feature)];
  const Feature& ft = target.frame.features[static_cast<std::size_t>(target_feature)];
  const auto aligned = aligner_.align({&source.pyramid, source.T_cam_map, fs.image_px.cast<double>(), fs.level}, p_map,
                                      target.pyramid, target.T_cam_map, ft.image_px.cast<double>());
  if (!aligned) return std::nullopt;
  return aligned->image_px;
}

void LocalMapper::move_feature(Keyframe& kf, int feature, const Eigen::Vector2d& image_px) const {
  Feature& f = kf.frame.features[static_cast<std::size_t>(feature)];
  f.image_px = image_px.cast<float>();
  f.px = camera_.ideal_from_image(image_px.x(), image_px.y());
}

void LocalMapper::enqueue(Keyframe keyframe) {
  if (!settings_.threaded) {
    process(std::move(keyframe));
    if (settings_.global_ba && stats_.keyframes_processed % settings_.global_ba_every == 0) global_adjustment();
    return;
  }
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(keyframe));
    abort_ = true;  // a running adjustment yields to the new keyframe
  }
  wake_.notify_all();
}

int LocalMapper::queued() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(queue_.size()) + (busy_ ? 1 : 0);
}

void LocalMapper::wait_idle() {
  if (!settings_.threaded) return;
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return (queue_.empty() && !busy_ && !global_pending_) || stop_; });
}

MapperStats LocalMapper::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void LocalMapper::worker() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    if (!queue_.empty()) {
      Keyframe kf = std::move(queue_.front());
      queue_.pop_front();
      busy_ = true;
      abort_ = false;
      lock.unlock();
      process(std::move(kf));
      lock.lock();
      busy_ = false;
      global_pending_ = settings_.global_ba;
    } else if (global_pending_) {
      busy_ = true;
      abort_ = false;
      lock.unlock();
      global_adjustment();
      lock.lock();
      busy_ = false;
      global_pending_ = false;
    } else {
      idle_.notify_all();
      wake_.wait(lock);
    }
  }
  idle_.notify_all();
}

void LocalMapper::process(Keyframe keyframe) {
  const auto start = std::chrono::steady_clock::now();
  carry_over_corrections(keyframe);
  std::vector<PointId> associations = std::move(keyframe.point_of_feature);
  keyframe.point_of_feature.clear();
  int kf = 0;
  {
    std::unique_lock lock(map_.mutex());
    kf = map_.add_keyframe(std::move(keyframe));
    for (std::size_t f = 0; f < associations.size(); ++f) {
      if (associations[f] != kNoPoint) map_.add_observation(associations[f], kf, static_cast<int>(f));
    }
    // A map started without attitudes takes its gravity direction from the first keyframe with one.
    const Keyframe& added = map_.keyframes()[static_cast<std::size_t>(kf)];
    if (!map_.down_map() && added.down_cam) map_.set_down_map(added.T_cam_map.linear().transpose() * *added.down_cam);
  }
  // Neighbours: the most covisible keyframes, completed by the nearest ones.
  std::vector<int> neighbours = map_.covisible(kf, 8);
  for (int n : map_.nearest(map_.keyframes()[static_cast<std::size_t>(kf)].T_cam_map, 5)) {
    if (n != kf && std::find(neighbours.begin(), neighbours.end(), n) == neighbours.end()) neighbours.push_back(n);
  }
  remeasure(kf, neighbours);
  // Triangulate against the most covisible neighbours (overlap guaranteed); those whose baseline is
  // too short for the scene depth are skipped inside.
  triangulate_new_points(kf, neighbours);
  std::vector<int> free_kfs{kf};
  for (int n : map_.covisible(kf, settings_.local_ba_keyframes - 1)) free_kfs.push_back(n);
  adjust(free_kfs, false, settings_.local_ba_iterations);
  close_loops(kf);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard lock(mutex_);
  ++stats_.keyframes_processed;
  ++stats_.local_ba_runs;
  stats_.last_keyframe_ms = ms;
  stats_.keyframe_ms.push_back(ms);
}

void LocalMapper::remeasure(int kf, const std::vector<int>& neighbours) {
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  std::vector<SearchCandidate> candidates;
  std::vector<char> already;  // observed by the new keyframe through tracking
  std::set<PointId> seen;
  for (int n : neighbours) {
    for (PointId id : map_.keyframes()[static_cast<std::size_t>(n)].point_of_feature) {
      const MapPoint* p = map_.point(id);
      if (!p || !seen.insert(id).second) continue;
      candidates.push_back(candidate_of(*p));
      already.push_back(p->observed_by(kf) >= 0 ? 1 : 0);
    }
  }
  matcher_.project_candidates(candidates, key.T_cam_map);
  FeatureGrid grid(camera_.ideal_min(), camera_.ideal_max(), 24.0);
  grid.build(key.frame);
  std::vector<int> search;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!already[i]) search.push_back(static_cast<int>(i));
  }
  std::vector<SearchMatch> matches;
  matcher_.search(candidates, search, key.frame, grid, 4.0, 0, settings_.max_hamming, matches);
  std::vector<char> found(already);
  // The re-found corners measured as the tracker measures them: aligned with the point's patch.
  std::vector<std::optional<Eigen::Vector2d>> refined(matches.size());
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const SearchCandidate& c = candidates[static_cast<std::size_t>(matches[i].candidate)];
    if (c.reference_keyframe < 0 || c.reference_keyframe >= static_cast<int>(map_.keyframes().size())) continue;
    refined[i] = align(map_.keyframes()[static_cast<std::size_t>(c.reference_keyframe)], c.reference_feature, c.p_map, key,
                       matches[i].feature);
  }
  std::unique_lock lock(map_.mutex());
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const SearchMatch& m = matches[i];
    found[static_cast<std::size_t>(m.candidate)] = 1;
    if (key.point_of_feature[static_cast<std::size_t>(m.feature)] != kNoPoint) continue;
    if (refined[i]) move_feature(map_.keyframes_mutable()[static_cast<std::size_t>(kf)], m.feature, *refined[i]);
    map_.add_observation(candidates[static_cast<std::size_t>(m.candidate)].id, kf, m.feature);
  }
  // Points that keep failing to be re-found where they should be visible are wrong (bad depth,
  // a mismatch at creation): cull them, as they also drag the tracking quality down.
  int culled = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!candidates[i].in_view) continue;
    auto it = map_.points_mutable().find(candidates[i].id);
    if (it == map_.points_mutable().end()) continue;
    MapPoint& p = it->second;
    (found[i] ? p.remeasure_hits : p.remeasure_misses) += 1;
    if (settings_.cull_points && p.remeasure_misses >= 3 && p.remeasure_misses > 2 * p.remeasure_hits) {
      map_.remove_point(p.id);
      ++culled;
    }
  }
  std::lock_guard stats_lock(mutex_);
  stats_.points_culled += culled;
}

std::vector<char> LocalMapper::near_mapped(const Keyframe& kf, const FeatureGrid& grid) const {
  std::vector<char> out(kf.frame.size(), 0);
  if (settings_.new_point_clearance_px <= 0) return out;
  std::vector<int> nearby;
  for (std::size_t i = 0; i < kf.frame.size(); ++i) {
    if (kf.point_of_feature[i] != kNoPoint) continue;
    const Feature& f = kf.frame.features[i];
    grid.query(f.px, settings_.new_point_clearance_px * sigma(f.level), 0, settings_.levels - 1, kf.frame, nearby);
    for (int j : nearby) {
      if (kf.point_of_feature[static_cast<std::size_t>(j)] != kNoPoint) {
        out[i] = 1;
        break;
      }
    }
  }
  return out;
}

void LocalMapper::triangulate_new_points(int kf, const std::vector<int>& neighbours) {
  const Keyframe& key = map_.keyframes()[static_cast<std::size_t>(kf)];
  const Eigen::Vector3d c_key = key.center();
  std::vector<char> key_used(key.frame.size(), 0);
  // Corners next to a mapped corner (another level's detection of it) would only duplicate that point.
  FeatureGrid key_grid(camera_.ideal_min(), camera_.ideal_max(), 24.0), other_grid = key_grid;
  std::vector<int> nearby;
  const bool clearance = settings_.new_point_clearance_px > 0;
  int skipped = 0;
  if (clearance) {
    key_grid.build(key.frame);
    key_used = near_mapped(key, key_grid);
    for (char c : key_used) skipped += c;
  }
  const double cos_min_parallax = std::cos(settings_.min_parallax_deg * M_PI / 180.0);
  int tried = 0;
  for (int n : neighbours) {
    if (tried++ >= settings_.triangulation_neighbours) break;
    const Keyframe& other = map_.keyframes()[static_cast<std::size_t>(n)];
    // Median depth of the neighbour's points decides whether the baseline is worth it.
    std::vector<double> depths;
    for (PointId id : other.point_of_feature) {
      if (const MapPoint* p = map_.point(id)) depths.push_back((other.T_cam_map * p->p_map).z());
    }
    if (depths.size() < 10) continue;
    std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
    const double baseline = (other.center() - c_key).norm();
    if (baseline < 0.01 * depths[depths.size() / 2]) continue;

    const Eigen::Isometry3d T_other_key = other.T_cam_map * key.T_cam_map.inverse();
    const Eigen::Matrix3d R = T_other_key.linear();
    const Eigen::Vector3d t = T_other_key.translation();
    Eigen::Matrix3d tx;
    tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
    const Eigen::Matrix3d E = tx * R;  // x_other^T E x_key = 0, normalized coordinates
    std::vector<PointId> new_points;
    std::unique_lock lock(map_.mutex(), std::defer_lock);
    std::vector<MapPoint> created;
    std::vector<std::pair<int, Eigen::Vector2d>> other_moved;  // refined corners of the neighbour
    std::vector<char> other_used(other.frame.size(), 0);
    if (clearance) {
      other_grid.build(other.frame);
      other_used = near_mapped(other, other_grid);
    }
    for (std::size_t i = 0; i < key.frame.size(); ++i) {
      if (key_used[i] || key.point_of_feature[i] != kNoPoint) continue;
      const Feature& fk = key.frame.features[i];
      const Eigen::Vector3d xk((fk.px.x() - camera_.cx()) / camera_.fx(), (fk.px.y() - camera_.cy()) / camera_.fy(), 1.0);
      const Eigen::Vector3d line = E * xk;
      const double line_norm = std::hypot(line.x(), line.y());
      if (line_norm < 1e-12) continue;
      int best = 257, second = 257, best_j = -1;
      for (std::size_t j = 0; j < other.frame.size(); ++j) {
        if (other_used[j] || other.point_of_feature[j] != kNoPoint) continue;
        const Feature& fo = other.frame.features[j];
        if (std::abs(fo.level - fk.level) > 1) continue;
        const int d = hamming(key.frame.descriptors[i], other.frame.descriptors[j]);
        if (d >= second) continue;
        // Epipolar gate: distance of the other feature to the epipolar line, in pixels.
        const Eigen::Vector3d xo((fo.px.x() - camera_.cx()) / camera_.fx(), (fo.px.y() - camera_.cy()) / camera_.fy(), 1.0);
        const double dist_px = std::abs(xo.dot(line)) / line_norm * camera_.fx();
        if (dist_px > 2.0 * sigma(fo.level)) continue;
        if (d < best) {
          second = best;
          best = d;
          best_j = static_cast<int>(j);
        } else {
          second = d;
        }
      }
      if (best_j < 0 || best > settings_.max_hamming || best > 0.8 * second) continue;
      const Feature& fo = other.frame.features[static_cast<std::size_t>(best_j)];
      auto p = triangulate(camera_, key.T_cam_map, fk.px, other.T_cam_map, fo.px);
      if (!p) continue;
      // The neighbour's corner aligned with the new point's patch (the new keyframe's feature is the
      // patch's centre, i.e. exact by definition), then triangulated again.
      Eigen::Vector2d fo_px = fo.px;
      const auto fo_refined = align(key, static_cast<int>(i), *p, other, best_j);
      if (fo_refined) {
        fo_px = camera_.ideal_from_image(fo_refined->x(), fo_refined->y());
        p = triangulate(camera_, key.T_cam_map, fk.px, other.T_cam_map, fo_px);
        if (!p) continue;
      }
      const Eigen::Vector3d rk = *p - c_key, ro = *p - other.center();
      if (rk.normalized().dot(ro.normalized()) > cos_min_parallax) continue;
      const auto pk = camera_.project(key.T_cam_map * *p), po = camera_.project(other.T_cam_map * *p);
      if (!pk || !po) continue;
      if ((*pk - fk.px).squaredNorm() > kChi2 * sigma(fk.level) * sigma(fk.level)) continue;
      if ((*po - fo_px).squaredNorm() > kChi2 * sigma(fo.level) * sigma(fo.level)) continue;
      // Scale consistency: the two observations' levels must agree with the two distances.
      const double ratio = rk.norm() / ro.norm(), level_ratio = sigma(fo.level) / sigma(fk.level);
      if (ratio > 1.8 * level_ratio || ratio < level_ratio / 1.8) continue;
      MapPoint mp;
      mp.p_map = *p;
      mp.descriptor = key.frame.descriptors[i];
      mp.observations = {{kf, static_cast<int>(i)}, {n, best_j}};
      mp.reference_keyframe = kf;
      mp.reference_level = fk.level;
      mp.reference_distance = rk.norm();
      created.push_back(std::move(mp));
      if (fo_refined) other_moved.emplace_back(best_j, *fo_refined);
      key_used[i] = 1;
      other_used[static_cast<std::size_t>(best_j)] = 1;
      if (clearance) {
        // The same corner on the other levels is now mapped too.
        key_grid.query(fk.px, settings_.new_point_clearance_px * sigma(fk.level), 0, settings_.levels - 1, key.frame, nearby);
        for (int k : nearby) key_used[static_cast<std::size_t>(k)] = 1;
        other_grid.query(fo.px, settings_.new_point_clearance_px * sigma(fo.level), 0, settings_.levels - 1, other.frame, nearby);
        for (int k : nearby) other_used[static_cast<std::size_t>(k)] = 1;
      }
    }
    lock.lock();
    for (const auto& [feature, image_px] : other_moved) move_feature(map_.keyframes_mutable()[static_cast<std::size_t>(n)], feature, image_px);
    for (MapPoint& mp : created) map_.add_point(std::move(mp));
    lock.unlock();
    std::lock_guard stats_lock(mutex_);
    stats_.points_created += static_cast<int>(created.size());
  }
  std::lock_guard stats_lock(mutex_);
  stats_.clearance_skips += skipped;
}

void LocalMapper::adjust(const std::vector<int>& free_keyframes, bool global, int max_iterations) {
  BundleProblem problem;
  std::set<int> free_set(free_keyframes.begin(), free_keyframes.end());
  if (global) {
    free_set.clear();
    for (const Keyframe& k : map_.keyframes()) free_set.insert(k.id);
  }
  for (int k : free_set) {
    for (PointId id : map_.keyframes()[static_cast<std::size_t>(k)].point_of_feature) {
      const MapPoint* p = map_.point(id);
      if (!p || problem.points.count(id)) continue;
      problem.points[id] = p->p_map;
      for (const Observation& o : p->observations) {
        const Keyframe& okf = map_.keyframes()[static_cast<std::size_t>(o.keyframe)];
        const Feature& f = okf.frame.features[static_cast<std::size_t>(o.feature)];
        problem.observations.push_back({o.keyframe, id, f.px, sigma(f.level)});
        if (!problem.poses.count(o.keyframe)) {
          problem.poses[o.keyframe] = okf.T_cam_map;
          problem.pose_fixed[o.keyframe] = !free_set.count(o.keyframe) || o.keyframe < settings_.global_ba_fixed_keyframes;
        }
      }
    }
  }
  // Monocular gauge: the first keyframe is fixed; the remaining scale freedom is held by the
  // damping of Levenberg-Marquardt (the map is up to scale anyway).
  if (problem.points.empty()) return;
  if (settings_.gravity_sigma_rad > 0 && map_.down_map()) {
    // The gravity prior: every keyframe of the problem that came with an attitude; the map's gravity
    // direction is refined by global adjustments only (a local window of ~2 s of flight at one
    // heading cannot tell a tilted map from a tilted IMU).
    problem.gravity_sigma_rad = settings_.gravity_sigma_rad;
    problem.down_map = map_.down_map();
    problem.down_map_fixed = !global;
    for (const auto& [id, T] : problem.poses) {
      if (const auto& down = map_.keyframes()[static_cast<std::size_t>(id)].down_cam) problem.down_cam[id] = *down;
    }
  }
  BundleSettings settings;
  settings.max_iterations = max_iterations;
  const BundleReport report = solve_bundle(camera_, problem, settings, settings_.threaded ? &abort_ : nullptr);
  if (report.aborted || report.iterations == 0) return;

  std::unique_lock lock(map_.mutex());
  // Each moved keyframe's correction (new map coordinates = G * old, for what is attached to it), so
  // that the tracker carries its pose over with its reference keyframe instead of searching the
  // moved points from a pose in the old map (which lost frames after adjustments).
  std::vector<Similarity3> correction(map_.keyframes().size());
  for (const auto& [id, T] : problem.poses) {
    if (problem.pose_fixed[id]) continue;
    Eigen::Isometry3d& pose = map_.keyframes_mutable()[static_cast<std::size_t>(id)].T_cam_map;
    correction[static_cast<std::size_t>(id)] = Similarity3::from_rigid(T.inverse() * pose);
    pose = T;
  }
  map_.record_correction(std::move(correction));
  if (problem.down_map && !problem.down_map_fixed) map_.set_down_map(*problem.down_map);
  auto& points = map_.points_mutable();
  for (const auto& [id, p] : problem.points) {
    auto it = points.find(id);
    if (it != points.end() && p.allFinite()) it->second.p_map = p;
  }
  // Outliers after adjustment: observations beyond the chi-square gate or behind the camera.
  int removed = 0;
  for (const BundleObservation& o : problem.observations) {
    const MapPoint* p = map_.point(o.point);
    if (!p) continue;
    const Eigen::Vector3d pc = map_.keyframes()[static_cast<std::size_t>(o.keyframe)].T_cam_map * p->p_map;
    const auto px = camera_.project(pc);
    if (!px || (*px - o.px).squaredNorm() > kChi2 * o.sigma * o.sigma) {
      map_.remove_observation(o.point, o.keyframe);
      ++removed;
    }
  }
  std::lock_guard stats_lock(mutex_);
  stats_.observations_removed += removed;
}

void LocalMapper::adjust_initial_map() { adjust({}, true, 20); }

void LocalMapper::carry_over_corrections(Keyframe& keyframe) const {
  // Threaded mode: the tracker computed this pose before a loop correction it had not seen yet.
  for (const MapCorrection* c : map_.corrections_since(keyframe.map_generation)) {
    const auto ref = static_cast<std::size_t>(keyframe.tracking_reference);
    if (keyframe.tracking_reference < 0 || ref >= c->keyframe_correction.size()) continue;
    keyframe.T_cam_map = (Similarity3::from_rigid(keyframe.T_cam_map) * c->keyframe_correction[ref].inverse()).rigid_pose();
  }
  keyframe.map_generation = map_.generation();
}

void LocalMapper::close_loops(int kf) {
  const auto start = std::chrono::steady_clock::now();
  const LoopReport report = loop_closer_.process(kf);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  {
    std::lock_guard lock(mutex_);
    if (!report.corrected) stats_.loop_search_ms.push_back(ms);
    if (!report.detected) return;
    stats_.loops.push_back(report);
    if (report.corrected) stats_.loop_ms.push_back(ms);
  }
  // The corrected map's points still disagree where the pose graph bent it: a global adjustment
  // settles them (at once in synchronous mode; in threaded mode it is pending after every keyframe).
  if (report.corrected && !settings_.threaded && settings_.global_ba) global_adjustment();
}

void LocalMapper::global_adjustment() {
  if (map_.keyframes().size() < 3 || static_cast<int>(map_.keyframes().size()) > settings_.global_ba_max_keyframes) return;
  adjust({}, true, settings_.global_ba_iterations);
  std::lock_guard lock(mutex_);
  ++stats_.global_ba_runs;
}

}  // namespace labo::slam
