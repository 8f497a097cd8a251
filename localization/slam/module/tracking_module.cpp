#include "localization/slam/module/tracking_module.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "localization/slam/module/keyframe_policy.hpp"
#include "localization/slam/optimize/se3.hpp"
#include "localization/slam/slam_settings.hpp"

namespace labo::slam {

TrackingModule::TrackingModule(const IdealCamera& camera, const SlamSettings& settings, const SlamMap& map,
                               const LocalMapper& mapper)
    : camera_(camera),
      settings_(settings),
      map_(map),
      mapper_(mapper),
      tracker_(camera, tracker_settings(settings)),
      relocalizer_(camera) {}

void TrackingModule::start(Seconds reference_t, Seconds t) {
  clear_tracking();
  state_ = TrackingState::Good;
  motion_.start(map_.keyframes()[0].T_cam_map, reference_t, map_.keyframes()[1].T_cam_map, t);
  reference_keyframe_ = 1;
  last_keyframe_t_ = t;
}

void TrackingModule::clear() {
  clear_tracking();
  state_ = TrackingState::Initializing;
}

void TrackingModule::relocalize_in_new_map() {
  clear_tracking();
  relocalizing_ = true;
  state_ = TrackingState::Lost;
}

void TrackingModule::clear_tracking() {
  motion_.clear();
  bad_frames_ = 0;
  relocalizing_ = false;
  reference_keyframe_ = -1;
  std::shared_lock lock(map_.mutex());
  map_generation_ = map_.generation();
}

TrackedFrame TrackingModule::track(const CurrentFrame& frame, const std::optional<Eigen::Isometry3d>& prior) {
  TrackedFrame out;
  SlamResult& result = out.result;
  follow_map_corrections();
  const std::optional<GravityPrior> gravity = gravity_prior(frame);
  result.gravity_used = gravity.has_value();
  std::optional<PosePrediction> prediction = predict_pose(frame, prior);
  if (!prediction) {
    result.state = TrackingState::Lost;
    result.reason = "lost: relocalizing against " + std::to_string(map_.keyframes().size()) + " keyframes";
    return out;
  }
  TrackOutcome o = search_map(frame, prediction->T_cam_map, prediction->coarse, gravity);
  if (o.map_generation != map_generation_ && !relocalizing_) follow_concurrent_correction(frame, gravity, *prediction, o);
  if (!prediction->coarse && !relocalizing_ && (!o.pose_valid || o.found < settings_.min_found_good)) {
    widen_search(frame, gravity, *prediction, o);
  }
  result.points_found = o.found;
  result.points_attempted = o.attempted;
  result.misses = {o.search.no_feature, o.search.too_far, o.search.ambiguous, o.search.taken, o.pose_outliers};
  result.quality = o.attempted > 0 ? static_cast<double>(o.found) / o.attempted : 0.0;
  const TrackingState frame_state = judge_quality(o, result.quality);
  if (frame_state == TrackingState::Lost) {
    lose_frame(o, result);
    return out;
  }
  accept_pose(o, frame_state, frame.t, result);
  if (keyframe_wanted(o, frame_state, frame.t)) {
    out.new_keyframe = make_keyframe(o, frame);
    result.keyframe_added = true;
  }
  return out;
}

std::optional<Similarity3> TrackingModule::follow_map_corrections() {
  // A loop correction moved the map under the tracker: carry the motion model's poses over with the
  // reference keyframe's correction (the part of the map the camera is looking at). Returns what
  // was applied (pose' = rigid part of pose * returned), if anything.
  std::shared_lock lock(map_.mutex());
  if (map_.generation() == map_generation_) return std::nullopt;
  const std::vector<const MapCorrection*> corrections = map_.corrections_since(map_generation_);
  const bool complete = !corrections.empty() && corrections.back()->generation == map_.generation() &&
                        corrections.front()->generation == map_generation_ + 1;
  map_generation_ = map_.generation();
  if (!complete || reference_keyframe_ < 0) {
    // Too far behind to carry the poses over: find the map again.
    motion_.clear();
    relocalizing_ = true;
    return std::nullopt;
  }
  Similarity3 G_inv;
  for (const MapCorrection* c : corrections) {
    if (static_cast<std::size_t>(reference_keyframe_) < c->keyframe_correction.size()) {
      G_inv = G_inv * c->keyframe_correction[static_cast<std::size_t>(reference_keyframe_)].inverse();
    }
  }
  motion_.follow(G_inv);
  return G_inv;
}

std::optional<GravityPrior> TrackingModule::gravity_prior(const CurrentFrame& frame) const {
  if (!frame.down_cam || !settings_.gravity_in_tracking) return std::nullopt;
  std::shared_lock lock(map_.mutex());
  if (!map_.down_map()) return std::nullopt;
  return GravityPrior{*map_.down_map(), *frame.down_cam, settings_.gravity_sigma_deg * M_PI / 180.0};
}

std::optional<TrackingModule::PosePrediction> TrackingModule::predict_pose(const CurrentFrame& frame,
                                                                           const std::optional<Eigen::Isometry3d>& prior) {
  PosePrediction p{.T_cam_map = motion_.last().value_or(Eigen::Isometry3d::Identity()), .coarse = true};
  if (relocalizing_) {
    // Searched tight around the relocalizer's pose (or the caller's when the relocalizer found none).
    const std::optional<RelocalizationCandidate> reloc =
        relocalizer_.relocalize(map_, frame.features, small_blurry_image(frame.gray));
    if (!reloc && !prior) return std::nullopt;
    if (reloc) {
      p.T_cam_map = reloc->T_cam_map;
      reference_keyframe_ = reloc->keyframe;
    } else {
      p.T_cam_map = *prior;
    }
    p.coarse = false;
  } else if (prior) {
    p.T_cam_map = *prior;
  } else if (const std::optional<Eigen::Isometry3d> step = motion_.step_to(frame.t)) {
    p.T_cam_map = *step * *motion_.last();
    // PTAM switches the coarse stage off when the camera barely moves: less jitter.
    p.coarse = rotation_angle(*step) * camera_.fx() + step->translation().norm() * camera_.fx() > 4.0;
  }
  return p;
}

TrackOutcome TrackingModule::search_map(const CurrentFrame& frame, const Eigen::Isometry3d& T_cam_map, bool coarse,
                                        const std::optional<GravityPrior>& gravity) {
  return tracker_.track(map_, frame.features, frame.grid, frame.pyramid, T_cam_map, reference_keyframe_, coarse, gravity);
}

void TrackingModule::follow_concurrent_correction(const CurrentFrame& frame, const std::optional<GravityPrior>& gravity,
                                                  PosePrediction& prediction, TrackOutcome& o) {
  // The mapper corrected the map between our prior and the search. An adjustment moves the map by a
  // fraction of a pixel: the pose found in the old map is carried over. A loop correction bends it:
  // carry the prior over and search again (once per loop closure at most).
  if (const std::optional<Similarity3> G_inv = follow_map_corrections()) {
    // How far the correction moves the camera, in pixels at the scene's depth.
    const Eigen::Isometry3d G = G_inv->rigid_pose();
    const Eigen::Vector3d centre = o.T_cam_map.inverse().translation();
    const double moved = (G * centre - centre).norm() / std::max(o.mean_depth, 1e-3) + rotation_angle(G);
    const bool small = moved * camera_.fx() < 1.0;
    if (small && o.pose_valid) {
      o.T_cam_map = (Similarity3::from_rigid(o.T_cam_map) * *G_inv).rigid_pose();
      return;
    }
    prediction.T_cam_map = (Similarity3::from_rigid(prediction.T_cam_map) * *G_inv).rigid_pose();
  }
  o = search_map(frame, prediction.T_cam_map, prediction.coarse, gravity);
}

void TrackingModule::widen_search(const CurrentFrame& frame, const std::optional<GravityPrior>& gravity,
                                  const PosePrediction& prediction, TrackOutcome& o) {
  // The drone tilts to start or stop a manoeuvre: 5 deg in one frame is ~50 px, beyond the fine
  // radius. Searched again coarse to fine from the same prior; kept when it finds more.
  TrackOutcome wide = search_map(frame, prediction.T_cam_map, true, gravity);
  if (wide.pose_valid && wide.found > o.found && wide.map_generation == o.map_generation) o = std::move(wide);
}

TrackingState TrackingModule::judge_quality(const TrackOutcome& o, double quality) const {
  TrackingState frame_state = TrackingState::Lost;
  if (o.pose_valid && quality >= settings_.quality_good && o.found >= settings_.min_found_good) {
    frame_state = TrackingState::Good;
  } else if (o.pose_valid && quality >= settings_.quality_lost && o.found >= settings_.min_found_good / 2) {
    frame_state = TrackingState::Dodgy;
  }
  if (relocalizing_ && frame_state != TrackingState::Good) frame_state = TrackingState::Lost;  // confirm with a good frame
  return frame_state;
}

void TrackingModule::lose_frame(const TrackOutcome& o, SlamResult& result) {
  ++bad_frames_;
  if (bad_frames_ >= settings_.lost_after_bad_frames) relocalizing_ = true;
  state_ = TrackingState::Lost;
  result.state = TrackingState::Lost;
  result.reason = relocalizing_ ? "lost: relocalizing" : "tracking failed (" + std::to_string(o.found) + " points)";
}

void TrackingModule::accept_pose(const TrackOutcome& o, TrackingState frame_state, Seconds t, SlamResult& result) {
  result.relocalized = relocalizing_;
  // After a relocalization the motion model's velocity is the mean over the loss (from the last
  // pose before it to this one), or none when a map correction cleared that pose.
  relocalizing_ = false;
  bad_frames_ = 0;
  state_ = frame_state;
  result.state = frame_state;
  result.T_cam_map = o.T_cam_map;
  if (frame_state == TrackingState::Dodgy) result.reason = "dodgy: few points found";
  motion_.accept(o.T_cam_map, t);
  if (o.reference_keyframe >= 0) reference_keyframe_ = o.reference_keyframe;
}

bool TrackingModule::keyframe_wanted(const TrackOutcome& o, TrackingState frame_state, Seconds t) const {
  // Which frames may and should become keyframes: module/keyframe_policy (Dodgy frames included
  // when their pose is still pinned: a map starved of keyframes spirals down to lost).
  if (t - last_keyframe_t_ < settings_.keyframe_min_interval_s) return false;
  if (static_cast<int>(map_.keyframes().size()) >= settings_.max_keyframes) return false;
  if (mapper_.queued() > 0) return false;  // the mapper is still busy with the previous one
  KeyframeCandidate c;
  c.state = frame_state;
  c.found = o.found;
  c.attempted = o.attempted;
  c.reference_shared = o.reference_shared;
  c.reference_points = o.reference_points;
  c.mean_depth = o.mean_depth;
  c.nearest_keyframe_distance = 1e9;
  {
    std::shared_lock lock(map_.mutex());
    const Eigen::Vector3d centre = o.T_cam_map.inverse().translation();
    for (const Keyframe& kf : map_.keyframes()) {
      c.nearest_keyframe_distance = std::min(c.nearest_keyframe_distance, (kf.center() - centre).norm());
    }
  }
  return keyframe_eligible(c, settings_) && keyframe_needed(c, settings_);
}

Keyframe TrackingModule::make_keyframe(const TrackOutcome& o, const CurrentFrame& frame) {
  Keyframe kf;
  kf.t = frame.t;
  kf.T_cam_map = o.T_cam_map;
  kf.frame = frame.features;
  kf.point_of_feature.assign(frame.features.size(), kNoPoint);
  for (std::size_t i = 0; i < o.matches.size(); ++i) {
    const auto [feature, id] = o.matches[i];
    kf.point_of_feature[static_cast<std::size_t>(feature)] = id;
    // The keyframe measures its tracked points where the tracker did (patch-aligned when it could).
    Feature& f = kf.frame.features[static_cast<std::size_t>(feature)];
    f.image_px = o.match_image_px[i].cast<float>();
    f.px = camera_.ideal_from_image(o.match_image_px[i].x(), o.match_image_px[i].y());
  }
  kf.pyramid = owned_pyramid(frame.pyramid);
  kf.small_image = small_blurry_image(frame.gray);
  kf.map_generation = map_generation_;
  kf.tracking_reference = reference_keyframe_;
  kf.down_cam = frame.down_cam;
  last_keyframe_t_ = frame.t;
  return kf;
}

}  // namespace labo::slam
