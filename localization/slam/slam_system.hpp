#pragma once
// SlamSystem: monocular keyframe SLAM for the AR.Drone's front camera (PTAM-style: tracking on every
// frame, mapping on keyframes), written from the published descriptions of PTAM and ORB-SLAM; none
// of their code. Poses are T_cam_map (map -> camera), the map's scale is arbitrary (the state estimator's
// ScaleEstimator makes it metric).
//
// Threading: track() is called from one thread. In MappingMode::Threaded the mapper runs in its own
// thread and never blocks tracking for longer than a map lock; in MappingMode::Synchronous the same
// mapper code runs inline inside track(), so lockstep runs are deterministic.
#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/camera_model.hpp"
#include "core/time.hpp"
#include "localization/slam/module/loop_report.hpp"

namespace labo::slam {

enum class TrackingState { Initializing, Good, Dodgy, Lost };
std::string to_string(TrackingState state);

enum class MappingMode { Threaded, Synchronous };

struct SlamSettings {
  MappingMode mapping_mode = MappingMode::Threaded;
  int pyramid_levels = 4;            // the SLAM design's four levels; checked
  double pyramid_scale = 1.5;        // between levels
  int max_features = 1000;           // per frame, over all levels
  int fast_threshold = 20;           // FAST intensity threshold (falls back to 7 in flat cells)
  double smoothing_sigma_px = 1.2;   // Gaussian smoothing before FAST (0: none), see docs/slam.md
  int max_points_searched = 800;     // fine stage
  bool patch_refinement = false;     // fine matches aligned to sub-pixel with the points' warped patches (docs/slam.md)
  int coarse_points = 60;            // coarse stage, from levels >= 2
  double coarse_radius_px = 30.0;    // level-0 pixels
  double fine_radius_px = 6.0;
  int pose_iterations = 10;
  double quality_good = 0.3;         // found / attempted
  double quality_lost = 0.13;
  int min_found_good = 40;
  int lost_after_bad_frames = 3;
  double keyframe_min_interval_s = 0.25;
  double keyframe_distance_ratio = 0.08;  // of the mean scene depth
  double keyframe_overlap_ratio = 0.55;   // tracked / points of the reference keyframe
  int keyframe_min_points_dodgy = 100;    // a Dodgy frame holding this many points may add a keyframe (0: never)
  int local_ba_keyframes = 5;             // newest + 4 nearest
  int local_ba_iterations = 10;           // Levenberg-Marquardt iterations per local adjustment
  int global_ba_iterations = 10;          // ... per global adjustment
  int max_keyframes = 400;
  bool global_ba_when_idle = true;
  int global_ba_max_keyframes = 200;      // larger maps get local adjustments only
  int global_ba_every = 5;                // synchronous mode: keyframes between global adjustments
  int global_ba_fixed_keyframes = 2;      // first keyframes held fixed by global adjustments (2: also the scale)
  bool cull_points = true;                // drop points that keep being missed where they should be seen
  double new_point_clearance_px = 0;      // no new point at a corner this close (x level scale) to a mapped one (0: off)
  bool loop_closure = true;
  double loop_min_gap_s = 20.0;           // a loop keyframe is at least this much older
  double init_min_parallax_px = 20.0;     // median displacement before trying two-view init
  double init_min_parallax_deg = 1.0;     // median triangulation angle an initial map must reach
  double init_timeout_s = 3.0;            // retry with a new reference after this
  int init_min_points = 60;
  // Gravity prior (docs/slam.md): the IMU's roll and pitch given with a frame hold the tilt of that
  // frame's pose and of its keyframe in every adjustment, with this standard deviation (0: off).
  double gravity_sigma_deg = 0;
  bool gravity_in_tracking = true;        // also in the tracker's pose update (else adjustments only)
};

// The IMU's attitude at a frame: gravity's direction ("down", a unit vector) in the camera frame, from
// the drone's roll and pitch (absolute, gravity-referenced) and the camera's mounting. `t` is when
// the attitude holds; it must be the frame's time (within kGravityMaxOffsetS): the caller interpolates.
struct GravityMeasurement {
  Seconds t = 0;
  Eigen::Vector3d down_cam = Eigen::Vector3d::UnitY();
};
constexpr Seconds kGravityMaxOffsetS = 0.005;

// "down" in the camera frame from the body's roll and pitch (radians, core/frames' yaw-pitch-roll
// convention; yaw does not matter) and the camera's mounting on the body.
Eigen::Vector3d gravity_down_in_camera(double roll_rad, double pitch_rad, const Eigen::Isometry3d& T_body_cam);

struct SlamResult {
  TrackingState state = TrackingState::Initializing;
  std::optional<Eigen::Isometry3d> T_cam_map;  // set when Good or Dodgy (up to scale)
  int points_found = 0;
  int points_attempted = 0;
  double quality = 0.0;       // found / attempted
  bool keyframe_added = false;
  bool relocalized = false;   // this frame recovered from Lost
  bool gravity_used = false;  // the tracker's pose update held the frame's tilt to the IMU's
  std::string reason;         // why not Good (empty when Good)
  // Why attempted points were not found (diagnosis, benchmark trace): the fine search's misses and
  // the matches the pose update rejected.
  struct Misses {
    int no_feature = 0, too_far = 0, ambiguous = 0, taken = 0, pose_outliers = 0;
  } misses;
  // This call's cost, excluding mapping run inline (measurements only; never feed the algorithm):
  double tracking_ms = 0.0;      // wall time
  double tracking_cpu_ms = 0.0;  // CPU time of the calling thread (one core, load-independent)
};

struct SlamStatus {
  TrackingState state = TrackingState::Initializing;
  double quality = 0.0;
  int map_points = 0;
  int keyframes = 0;
  // What the map holds in memory: keyframes' pyramids, small images, features and descriptors, and
  // the points (bounded by max_keyframes; the bulk of a long-running server's growth until full).
  std::size_t map_bytes = 0;
  int points_found = 0;
  int mapping_queue = 0;
  int local_ba_runs = 0;
  int global_ba_runs = 0;
  int loops_corrected = 0;
  std::string reason;
  std::vector<Eigen::Vector3d> points_map;       // subsampled for the top-down view
  std::vector<Eigen::Isometry3d> keyframes_T_map_cam;
  std::vector<Seconds> keyframe_times;  // one per keyframe pose
  std::optional<Eigen::Vector3d> down_map;  // gravity's direction in the map, from the IMU attitudes given
};

// Mapping figures for benchmarks (wall times are measurements only).
struct MappingStatistics {
  std::vector<double> keyframe_ms;  // processing time of each keyframe
  int points_created = 0;
  int observations_removed = 0;
  int global_ba_runs = 0;
  int loops_detected = 0;
  int loops_corrected = 0;
  int points_fused = 0;        // by loop closures
  int clearance_skips = 0;         // corners left alone next to a mapped corner (new_point_clearance_px)
  std::vector<double> loop_ms;  // each correction's wall time
  std::vector<double> loop_search_ms;  // each keyframe's loop search (no correction) wall time
  std::vector<LoopReport> loops;
};

class SlamSystem {
 public:
  // Throws std::invalid_argument on invalid intrinsics or settings (naming the field).
  SlamSystem(const PinholeCamera& camera, const SlamSettings& settings = {});
  ~SlamSystem();
  SlamSystem(const SlamSystem&) = delete;
  SlamSystem& operator=(const SlamSystem&) = delete;

  // One 8-bit grey frame of the camera's size, stamped t. prior_T_cam_map (e.g. the filter's
  // prediction) replaces the motion model's prior when given. Frames of the wrong size or type,
  // and non-increasing timestamps, return Lost with the reason and leave the map untouched.
  // `gravity`: the IMU's attitude at this frame (used when settings.gravity_sigma_deg > 0); a
  // non-finite or zero direction, or one stamped at another time, refuses the frame.
  SlamResult track(const cv::Mat& gray, Seconds t,
                   const std::optional<Eigen::Isometry3d>& prior_T_cam_map = std::nullopt,
                   const std::optional<GravityMeasurement>& gravity = std::nullopt);

  SlamStatus status() const;
  // Every stride-th map point (map units) into `out`, at most `max_points` of them (the lab page's
  // top-down view). Reuses `out`'s buffer: allocates nothing once it holds max_points. The map's own
  // lock is held while copying; the mapper may run meanwhile.
  void sample_points(std::vector<Eigen::Vector3d>& out, std::size_t max_points) const;
  MappingStatistics mapping_statistics() const;
  // Drops the map and starts initializing again.
  void reset();
  // Blocks until the mapper has processed every queued keyframe (tests, benchmarks, saving).
  void wait_for_mapping();

  // Binary map file (keyframes, points, descriptors, camera). save throws on I/O errors; load
  // throws std::runtime_error (truncated, corrupted, other camera, wrong version) and then leaves
  // the current map untouched. After load the system relocalizes against the loaded keyframes.
  void save_map(const std::filesystem::path& file) const;
  void load_map(const std::filesystem::path& file);

  const PinholeCamera& camera() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::slam
