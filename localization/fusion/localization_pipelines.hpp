#pragma once
// The seam between flight control and localization: what FlightStack feeds in (navdata, frames, the
// commands it sends) and what it reads back (the filter's predicted pose, the instrument, landing
// platform and face observations, the SLAM summary). FlightStack owns one LocalizationPipelines; the
// lab implementation wires StateEstimator, PlanarObjectLocalizer, SlamSystem and FacePoseEstimator
// (localization/fusion/lab_pipelines.hpp); tests substitute a model with known perception.
//
// Control decides which visual source feeds the filter (SLAM far, homography near, face in
// face-follow; LocalizationSwitch) and tells the pipelines through set_focus().
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/face/person_shape.hpp"

namespace labo::fusion {

struct VisionJob;
struct VisionResults;
struct SlamPointsXy;
struct PlanarTarget;

// Which visual source drives the pose (the paper's colour code, docs/control.md).
enum class FeedbackSource { Slam, Homography, Face, DeadReckoning };
std::string to_string(FeedbackSource source);
std::string colour_of(FeedbackSource source);  // "#rrggbb" for plots and the UI

struct PoseEstimate {
  Seconds t = 0;
  bool valid = false;  // false before the first navdata
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();
  double yaw_rate = 0;
  FeedbackSource source = FeedbackSource::DeadReckoning;
  double quality = 0;  // 0..1
  double position_sigma_m = 0;  // 1-sigma position uncertainty (the worst-known axis)
  double altitude_sigma_m = 0;  // 1-sigma altitude uncertainty
  double drift_bound_m = 0;     // how far dead reckoning may have drifted (estimation::FusedState)
  double unobserved_flight_s = 0;  // flight bridged unseen since the last fix; 0: the place is confirmed
};

enum class TrackState { Off, Searching, Tracking, Lost };
std::string to_string(TrackState state);

// A planar target (instrument in the front camera, platform in the bottom camera) or the face.
struct TargetObservation {
  TrackState state = TrackState::Off;
  Seconds t = 0;                                            // frame time of the last result
  Eigen::Isometry3d T_cam_target = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_target = Eigen::Isometry3d::Identity();  // placed in the world
  bool placed_in_world = false;
  std::vector<cv::Point2f> image_points;  // panel corners, or the 68 face landmarks
  double quality = 0;
  double rotation_sigma_rad = 0;  // 1-sigma of T_cam_target's rotation when the front-end measures it; 0: unknown
  std::string method;  // "template", "features" (near detection), "ecc", "pnp-lm", ...
  std::string reason;  // why lost, for the UI
  // Tracking the target's place only (the teacher's head while their face cannot be posed):
  // T_cam_target's translation is measured, its rotation is the last one measured.
  bool position_only = false;
  // The target's centre from the body's origin, level and along the heading (x forward, y left,
  // z up), turned by the roll and pitch measured when the frame was taken rather than by the
  // latest ones: where it is as the camera saw it, with no placement in the world mixed in.
  std::optional<Eigen::Vector3d> offset_heading_m;
};

// A point seen from the body (`in_body_m`, the body's axes) as an offset along the heading: turned by
// the body's pitch and roll so that x is level forward, y level left and z up.
Eigen::Vector3d offset_along_heading(const Eigen::Vector3d& in_body_m, double pitch_rad, double roll_rad);

enum class SlamState { Off, Initializing, Good, Dodgy, Lost };
std::string to_string(SlamState state);

struct SlamSummary {
  SlamState state = SlamState::Off;
  int points_found = 0;
  int points_attempted = 0;
  int keyframes = 0;
  int map_points = 0;
  std::size_t map_bytes = 0;  // slam::SlamStatus::map_bytes
  bool scale_estimated = false;
  double scale = 1.0;  // metres per map unit
  int scale_pairs = 0;         // inlier displacement pairs behind the scale
  int scale_pairs_needed = 0;  // pairs the scale needs before SLAM poses are fused
};

// What control asks localization to look for right now (vision costs time: do only what is needed).
struct PerceptionFocus {
  std::string instrument_id;  // empty: no instrument
  bool platform = false;      // bottom camera, landing platform
  bool face = false;
  bool slam = true;
  FeedbackSource feedback = FeedbackSource::Slam;  // the visual source allowed to correct the filter
};

class LocalizationPipelines {
 public:
  virtual ~LocalizationPipelines() = default;
  virtual void on_navdata(const NavdataSample& sample) = 0;
  virtual void on_command(const MoveCommand& command, Seconds t) = 0;
  // One frame's vision, inline.
  virtual void on_video(const VideoFrame& frame) = 0;
  // The same in three steps for a worker thread (vision_job.hpp): prepare here, run_vision_job()
  // there, apply back here. Pipelines without front-ends have no vision to prepare.
  virtual bool prepare_vision(const VideoFrame&, VisionJob&) { return false; }
  virtual void apply_vision(const VisionResults&) {}
  virtual void set_focus(const PerceptionFocus& focus) = 0;
  // The registered person face-follow follows from the next frame on; false when these pipelines
  // have no face front-end to give the shape to.
  virtual bool follow_person(const face::PersonShape&) { return false; }
  // Re-anchors the filter (on the platform before take-off): world pose known.
  virtual void reset(const Eigen::Isometry3d& T_world_body, Seconds t) = 0;
  // The same at the first navdata sample's time: what a flight that has not heard from the drone
  // yet knows (StateEstimator::start_at_first_navdata).
  virtual void start_at_first_navdata(const Eigen::Isometry3d& T_world_body) = 0;
  // The drone was set down at a known pose (someone put it on its platform) while these pipelines
  // ran: StateEstimator::set_down_at_next_navdata (the map and the instruments' places are kept).
  // Pipelines without a map start over.
  virtual void set_down_at_next_navdata(const Eigen::Isometry3d& T_world_body) { start_at_first_navdata(T_world_body); }

  virtual PoseEstimate predict(Seconds t) const = 0;
  virtual TargetObservation instrument() const = 0;
  virtual TargetObservation platform() const = 0;
  virtual TargetObservation face() const = 0;
  virtual SlamSummary slam() const = 0;
  // An instrument placed in the lab while flying (an admin's upload): its front-end from now on. The
  // caller has checked that its id is new. False: these pipelines cannot add instruments.
  virtual bool add_instrument(const PlanarTarget& instrument) {
    (void)instrument;
    return false;
  }
  // The SLAM map seen from above (slam_points_top_down.hpp); null without one.
  virtual std::shared_ptr<const SlamPointsXy> slam_points() const { return nullptr; }
};

}  // namespace labo::fusion
