#pragma once
// The seam between the simulated lab's physics (SimulatedLab, drone/sim/simulated_lab.hpp) and its
// cameras (LabRenderer, drone/sim/lab_renderer.hpp): what the world looks like at one instant, and a
// renderer that turns it into a camera image. Tests substitute a trivial renderer.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "drone/lab/lab_description.hpp"

namespace labo::sim {

// Everything that moves in the lab at one instant, in the world frame (x, y on the floor, z up).
struct SceneState {
  Seconds t = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();     // for motion blur
  Eigen::Vector3d angular_velocity_body_radps = Eigen::Vector3d::Zero();
  // The teacher's head: face frame of core/candide3.hpp (origin between the eyes, metres).
  Eigen::Isometry3d T_world_head = Eigen::Isometry3d::Identity();
  Eigen::Vector2d teacher_floor_xy = Eigen::Vector2d::Zero();       // the body below the head
  bool teacher_present = true;
  double exposure_gain = 1.0;  // auto-exposure state: 1 is nominal
};

class SceneRenderer {
 public:
  virtual ~SceneRenderer() = default;
  // The camera's view, BGR at the camera's configured size, into `bgr` (reallocated only when its
  // size or type differ, so a caller reusing one Mat does not allocate per frame).
  // Motion blur integrates the scene's velocities over the camera's shutter time.
  virtual void render(CameraId camera, const SceneState& scene, cv::Mat& bgr) = 0;
  // An instrument placed in the lab after the renderer was built: drawn from the next frame on. A
  // renderer that draws no lab has nothing to add.
  virtual void add_instrument(const lab::InstrumentSpec& instrument) { (void)instrument; }
};

}  // namespace labo::sim
