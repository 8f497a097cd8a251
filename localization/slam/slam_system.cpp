#include "localization/slam/slam_system.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "core/frames.hpp"
#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/feature/feature_extractor.hpp"
#include "localization/slam/initialize/map_initializer.hpp"
#include "localization/slam/io/map_file.hpp"
#include "localization/slam/module/frame_tracker.hpp"
#include "localization/slam/module/keyframe_policy.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/module/relocalizer.hpp"
#include "localization/slam/optimize/se3.hpp"

namespace labo::slam {

Eigen::Vector3d gravity_down_in_camera(double roll_rad, double pitch_rad, const Eigen::Isometry3d& T_body_cam) {
  const Eigen::Matrix3d R_world_body = rotation_from_ypr(0.0, pitch_rad, roll_rad);
  return T_body_cam.linear().transpose() * (R_world_body.transpose() * -Eigen::Vector3d::UnitZ());
}

std::string to_string(TrackingState state) {
  switch (state) {
    case TrackingState::Initializing: return "initializing";
    case TrackingState::Good: return "good";
    case TrackingState::Dodgy: return "dodgy";
    case TrackingState::Lost: return "lost";
  }
  return "unknown";
}

namespace {

// CPU time of the calling thread, ms: the "one core" cost, independent of how loaded the machine is.
// A measurement only; nothing in the algorithm depends on it.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Stopwatch {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  double cpu = thread_cpu_ms();
  double wall_ms() const { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall).count(); }
  double cpu_ms() const { return thread_cpu_ms() - cpu; }
};

void validate_settings(const SlamSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("slam settings: " + what); };
  if (s.pyramid_levels != 4) fail("pyramid_levels must be 4");
  if (!(s.pyramid_scale >= 1.1 && s.pyramid_scale <= 2.5)) fail("pyramid_scale must be in [1.1, 2.5]");
  if (s.max_features < 100 || s.max_features > 5000) fail("max_features must be in [100, 5000]");
  if (s.max_points_searched < 50 || s.max_points_searched > 5000) fail("max_points_searched must be in [50, 5000]");
  if (s.fast_threshold < 5 || s.fast_threshold > 100) fail("fast_threshold must be in [5, 100]");
  if (!(s.smoothing_sigma_px >= 0 && s.smoothing_sigma_px <= 3)) fail("smoothing_sigma_px must be in [0, 3]");
  if (!(s.quality_lost > 0 && s.quality_lost < s.quality_good && s.quality_good < 1)) {
    fail("need 0 < quality_lost < quality_good < 1");
  }
  if (s.keyframe_min_points_dodgy < 0) fail("keyframe_min_points_dodgy must be >= 0 (0: keyframes from Good frames only)");
  if (s.lost_after_bad_frames < 1) fail("lost_after_bad_frames must be >= 1");
  if (s.local_ba_keyframes < 2) fail("local_ba_keyframes must be >= 2");
  if (s.local_ba_iterations < 1 || s.global_ba_iterations < 1) fail("local_ba_iterations and global_ba_iterations must be >= 1");
  if (s.init_min_points < 20) fail("init_min_points must be >= 20");
  if (!(s.init_min_parallax_px > 0)) fail("init_min_parallax_px must be > 0");
  if (!(s.init_min_parallax_deg > 0 && s.init_min_parallax_deg < 90)) fail("init_min_parallax_deg must be in (0, 90)");
  if (s.global_ba_max_keyframes < 3) fail("global_ba_max_keyframes must be >= 3");
  if (s.global_ba_every < 1) fail("global_ba_every must be >= 1");
  if (s.global_ba_fixed_keyframes < 1 || s.global_ba_fixed_keyframes > 10) fail("global_ba_fixed_keyframes must be in [1, 10]");
  if (!(s.gravity_sigma_deg >= 0 && s.gravity_sigma_deg <= 10)) fail("gravity_sigma_deg must be in [0, 10] (0: no gravity prior)");
  if (!(s.loop_min_gap_s > 0)) fail("loop_min_gap_s must be > 0");
}

// Keyframes keep their own pyramid: the extractor reuses its buffers (and level 0 may be the caller's frame).
std::vector<cv::Mat> copy_pyramid(const std::vector<cv::Mat>& pyramid) {
  std::vector<cv::Mat> out;
  out.reserve(pyramid.size());
  for (const cv::Mat& level : pyramid) out.push_back(level.clone());
  return out;
}

const PinholeCamera& validated(const PinholeCamera& camera) {
  validate(camera.intrinsics(), "slam");
  return camera;
}

}  // namespace

struct SlamSystem::Impl {
  Impl(const PinholeCamera& cam, const SlamSettings& s)
      : settings(s),
        camera(validated(cam)),
        extractor(camera, {.levels = s.pyramid_levels,
                           .scale = s.pyramid_scale,
                           .max_features = s.max_features,
                           .fast_threshold = s.fast_threshold,
                           .fast_threshold_low = 7,
                           .cell_px = 40,
                           .smoothing_sigma_px = s.smoothing_sigma_px}),
        grid(camera.ideal_min(), camera.ideal_max(), 24.0),
        initializer(camera, {.min_parallax_px = s.init_min_parallax_px,
                             .timeout_s = s.init_timeout_s,
                             .search_radius_px = 30.0,
                             .max_hamming = 60,
                             .geometry = {.min_points = s.init_min_points,
                                          .min_parallax_deg = s.init_min_parallax_deg,
                                          .ransac_threshold_px = 1.5,
                                          .homography_ratio = 0.45}}),
        tracker(camera, {.levels = s.pyramid_levels,
                         .level_scale = s.pyramid_scale,
                         .max_points_searched = s.max_points_searched,
                         .coarse_points = s.coarse_points,
                         .coarse_radius_px = s.coarse_radius_px,
                         .fine_radius_px = s.fine_radius_px,
                         .max_hamming = 50,
                         .local_keyframes = 10,
                         .patch_refinement = s.patch_refinement}),
        relocalizer(camera),
        mapper(std::make_unique<LocalMapper>(camera, map, mapper_settings(s))) {}

  static MapperSettings mapper_settings(const SlamSettings& s) {
    MapperSettings m;
    m.threaded = s.mapping_mode == MappingMode::Threaded;
    m.levels = s.pyramid_levels;
    m.level_scale = s.pyramid_scale;
    m.local_ba_keyframes = s.local_ba_keyframes;
    m.local_ba_iterations = s.local_ba_iterations;
    m.global_ba_iterations = s.global_ba_iterations;
    m.global_ba = s.global_ba_when_idle;
    m.global_ba_max_keyframes = s.global_ba_max_keyframes;
    m.global_ba_every = s.global_ba_every;
    m.global_ba_fixed_keyframes = s.global_ba_fixed_keyframes;
    m.cull_points = s.cull_points;
    m.new_point_clearance_px = s.new_point_clearance_px;
    m.patch_refinement = s.patch_refinement;
    m.gravity_sigma_rad = s.gravity_sigma_deg * M_PI / 180.0;
    m.loop.enabled = s.loop_closure;
    m.loop.min_gap_s = s.loop_min_gap_s;
    m.loop.levels = s.pyramid_levels;
    m.loop.level_scale = s.pyramid_scale;
    return m;
  }

  SlamResult track(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior,
                   const std::optional<GravityMeasurement>& gravity);
  std::optional<std::string> refuse_input(const cv::Mat& gray, Seconds t, const std::optional<GravityMeasurement>& gravity) const;
  std::optional<GravityPrior> gravity_prior() const;
  SlamResult initialize(Seconds t);
  SlamResult track_map(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior);
  void accept_pose(const Eigen::Isometry3d& T, Seconds t);
  KeyframeCandidate keyframe_candidate(const TrackOutcome& o, TrackingState frame_state) const;
  bool want_keyframe(const TrackOutcome& o, TrackingState frame_state, Seconds t) const;
  void add_keyframe(const TrackOutcome& o, const cv::Mat& gray, Seconds t);
  void start_map(const InitialMap& init, const cv::Mat& gray, Seconds t);
  void clear_tracking();
  std::optional<Similarity3> follow_map_corrections();

  SlamSettings settings;
  IdealCamera camera;
  SlamMap map;
  FeatureExtractor extractor;
  FeatureGrid grid;
  MapInitializer initializer;
  FrameTracker tracker;
  Relocalizer relocalizer;
  std::unique_ptr<LocalMapper> mapper;
  FrameFeatures frame;
  std::optional<Eigen::Vector3d> frame_down_cam;  // this frame's IMU attitude, when given

  TrackingState state = TrackingState::Initializing;
  std::optional<Seconds> last_t;
  std::optional<Eigen::Isometry3d> last_T, previous_T;
  Seconds last_pose_t = 0, previous_pose_t = 0;
  int bad_frames = 0;
  bool relocalizing = false;
  int reference_keyframe = -1;
  int map_generation = 0;  // the last map correction this tracker's poses follow
  Seconds last_keyframe_t = -1e9;
  cv::Mat reference_small_image;  // of the initializer's reference frame
  std::vector<cv::Mat> reference_pyramid;  // the same frame's pyramid (keyframe 0's)
  std::optional<Eigen::Vector3d> reference_down_cam;  // the same frame's IMU attitude
  SlamResult last;
  double inline_mapping_wall_ms = 0, inline_mapping_cpu_ms = 0;
};

std::optional<std::string> SlamSystem::Impl::refuse_input(const cv::Mat& gray, Seconds t,
                                                         const std::optional<GravityMeasurement>& gravity) const {
  if (gray.empty()) return "empty frame";
  if (gray.type() != CV_8UC1) return "frame must be 8-bit grey (CV_8UC1)";
  if (gray.cols != camera.real().width() || gray.rows != camera.real().height()) {
    return "frame is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) + ", camera is " +
           std::to_string(camera.real().width()) + "x" + std::to_string(camera.real().height());
  }
  if (!std::isfinite(t)) return "timestamp is not a finite number";
  if (last_t && t <= *last_t) {
    return "timestamp " + std::to_string(t) + " s is not after the previous frame's " + std::to_string(*last_t) + " s";
  }
  if (gravity) {
    if (!gravity->down_cam.allFinite() || !(gravity->down_cam.norm() > 0.5 && gravity->down_cam.norm() < 2.0)) {
      return "gravity direction is not a finite unit vector";
    }
    if (!std::isfinite(gravity->t) || std::abs(gravity->t - t) > kGravityMaxOffsetS) {
      return "attitude stamped " + std::to_string(gravity->t) + " s for a frame at " + std::to_string(t) + " s";
    }
  }
  return std::nullopt;
}

SlamResult SlamSystem::Impl::track(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior,
                                   const std::optional<GravityMeasurement>& gravity) {
  const Stopwatch watch;
  inline_mapping_wall_ms = inline_mapping_cpu_ms = 0;
  SlamResult result;
  if (const auto refusal = refuse_input(gray, t, gravity)) {
    // Refused frames change nothing: not the map, not the motion model, not the state.
    result.state = TrackingState::Lost;
    result.reason = "frame refused: " + *refusal;
    return result;
  }
  last_t = t;
  frame_down_cam.reset();
  if (gravity && settings.gravity_sigma_deg > 0) frame_down_cam = gravity->down_cam.normalized();
  extractor.extract(gray, frame);
  grid.build(frame);
  if (state == TrackingState::Initializing) {
    const int attempts = initializer.attempts();
    std::optional<InitialMap> init = initializer.add_frame(frame, grid, t);
    if (initializer.attempts() != attempts) {
      reference_small_image = small_blurry_image(gray);
      reference_pyramid = copy_pyramid(extractor.pyramid());
      reference_down_cam = frame_down_cam;
    }
    if (init) {
      const Stopwatch mapping_watch;
      start_map(*init, gray, t);
      inline_mapping_wall_ms += mapping_watch.wall_ms();
      inline_mapping_cpu_ms += mapping_watch.cpu_ms();
      result.state = state;
      result.T_cam_map = last_T;
      result.points_found = result.points_attempted = static_cast<int>(init->points.size());
      result.quality = 1.0;
      result.keyframe_added = true;
    } else {
      result.state = TrackingState::Initializing;
      result.reason = initializer.reason();
    }
  } else {
    result = track_map(gray, t, prior);
  }
  // Mapping done inline (synchronous mode, map start) is mapping time, not tracking time.
  result.tracking_ms = watch.wall_ms() - inline_mapping_wall_ms;
  result.tracking_cpu_ms = watch.cpu_ms() - inline_mapping_cpu_ms;
  last = result;
  return result;
}

void SlamSystem::Impl::start_map(const InitialMap& init, const cv::Mat& gray, Seconds t) {
  {
    std::unique_lock lock(map.mutex());
    Keyframe first;
    first.t = init.reference_t;
    first.frame = init.reference;
    first.small_image = reference_small_image.clone();
    first.pyramid = reference_pyramid;
    first.down_cam = reference_down_cam;
    const int k0 = map.add_keyframe(std::move(first));
    Keyframe second;
    second.t = t;
    second.T_cam_map = init.T_current_reference;
    second.frame = frame;
    second.small_image = small_blurry_image(gray);
    second.pyramid = copy_pyramid(extractor.pyramid());
    second.down_cam = frame_down_cam;
    const int k1 = map.add_keyframe(std::move(second));
    // The map's gravity direction from the first keyframe's attitude (its camera frame is the map's);
    // global adjustments refine it with every keyframe's.
    if (reference_down_cam) map.set_down_map(*reference_down_cam);
    else if (frame_down_cam) map.set_down_map(init.T_current_reference.linear().transpose() * *frame_down_cam);
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
  mapper->adjust_initial_map();
  // Rescale so that the median depth seen from the first keyframe is 1 (the map's unit).
  {
    std::unique_lock lock(map.mutex());
    std::vector<double> depths;
    for (const auto& [id, p] : map.points()) depths.push_back(p.p_map.z());
    if (!depths.empty()) {
      std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
      const double s = depths[depths.size() / 2] > 1e-9 ? 1.0 / depths[depths.size() / 2] : 1.0;
      for (auto& [id, p] : map.points_mutable()) {
        p.p_map *= s;
        p.reference_distance *= s;
      }
      for (auto& kf : map.keyframes_mutable()) kf.T_cam_map.translation() *= s;
    }
  }
  clear_tracking();
  state = TrackingState::Good;
  last_T = map.keyframes()[1].T_cam_map;
  last_pose_t = t;
  previous_T = map.keyframes()[0].T_cam_map;
  previous_pose_t = init.reference_t;
  reference_keyframe = 1;
  last_keyframe_t = t;
}

void SlamSystem::Impl::clear_tracking() {
  last_T.reset();
  previous_T.reset();
  bad_frames = 0;
  relocalizing = false;
  reference_keyframe = -1;
  std::shared_lock lock(map.mutex());
  map_generation = map.generation();
}

std::optional<Similarity3> SlamSystem::Impl::follow_map_corrections() {
  // A loop correction moved the map under the tracker: carry the motion model's poses over with the
  // reference keyframe's correction (the part of the map the camera is looking at). Returns what
  // was applied (pose' = rigid part of pose * returned), if anything.
  std::shared_lock lock(map.mutex());
  if (map.generation() == map_generation) return std::nullopt;
  const std::vector<const MapCorrection*> corrections = map.corrections_since(map_generation);
  const bool complete = !corrections.empty() && corrections.back()->generation == map.generation() &&
                        corrections.front()->generation == map_generation + 1;
  map_generation = map.generation();
  if (!complete || reference_keyframe < 0) {
    // Too far behind to carry the poses over: find the map again.
    last_T.reset();
    previous_T.reset();
    relocalizing = true;
    return std::nullopt;
  }
  Similarity3 G_inv;
  for (const MapCorrection* c : corrections) {
    if (static_cast<std::size_t>(reference_keyframe) < c->keyframe_correction.size()) {
      G_inv = G_inv * c->keyframe_correction[static_cast<std::size_t>(reference_keyframe)].inverse();
    }
  }
  if (last_T) last_T = (Similarity3::from_rigid(*last_T) * G_inv).rigid_pose();
  if (previous_T) previous_T = (Similarity3::from_rigid(*previous_T) * G_inv).rigid_pose();
  return G_inv;
}

std::optional<GravityPrior> SlamSystem::Impl::gravity_prior() const {
  if (!frame_down_cam || !settings.gravity_in_tracking) return std::nullopt;
  std::shared_lock lock(map.mutex());
  if (!map.down_map()) return std::nullopt;
  return GravityPrior{*map.down_map(), *frame_down_cam, settings.gravity_sigma_deg * M_PI / 180.0};
}

void SlamSystem::Impl::accept_pose(const Eigen::Isometry3d& T, Seconds t) {
  previous_T = last_T;
  previous_pose_t = last_pose_t;
  last_T = T;
  last_pose_t = t;
}

SlamResult SlamSystem::Impl::track_map(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior) {
  follow_map_corrections();
  const std::optional<GravityPrior> gravity = gravity_prior();
  SlamResult result;
  result.gravity_used = gravity.has_value();
  bool coarse = true;
  Eigen::Isometry3d guess = last_T.value_or(Eigen::Isometry3d::Identity());
  std::optional<RelocalizationCandidate> reloc;
  if (relocalizing) {
    reloc = relocalizer.relocalize(map, frame, small_blurry_image(gray));
    if (!reloc && !prior) {
      result.state = TrackingState::Lost;
      result.reason = "lost: relocalizing against " + std::to_string(map.keyframes().size()) + " keyframes";
      return result;
    }
    if (reloc) {
      guess = reloc->T_cam_map;
      reference_keyframe = reloc->keyframe;
    } else {
      guess = *prior;
    }
    coarse = false;
  } else if (prior) {
    guess = *prior;
  } else if (last_T && previous_T && last_pose_t > previous_pose_t) {
    // Decaying constant-velocity model, scaled to this frame's interval.
    const Eigen::Isometry3d delta = *last_T * previous_T->inverse();
    const double fraction = 0.9 * (t - last_pose_t) / (last_pose_t - previous_pose_t);
    const Eigen::Isometry3d step = scale_motion(delta, std::min(fraction, 3.0));
    guess = step * *last_T;
    // PTAM switches the coarse stage off when the camera barely moves: less jitter.
    coarse = rotation_angle(step) * camera.fx() + step.translation().norm() * camera.fx() > 4.0;
  }
  TrackOutcome o = tracker.track(map, frame, grid, extractor.pyramid(), guess, reference_keyframe, coarse, gravity);
  if (o.map_generation != map_generation && !relocalizing) {
    // The mapper corrected the map between our prior and the tracking pass. An adjustment moves the
    // map by a fraction of a pixel: the pose found in the old map is carried over. A loop correction
    // bends it: carry the prior over and track again (once per loop closure at most).
    if (const auto G_inv = follow_map_corrections()) {
      // How far the correction moves the camera, in pixels at the scene's depth.
      const Eigen::Isometry3d G = G_inv->rigid_pose();
      const Eigen::Vector3d centre = o.T_cam_map.inverse().translation();
      const double moved = (G * centre - centre).norm() / std::max(o.mean_depth, 1e-3) + rotation_angle(G);
      const bool small = moved * camera.fx() < 1.0;
      if (small && o.pose_valid) {
        o.T_cam_map = (Similarity3::from_rigid(o.T_cam_map) * *G_inv).rigid_pose();
      } else {
        guess = (Similarity3::from_rigid(guess) * *G_inv).rigid_pose();
        o = tracker.track(map, frame, grid, extractor.pyramid(), guess, reference_keyframe, coarse, gravity);
      }
    } else {
      o = tracker.track(map, frame, grid, extractor.pyramid(), guess, reference_keyframe, coarse, gravity);
    }
  }
  if (!coarse && !relocalizing && (!o.pose_valid || o.found < settings.min_found_good)) {
    // The motion model said "barely moving" but the view jumped (the drone tilts to start or stop a
    // manoeuvre: 5 deg in one frame is ~50 px): search again coarse to fine from the same prior.
    TrackOutcome wide = tracker.track(map, frame, grid, extractor.pyramid(), guess, reference_keyframe, true, gravity);
    if (wide.pose_valid && wide.found > o.found && wide.map_generation == o.map_generation) o = std::move(wide);
  }
  result.points_found = o.found;
  result.points_attempted = o.attempted;
  result.misses = {o.search.no_feature, o.search.too_far, o.search.ambiguous, o.search.taken, o.pose_outliers};
  result.quality = o.attempted > 0 ? static_cast<double>(o.found) / o.attempted : 0.0;
  TrackingState frame_state = TrackingState::Lost;
  if (o.pose_valid && result.quality >= settings.quality_good && o.found >= settings.min_found_good) {
    frame_state = TrackingState::Good;
  } else if (o.pose_valid && result.quality >= settings.quality_lost && o.found >= settings.min_found_good / 2) {
    frame_state = TrackingState::Dodgy;
  }
  if (relocalizing && frame_state != TrackingState::Good) frame_state = TrackingState::Lost;  // confirm with a good frame
  if (frame_state == TrackingState::Lost) {
    ++bad_frames;
    if (bad_frames >= settings.lost_after_bad_frames) relocalizing = true;
    state = TrackingState::Lost;
    result.state = TrackingState::Lost;
    result.reason = relocalizing ? "lost: relocalizing" : "tracking failed (" + std::to_string(o.found) + " points)";
    return result;
  }
  result.relocalized = relocalizing;
  if (relocalizing) {
    // A relocalized pose has no velocity: restart the motion model from it.
    previous_T.reset();
  }
  relocalizing = false;
  bad_frames = 0;
  state = frame_state;
  result.state = frame_state;
  result.T_cam_map = o.T_cam_map;
  if (frame_state == TrackingState::Dodgy) result.reason = "dodgy: few points found";
  accept_pose(o.T_cam_map, t);
  if (o.reference_keyframe >= 0) reference_keyframe = o.reference_keyframe;
  // Which frames may and should become keyframes: module/keyframe_policy (Dodgy frames included
  // when their pose is still pinned: a map starved of keyframes spirals down to lost).
  if (want_keyframe(o, frame_state, t)) {
    add_keyframe(o, gray, t);
    result.keyframe_added = true;
  }
  return result;
}

KeyframeCandidate SlamSystem::Impl::keyframe_candidate(const TrackOutcome& o, TrackingState frame_state) const {
  KeyframeCandidate c;
  c.state = frame_state;
  c.found = o.found;
  c.attempted = o.attempted;
  c.reference_shared = o.reference_shared;
  c.reference_points = o.reference_points;
  c.mean_depth = o.mean_depth;
  c.nearest_keyframe_distance = 1e9;
  std::shared_lock lock(map.mutex());
  const Eigen::Vector3d centre = o.T_cam_map.inverse().translation();
  for (const Keyframe& kf : map.keyframes()) {
    c.nearest_keyframe_distance = std::min(c.nearest_keyframe_distance, (kf.center() - centre).norm());
  }
  return c;
}

bool SlamSystem::Impl::want_keyframe(const TrackOutcome& o, TrackingState frame_state, Seconds t) const {
  if (t - last_keyframe_t < settings.keyframe_min_interval_s) return false;
  if (static_cast<int>(map.keyframes().size()) >= settings.max_keyframes) return false;
  if (mapper->queued() > 0) return false;  // the mapper is still busy with the previous one
  const KeyframeCandidate candidate = keyframe_candidate(o, frame_state);
  return keyframe_eligible(candidate, settings) && keyframe_needed(candidate, settings);
}

void SlamSystem::Impl::add_keyframe(const TrackOutcome& o, const cv::Mat& gray, Seconds t) {
  Keyframe kf;
  kf.t = t;
  kf.T_cam_map = o.T_cam_map;
  kf.frame = frame;
  kf.point_of_feature.assign(frame.size(), kNoPoint);
  for (std::size_t i = 0; i < o.matches.size(); ++i) {
    const auto [feature, id] = o.matches[i];
    kf.point_of_feature[static_cast<std::size_t>(feature)] = id;
    // The keyframe measures its tracked points where the tracker did (patch-aligned when it could).
    Feature& f = kf.frame.features[static_cast<std::size_t>(feature)];
    f.image_px = o.match_image_px[i].cast<float>();
    f.px = camera.ideal_from_image(o.match_image_px[i].x(), o.match_image_px[i].y());
  }
  kf.pyramid = copy_pyramid(extractor.pyramid());
  kf.small_image = small_blurry_image(gray);
  kf.map_generation = map_generation;
  kf.tracking_reference = reference_keyframe;
  kf.down_cam = frame_down_cam;
  last_keyframe_t = t;
  const Stopwatch mapping_watch;
  mapper->enqueue(std::move(kf));  // returns at once in threaded mode
  inline_mapping_wall_ms += mapping_watch.wall_ms();
  inline_mapping_cpu_ms += mapping_watch.cpu_ms();
}

SlamSystem::SlamSystem(const PinholeCamera& camera, const SlamSettings& settings) {
  validate_settings(settings);
  impl_ = std::make_unique<Impl>(camera, settings);
}

SlamSystem::~SlamSystem() = default;

SlamResult SlamSystem::track(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior_T_cam_map,
                             const std::optional<GravityMeasurement>& gravity) {
  return impl_->track(gray, t, prior_T_cam_map, gravity);
}

SlamStatus SlamSystem::status() const {
  SlamStatus s;
  s.state = impl_->state;
  s.quality = impl_->last.quality;
  s.points_found = impl_->last.points_found;
  s.reason = impl_->last.reason;
  const MapperStats stats = impl_->mapper->stats();
  s.mapping_queue = impl_->mapper->queued();
  s.local_ba_runs = stats.local_ba_runs;
  s.global_ba_runs = stats.global_ba_runs;
  s.loops_corrected = static_cast<int>(stats.loop_ms.size());
  std::shared_lock lock(impl_->map.mutex());
  s.map_points = static_cast<int>(impl_->map.points().size());
  s.keyframes = static_cast<int>(impl_->map.keyframes().size());
  // At most ~2000 points for the top-down view.
  const std::size_t stride = std::max<std::size_t>(1, impl_->map.points().size() / 2000);
  std::size_t i = 0;
  for (const auto& [id, p] : impl_->map.points()) {
    if (i++ % stride == 0) s.points_map.push_back(p.p_map);
  }
  for (const Keyframe& kf : impl_->map.keyframes()) {
    s.keyframes_T_map_cam.push_back(kf.T_cam_map.inverse());
    s.keyframe_times.push_back(kf.t);
  }
  s.down_map = impl_->map.down_map();
  return s;
}

MappingStatistics SlamSystem::mapping_statistics() const {
  const MapperStats stats = impl_->mapper->stats();
  MappingStatistics out;
  out.keyframe_ms = stats.keyframe_ms;
  out.points_created = stats.points_created;
  out.observations_removed = stats.observations_removed;
  out.clearance_skips = stats.clearance_skips;
  out.global_ba_runs = stats.global_ba_runs;
  out.loops_detected = static_cast<int>(stats.loops.size());
  out.loops_corrected = static_cast<int>(stats.loop_ms.size());
  for (const LoopReport& l : stats.loops) out.points_fused += l.points_fused;
  out.loop_ms = stats.loop_ms;
  out.loop_search_ms = stats.loop_search_ms;
  out.loops = stats.loops;
  return out;
}

void SlamSystem::reset() {
  impl_->mapper->wait_idle();
  {
    std::unique_lock lock(impl_->map.mutex());
    impl_->map.clear();
  }
  impl_->initializer.reset();
  impl_->clear_tracking();
  impl_->state = TrackingState::Initializing;
  impl_->last = {};
}

void SlamSystem::wait_for_mapping() { impl_->mapper->wait_idle(); }

const PinholeCamera& SlamSystem::camera() const { return impl_->camera.real(); }

void SlamSystem::save_map(const std::filesystem::path& file) const {
  impl_->mapper->wait_idle();
  std::shared_lock lock(impl_->map.mutex());
  write_map_file(file, impl_->camera.real().intrinsics(), impl_->map);
}

void SlamSystem::load_map(const std::filesystem::path& file) {
  SlamMap loaded;
  read_map_file(file, impl_->camera.real().intrinsics(), loaded);  // throws before touching our map
  impl_->mapper->wait_idle();
  {
    std::unique_lock lock(impl_->map.mutex());
    impl_->map.clear();
    for (Keyframe& kf : loaded.keyframes_mutable()) {
      std::vector<PointId> links = std::move(kf.point_of_feature);
      const int id = impl_->map.add_keyframe(std::move(kf));
      impl_->map.keyframes_mutable()[static_cast<std::size_t>(id)].point_of_feature = std::move(links);
    }
    for (auto& [id, p] : loaded.points_mutable()) impl_->map.points_mutable().emplace(id, std::move(p));
    impl_->map.set_next_point_id(loaded.next_point_id());
    for (const LoopEdge& e : loaded.loop_edges()) impl_->map.add_loop_edge(e);
    if (loaded.down_map()) impl_->map.set_down_map(*loaded.down_map());
  }
  impl_->clear_tracking();
  impl_->relocalizing = true;
  impl_->state = TrackingState::Lost;
  impl_->last = {};
  impl_->last.state = TrackingState::Lost;
  impl_->last.reason = "map loaded: relocalizing";
}

}  // namespace labo::slam
