#pragma once
// The simulated lab with its teacher and a drone hovering still: the camera fixed at `camera_at`
// looking along +x; the teacher stands at `at` facing `yaw` (world). Rendered sharp by default, or as
// the lab's camera renders in flight (noise, motion blur).
#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/frames.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "drone/sim/render_commands.hpp"
#include "localization/face/teacher_head.hpp"

namespace labo::face::testing {

struct TeacherScene {
  explicit TeacherScene(bool sharp = true) : renderer{lab, ardrone2_cameras(), load_lab_teacher_head(lab), 1, options(sharp)} {}

  lab::LabDescription lab = lab::load_lab_description(lab::default_lab_path());
  sim::LabRenderer renderer;
  Eigen::Vector3d camera_at = Eigen::Vector3d::Zero();

  static sim::LabRenderOptions options(bool sharp) {
    sim::LabRenderOptions o;
    o.motion_blur = !sharp;
    o.noise = !sharp;
    return o;
  }

  sim::SceneState scene(const Eigen::Vector2d& at, double yaw) const {
    sim::SceneState s;
    s.teacher_floor_xy = at;
    s.T_world_head = sim::teacher_head_pose(lab, at.x(), at.y(), yaw);
    s.T_world_body = make_pose(camera_at - T_body_cam_front().translation().x() * Eigen::Vector3d::UnitX(), 0.0);
    return s;
  }
  // The face's pose in the camera (face/ convention: z out of the face).
  Eigen::Isometry3d T_cam_face(const sim::SceneState& s) const {
    return (s.T_world_body * T_body_cam_front()).inverse() * s.T_world_head;
  }
  cv::Mat gray(const sim::SceneState& s) {
    cv::Mat bgr, out;
    renderer.render(CameraId::Front, s, bgr);
    cv::cvtColor(bgr, out, cv::COLOR_BGR2GRAY);
    return out;
  }
};

}  // namespace labo::face::testing
