#include "bench/planar/lab_sequences.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/lab_renderer.hpp"

namespace labo::bench {

using lab::InstrumentSpec;
using lab::LabDescription;
using lab::PlatformSpec;
using lab::default_lab_path;
using lab::load_lab_description;

using sim::LabRenderer;
using sim::SceneState;


namespace {
constexpr double kFps = 30.0;
constexpr double kPi = 3.14159265358979323846;
}  // namespace

PlanarSequence render_lab_approach(const std::string& name, double min_visible) {
  const LabDescription lab = load_lab_description(default_lab_path());
  const InstrumentSpec* scope = lab.find_instrument("oscilloscope");
  if (scope == nullptr) throw std::runtime_error(lab.source.string() + ": no instrument 'oscilloscope'");
  const CamerasConfig cameras = ardrone2_cameras();
  LabRenderer renderer(lab, cameras, std::nullopt, 7);
  PlanarSequence s;
  s.name = name;
  s.panel = {cv::imread(scope->template_path.string(), cv::IMREAD_GRAYSCALE), scope->width_m, scope->height_m};
  if (s.panel.image.empty()) throw std::runtime_error(scope->template_path.string() + ": unreadable template");
  const Eigen::Isometry3d T_body_cam = LabRenderer::T_body_cam(CameraId::Front);
  const Eigen::Vector3d centre = scope->T_world_object.translation();
  const Eigen::Vector3d towards_viewer = -scope->T_world_object.linear().col(2);
  const Eigen::Vector3d side = towards_viewer.cross(Eigen::Vector3d::UnitZ()).normalized();
  const int frames = 150;
  const auto body_at = [&](double i) {
    const double a = i / (frames - 1);
    const Eigen::Vector3d camera = centre + towards_viewer * (3.0 - 2.4 * a) + side * (0.2 * std::sin(3.0 * a)) +
                                   Eigen::Vector3d::UnitZ() * (0.05 * std::sin(5.0 * a));
    const Eigen::Vector3d d = centre + side * (0.05 * std::sin(7.0 * a)) - camera;  // a yaw wobble
    Eigen::Isometry3d T = make_pose(Eigen::Vector3d::Zero(), std::atan2(d.y(), d.x()),
                                    -std::atan2(d.z(), d.head<2>().norm()), 0.0);
    T.translation() = camera - T.linear() * T_body_cam.translation();
    return T;
  };
  const PinholeCamera camera(cameras.front);
  cv::Mat bgr, gray;
  for (int i = 0; i < frames; ++i) {
    SceneState scene;
    scene.t = i / kFps;
    scene.T_world_body = body_at(i);
    scene.velocity_world_mps = (body_at(i + 0.5).translation() - body_at(i - 0.5).translation()) * kFps;
    scene.teacher_present = false;
    renderer.render(CameraId::Front, scene, bgr);
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    const Eigen::Isometry3d T_cam_object = (scene.T_world_body * T_body_cam).inverse() * scope->T_world_object;
    s.frames.push_back(gray.clone());
    s.truth.push_back(T_cam_object);
    s.in_view.push_back(visible_fraction(camera, s.panel, T_cam_object) >= min_visible);
  }
  return s;
}


PlanarSequence render_lab_platform_pass(const std::string& name, double min_visible) {
  const LabDescription lab = load_lab_description(default_lab_path());
  const PlatformSpec& platform = lab.platform;
  const CamerasConfig cameras = ardrone2_cameras();
  LabRenderer renderer(lab, cameras, std::nullopt, 7);
  PlanarSequence s;
  s.name = name;
  s.bottom_camera = true;
  s.panel = {cv::imread(platform.template_path.string(), cv::IMREAD_GRAYSCALE), platform.width_m, platform.height_m};
  if (s.panel.image.empty()) throw std::runtime_error(platform.template_path.string() + ": unreadable template");
  s.sift_switch_distance_m = platform.sift_switch_distance_m;
  s.sift_min_inliers = platform.sift_min_inliers;
  const Eigen::Isometry3d T_body_cam = LabRenderer::T_body_cam(CameraId::Bottom);
  const Eigen::Vector3d top = platform.T_world_object.translation();
  const int frames = 240;
  // The camera's height above the platform's top, its sideways offset, and the body's yaw, pitch and
  // roll (the tilts in phase with the sway's acceleration, as a drone tilts to move), at frame i.
  const auto body_at = [&](double i) {
    const double t = i / kFps, a = i / (frames - 1);
    const double h = 0.3 + 1.2 * (0.5 + 0.5 * std::cos(2 * kPi * a));
    const double sway = 0.1 * h, wx = 2 * kPi * 0.4, wy = 2 * kPi * 0.3;
    const Eigen::Vector3d camera = top + Eigen::Vector3d(sway * std::sin(wx * t), 0.8 * sway * std::sin(wy * t + 1.0), h);
    Eigen::Isometry3d T = make_pose(Eigen::Vector3d::Zero(), 0.5 * std::sin(2 * kPi * 0.15 * t), 0.06 * std::sin(wx * t),
                                    0.05 * std::sin(wy * t + 1.0));
    T.translation() = camera - T.linear() * T_body_cam.translation();
    return T;
  };
  const PinholeCamera camera(cameras.bottom);
  cv::Mat bgr, gray;
  for (int i = 0; i < frames; ++i) {
    SceneState scene;
    scene.t = i / kFps;
    scene.T_world_body = body_at(i);
    const Eigen::Isometry3d before = body_at(i - 0.5), after = body_at(i + 0.5);
    scene.velocity_world_mps = (after.translation() - before.translation()) * kFps;
    const Eigen::AngleAxisd turn(before.linear().transpose() * after.linear());
    scene.angular_velocity_body_radps = turn.axis() * turn.angle() * kFps;
    scene.teacher_present = false;
    renderer.render(CameraId::Bottom, scene, bgr);
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    const Eigen::Isometry3d T_cam_object = (scene.T_world_body * T_body_cam).inverse() * platform.T_world_object;
    s.frames.push_back(gray.clone());
    s.truth.push_back(T_cam_object);
    s.in_view.push_back(visible_fraction(camera, s.panel, T_cam_object) >= min_visible);
  }
  return s;
}

}  // namespace labo::bench
