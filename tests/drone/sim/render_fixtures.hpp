#pragma once
// Shared set-up of the renderer tests: the default lab, the AR.Drone 2.0 cameras, sharp images.
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "core/camera_config.hpp"
#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/lab_renderer.hpp"

namespace labo::test {
using namespace labo::sim;

inline CamerasConfig ardrone_cameras() {
  return ardrone2_cameras();
}

inline LabRenderOptions sharp_options() {
  LabRenderOptions o;
  o.motion_blur = false;
  o.noise = false;
  return o;
}

// The body pose whose front camera sits at `camera_at` and looks at `target` (no roll).
inline Eigen::Isometry3d body_looking_at(const Eigen::Vector3d& camera_at, const Eigen::Vector3d& target) {
  const Eigen::Vector3d d = target - camera_at;
  const double yaw = std::atan2(d.y(), d.x());
  const double pitch = -std::atan2(d.z(), d.head<2>().norm());
  Eigen::Isometry3d T = make_pose(Eigen::Vector3d::Zero(), yaw, pitch, 0.0);
  T.translation() = camera_at - T.linear() * T_body_cam_front().translation();
  return T;
}

inline SceneState still_scene(const Eigen::Isometry3d& T_world_body, bool teacher = false) {
  SceneState s;
  s.T_world_body = T_world_body;
  s.teacher_present = teacher;
  return s;
}

// The teacher standing at (x, y), facing yaw.
inline void place_teacher(SceneState& s, const lab::LabDescription& lab, double x, double y, double yaw) {
  const Eigen::Vector3d f(std::cos(yaw), std::sin(yaw), 0.0), up = Eigen::Vector3d::UnitZ();
  s.teacher_present = true;
  s.teacher_floor_xy = {x, y};
  s.T_world_head = Eigen::Isometry3d::Identity();
  s.T_world_head.linear().col(0) = up.cross(f);
  s.T_world_head.linear().col(1) = up;
  s.T_world_head.linear().col(2) = f;
  s.T_world_head.translation() = Eigen::Vector3d(x, y, lab.teacher.eye_height_m);
}

// The level-0 texel a pixel's ray shows on rectangle `rect` (ignoring what is in front), if it hits it.
inline std::optional<std::uint32_t> texel_seen(const LabScene& scene, int rect, const PinholeCamera& camera,
                                               const Eigen::Isometry3d& T_world_cam, int px, int py) {
  const SceneRect& r = scene.rects[static_cast<std::size_t>(rect)];
  const Eigen::Vector3d ray = T_world_cam.linear() * camera.unproject({px, py});
  const Eigen::Vector3d c = T_world_cam.translation();
  const double nd = r.normal.dot(ray);
  if (nd >= 0) return std::nullopt;
  const double t = r.normal.dot(r.origin - c) / nd;
  const Eigen::Vector3d p = c + t * ray - r.origin;
  const double a = p.dot(r.axis_u), b = p.dot(r.axis_v);
  if (a < 0 || b < 0 || a > r.size_u || b > r.size_v) return std::nullopt;
  return scene.textures[static_cast<std::size_t>(r.texture)].sample(
      0, static_cast<float>(a * r.texels_per_m_u - 0.5), static_cast<float>(b * r.texels_per_m_v - 0.5));
}

inline int colour_distance(const cv::Vec3b& px, std::uint32_t texel) {
  return std::abs(px[0] - texel_b(texel)) + std::abs(px[1] - texel_g(texel)) + std::abs(px[2] - texel_r(texel));
}

struct TemplateMatch {
  double ncc = 0;            // normalized cross-correlation, grey
  double mean_abs_diff = 0;  // grey levels
};

// Compares the image with `tpl` warped by H (template pixels -> image), inside the warped template
// shrunk by 3 pixels.
inline TemplateMatch compare_with_template(const cv::Mat& bgr, const cv::Mat& tpl, const cv::Mat& H) {
  cv::Mat small = tpl, warped, mask;
  // Pre-shrink by the warp's scale so that the reference is not aliased.
  const double scale = std::sqrt(std::abs(cv::determinant(H(cv::Rect(0, 0, 2, 2)))));
  cv::Mat Hs = H.clone();
  if (scale < 0.7) {
    cv::resize(tpl, small, cv::Size(), scale, scale, cv::INTER_AREA);
    const cv::Mat S = (cv::Mat_<double>(3, 3) << tpl.cols / static_cast<double>(small.cols), 0,
                       0.5 * tpl.cols / small.cols - 0.5, 0, tpl.rows / static_cast<double>(small.rows),
                       0.5 * tpl.rows / small.rows - 0.5, 0, 0, 1);
    Hs = H * S;
  }
  cv::warpPerspective(small, warped, Hs, bgr.size(), cv::INTER_LINEAR);
  cv::warpPerspective(cv::Mat(small.size(), CV_8U, cv::Scalar(255)), mask, Hs, bgr.size(), cv::INTER_NEAREST);
  cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), 3);
  cv::Mat a, b, af, bf, mf;
  cv::cvtColor(bgr, a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(warped, b, cv::COLOR_BGR2GRAY);
  a.convertTo(af, CV_32F);
  b.convertTo(bf, CV_32F);
  mask.convertTo(mf, CV_32F, 1.0 / 255);
  TemplateMatch m;
  cv::Mat diff;
  cv::absdiff(af, bf, diff);
  m.mean_abs_diff = cv::mean(diff, mask)[0];
  af -= cv::mean(af, mask)[0];
  bf -= cv::mean(bf, mask)[0];
  af = af.mul(mf);
  bf = bf.mul(mf);
  m.ncc = af.dot(bf) / std::sqrt(af.dot(af) * bf.dot(bf));
  return m;
}

}  // namespace labo::test
