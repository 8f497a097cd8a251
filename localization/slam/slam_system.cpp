#include "localization/slam/slam_system.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "core/frames.hpp"
#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/feature/feature_extractor.hpp"
#include "localization/slam/initialize/map_initializer.hpp"
#include "localization/slam/initialize/map_start.hpp"
#include "localization/slam/io/map_file.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/module/relocalizer.hpp"
#include "localization/slam/module/tracking_module.hpp"
#include "localization/slam/slam_settings.hpp"

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

const PinholeCamera& validated(const PinholeCamera& camera) {
  validate(camera.intrinsics(), "slam");
  return camera;
}

}  // namespace

// The facade's state: the modules, the current frame, and what initialization keeps of its
// reference frame. track() is: refuse_input, read_frame, then initialize (until the map starts) or
// track_map (module/tracking_module) and hand_to_mapper.
struct SlamSystem::Impl {
  Impl(const PinholeCamera& cam, const SlamSettings& s)
      : settings(s),
        camera(validated(cam)),
        extractor(camera, extractor_settings(s)),
        grid(camera.ideal_min(), camera.ideal_max(), 24.0),
        initializer(camera, initializer_settings(s)),
        mapper(std::make_unique<LocalMapper>(camera, map, mapper_settings(s))),
        tracking(camera, s, map, *mapper) {}

  SlamResult track(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior,
                   const std::optional<GravityMeasurement>& gravity);
  std::optional<std::string> refuse_input(const cv::Mat& gray, Seconds t, const std::optional<GravityMeasurement>& gravity) const;
  void read_frame(const cv::Mat& gray, const std::optional<GravityMeasurement>& gravity);
  SlamResult initialize(const cv::Mat& gray, Seconds t);
  void create_map(const InitialMap& init, const cv::Mat& gray, Seconds t);
  SlamResult track_map(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior);
  void hand_to_mapper(Keyframe keyframe);

  SlamSettings settings;
  IdealCamera camera;
  SlamMap map;
  FeatureExtractor extractor;
  FeatureGrid grid;
  MapInitializer initializer;
  std::unique_ptr<LocalMapper> mapper;
  TrackingModule tracking;
  FrameFeatures frame;
  std::optional<Eigen::Vector3d> frame_down_cam;  // this frame's IMU attitude, when given

  std::optional<Seconds> last_t;
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
  if (const auto refusal = refuse_input(gray, t, gravity)) {
    // Refused frames change nothing: not the map, not the motion model, not the state.
    SlamResult result;
    result.state = TrackingState::Lost;
    result.reason = "frame refused: " + *refusal;
    return result;
  }
  last_t = t;
  read_frame(gray, gravity);
  SlamResult result = tracking.state() == TrackingState::Initializing ? initialize(gray, t) : track_map(gray, t, prior);
  // Mapping done inline (synchronous mode, map start) is mapping time, not tracking time.
  result.tracking_ms = watch.wall_ms() - inline_mapping_wall_ms;
  result.tracking_cpu_ms = watch.cpu_ms() - inline_mapping_cpu_ms;
  last = result;
  return result;
}

void SlamSystem::Impl::read_frame(const cv::Mat& gray, const std::optional<GravityMeasurement>& gravity) {
  frame_down_cam.reset();
  if (gravity && settings.gravity_sigma_deg > 0) frame_down_cam = gravity->down_cam.normalized();
  extractor.extract(gray, frame);
  grid.build(frame);
}

SlamResult SlamSystem::Impl::initialize(const cv::Mat& gray, Seconds t) {
  const int attempts = initializer.attempts();
  const std::optional<InitialMap> init = initializer.add_frame(frame, grid, t);
  if (initializer.attempts() != attempts) {
    // A new reference frame: keyframe 0 if the map starts from it.
    reference_small_image = small_blurry_image(gray);
    reference_pyramid = owned_pyramid(extractor.pyramid());
    reference_down_cam = frame_down_cam;
  }
  SlamResult result;
  if (!init) {
    result.state = TrackingState::Initializing;
    result.reason = initializer.reason();
    return result;
  }
  const Stopwatch mapping_watch;
  create_map(*init, gray, t);
  inline_mapping_wall_ms += mapping_watch.wall_ms();
  inline_mapping_cpu_ms += mapping_watch.cpu_ms();
  result.state = tracking.state();
  result.T_cam_map = tracking.last_pose();
  result.points_found = result.points_attempted = static_cast<int>(init->points.size());
  result.quality = 1.0;
  result.keyframe_added = true;
  return result;
}

void SlamSystem::Impl::create_map(const InitialMap& init, const cv::Mat& gray, Seconds t) {
  Keyframe reference;
  reference.small_image = reference_small_image.clone();
  reference.pyramid = reference_pyramid;
  reference.down_cam = reference_down_cam;
  Keyframe current;
  current.t = t;
  current.frame = frame;
  current.small_image = small_blurry_image(gray);
  current.pyramid = owned_pyramid(extractor.pyramid());
  current.down_cam = frame_down_cam;
  start_map(init, std::move(reference), std::move(current), map, *mapper);
  tracking.start(init.reference_t, t);
}

SlamResult SlamSystem::Impl::track_map(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior) {
  TrackedFrame tracked = tracking.track({.gray = gray,
                                         .t = t,
                                         .features = frame,
                                         .grid = grid,
                                         .pyramid = extractor.pyramid(),
                                         .down_cam = frame_down_cam},
                                        prior);
  if (tracked.new_keyframe) hand_to_mapper(std::move(*tracked.new_keyframe));
  return tracked.result;
}

void SlamSystem::Impl::hand_to_mapper(Keyframe keyframe) {
  const Stopwatch mapping_watch;
  mapper->enqueue(std::move(keyframe));  // returns at once in threaded mode
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
  s.state = impl_->tracking.state();
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
  s.map_bytes = impl_->map.points().size() * sizeof(MapPoint);
  for (const Keyframe& kf : impl_->map.keyframes()) {
    for (const cv::Mat& level : kf.pyramid) s.map_bytes += level.total() * level.elemSize();
    s.map_bytes += kf.small_image.total() * kf.small_image.elemSize();
    s.map_bytes += kf.frame.features.capacity() * sizeof(Feature) + kf.frame.descriptors.capacity() * sizeof(Descriptor) +
                   kf.point_of_feature.capacity() * sizeof(PointId);
  }
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

void SlamSystem::sample_points(std::vector<Eigen::Vector3d>& out, std::size_t max_points) const {
  out.clear();
  if (max_points == 0) return;
  std::shared_lock lock(impl_->map.mutex());
  const std::size_t n = impl_->map.points().size();
  const std::size_t stride = (n + max_points - 1) / max_points;
  std::size_t i = 0;
  for (const auto& [id, p] : impl_->map.points()) {
    if (i++ % stride == 0 && out.size() < max_points) out.push_back(p.p_map);
  }
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
  impl_->tracking.clear();
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
  impl_->tracking.relocalize_in_new_map();
  impl_->last = {};
  impl_->last.state = TrackingState::Lost;
  impl_->last.reason = "map loaded: relocalizing";
}

}  // namespace labo::slam
