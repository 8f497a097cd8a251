#pragma once
// A mission is a stage machine stepped once per control tick. It reads the fused pose and the
// perception results, tells localization what to look for (focus, camera) and flies through the
// autopilot (targets, take-off, landing). Its current stage is reported to the UI.
#include <optional>
#include <string>

#include "control/autopilot.hpp"
#include "control/control_config.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/localization_pipelines.hpp"

namespace labo::control {

struct MissionContext {
  Seconds t = 0;
  const fusion::PoseEstimate& pose;
  const fusion::LocalizationPipelines& perception;
  Autopilot& autopilot;
  const fusion::LabGeometry& lab;
  const ControlConfig& config;
  fusion::PerceptionFocus& focus;
  CameraId& camera;
  Eigen::Vector3d centre_ray_front;  // front camera ray through the image centre (x/z, y/z, 1)
  std::optional<FlightOutput> phase_action;  // take-off / land issued this tick
};

enum class MissionOutcome { Running, Succeeded, Failed };

class Mission {
 public:
  virtual ~Mission() = default;
  virtual std::string name() const = 0;
  virtual MissionOutcome step(MissionContext& ctx) = 0;
  virtual int stage_index() const = 0;  // 1-based
  virtual int stage_count() const = 0;
  virtual std::string stage() const = 0;  // "3 inspect: holding 4.2/10 s"
  // False while dead reckoning is the expected source (take-off, landing): safety does not count it
  // as localization loss.
  virtual bool needs_visual_localization() const = 0;
  // True while the stage may fly on navdata odometry for a while (the return home: SLAM relocalizing,
  // or off while the bottom camera looks for the platform); safety then grants
  // return_dead_reckoning_s before it escalates.
  virtual bool tolerates_dead_reckoning() const { return false; }
  virtual bool accepts_stop_face_follow() const { return false; }
  // The instrument this mission inspects (empty: none); it may not be removed meanwhile.
  virtual std::string inspected_instrument() const { return ""; }
  virtual void stop_face_follow() {}
  // Why it failed, or what it achieved.
  const std::string& result() const { return result_; }

 protected:
  std::string result_;
};

// Pose from which the front camera sees a planar target (or face) at `distance_m`, facing it from its
// -z side (z points into the panel), with the target's centre on `centre_ray` - the ray through the
// image centre, which is not the optical axis (the principal point is off-centre) - so the panel
// appears centred in the image.
PoseTarget standoff_target(const Eigen::Isometry3d& T_world_target, double distance_m,
                           const Eigen::Vector3d& centre_ray = Eigen::Vector3d::UnitZ());
// The front camera's ray through the image centre, (x/z, y/z, 1).
Eigen::Vector3d image_centre_ray(double fx, double fy, double cx, double cy, int width, int height);
// Places a target seen by a camera in the world: T_world_body * T_body_cam * T_cam_target.
Eigen::Isometry3d place_in_world(const fusion::PoseEstimate& pose, CameraId camera, const Eigen::Isometry3d& T_cam_target);
// The observation's world pose: the pipeline's placement when it made one, else place_in_world().
Eigen::Isometry3d world_pose_of(const fusion::TargetObservation& obs, const fusion::PoseEstimate& pose, CameraId camera);
// Camera-to-target distance, from the latest observation.
double camera_distance(const fusion::TargetObservation& obs);
std::string format_seconds(double s);

}  // namespace labo::control
