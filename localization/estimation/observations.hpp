#pragma once
// What the vision pipelines hand to the StateEstimator, each stamped with the time of the video frame
// it was computed from (the frame's receive time on the link's clock; the estimator subtracts the video
// delay itself). Poses follow the T_a_b convention of core/frames.hpp.
#include <Eigen/Geometry>
#include <optional>
#include <string_view>

#include "core/time.hpp"
#include "drone/drone_link.hpp"

namespace labo::estimation {

// Which measurement drives the fused estimate now (paper Fig. 9).
enum class LocalizationSource { Slam, Homography, Face, DeadReckoning };

// The paper's colour code for plots and the UI: green while vision tracking is good (SLAM or face),
// blue while the instrument's homography drives the estimate, red when SLAM (or the face) is lost and
// only navdata and the model remain, black when the object tracking was lost.
enum class SourceColour { Green, Blue, Red, Black };

std::string_view to_string(LocalizationSource source);
std::string_view to_string(SourceColour colour);

// A pose of the front camera from the SLAM system, in map units (the map's scale is unknown; the
// estimator learns it). A new map_id (the SLAM re-initialised) restarts the map-to-world transform.
struct SlamObservation {
  Seconds t = 0;                  // video frame time
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  int map_id = 0;
  // The map is already metric (a saved map whose scale was fixed before): scale 1, fused at once.
  bool map_is_metric = false;
  bool tracking_good = true;      // SLAM state good (dodgy/lost/initializing must not be sent as good)
  double quality = 1.0;           // 0..1, e.g. points found / attempted
};

// A planar object (instrument, or the landing platform in the bottom camera) localized in a frame.
struct ObjectObservation {
  Seconds t = 0;                  // video frame time
  int object_index = 0;           // which object (FrameId::object(index))
  CameraId camera = CameraId::Front;
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();
  // The object's pose in the world as surveyed (lab.json), when known. The estimator places the object
  // by cascading T_world_body * T_body_cam * T_cam_object at its first sighting, weighted with this
  // survey, and refines it while another source (SLAM) localizes the drone.
  std::optional<Eigen::Isometry3d> T_world_object_surveyed;
  double quality = 1.0;           // 0..1
  // 1-sigma of T_cam_object's rotation as the localizer measured it (PlanarResult::rotation_sigma_rad,
  // growing with the distance); 0: unknown, the estimator then assumes noise.object_yaw_rad x distance.
  double rotation_sigma_rad = 0;
};

// The teacher's face from the front camera. The face moves: its world pose is tracked with a short
// memory, and the drone's pose relative to it is what face following uses.
struct FaceObservation {
  Seconds t = 0;                  // video frame time
  Eigen::Isometry3d T_cam_face = Eigen::Isometry3d::Identity();
  double quality = 1.0;           // 0..1
};

}  // namespace labo::estimation
