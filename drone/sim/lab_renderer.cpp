#include "drone/sim/lab_renderer.hpp"

#include <algorithm>

#include "core/frames.hpp"

namespace labo::sim {

using lab::Box3;
using lab::InstrumentSpec;
using lab::LabDescription;


LabRenderer::CameraPipeline::CameraPipeline(const PinholeCamera& camera, const LabScene& scene, Eigen::Isometry3d T_bc)
    : rays(camera), tracer(rays, scene), blur(rays), T_body_cam(T_bc) {
  const std::size_t n = static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height());
  colour.resize(n);
  blurred.resize(n);
  depth.resize(n);
}

LabRenderer::LabRenderer(const LabDescription& lab, const CamerasConfig& cameras, std::optional<TexturedHeadModel> head,
                         unsigned seed, LabRenderOptions options, const CameraMounts& mounts)
    : options_(options),
      room_(lab.room),
      scene_(build_lab_scene(lab)),
      teacher_(lab.teacher, std::move(head)),
      seed_(seed),
      sensor_(seed, options.noise_sigma) {
  for (const auto& b : lab.benches) solids_.push_back(b.box);
  for (const auto& i : lab.instruments) solids_.push_back(i.bounds());
  solids_.push_back(lab.platform.box());
  validate(cameras.front, "cameras.front");
  validate(cameras.bottom, "cameras.bottom");
  front_ = std::make_unique<CameraPipeline>(PinholeCamera(cameras.front), scene_, mounts.front);
  bottom_ = std::make_unique<CameraPipeline>(PinholeCamera(cameras.bottom), scene_, mounts.bottom);
}

void LabRenderer::add_instrument(const InstrumentSpec& instrument) {
  // Housing textures from the renderer's seed and the scene's size: the same uploads in the same
  // order draw the same lab.
  append_instrument(scene_, instrument, seed_ * 2654435761u + static_cast<unsigned>(scene_.rects.size()));
  solids_.push_back(instrument.bounds());
  front_ = std::make_unique<CameraPipeline>(front_->rays.camera(), scene_, front_->T_body_cam);
  bottom_ = std::make_unique<CameraPipeline>(bottom_->rays.camera(), scene_, bottom_->T_body_cam);
}

Eigen::Isometry3d LabRenderer::T_body_cam(CameraId id) {
  return id == CameraId::Front ? T_body_cam_front() : T_body_cam_bottom();
}

LabRenderer::CameraPipeline& LabRenderer::pipeline(CameraId id) { return id == CameraId::Front ? *front_ : *bottom_; }

const PinholeCamera& LabRenderer::camera(CameraId id) const {
  return (id == CameraId::Front ? *front_ : *bottom_).rays.camera();
}

const LabRenderer::FrameStats& LabRenderer::last_stats(CameraId id) const {
  return (id == CameraId::Front ? *front_ : *bottom_).stats;
}

Eigen::Isometry3d LabRenderer::camera_pose(const CameraPipeline& p, const Eigen::Isometry3d& T_world_body) const {
  constexpr double kClearance_m = 0.01;
  Eigen::Isometry3d T = T_world_body * p.T_body_cam;
  const Eigen::Vector3d c = T.translation();
  double surface = room_.min.z();
  for (const Box3& b : solids_) {
    if (c.x() >= b.min.x() && c.x() <= b.max.x() && c.y() >= b.min.y() && c.y() <= b.max.y()) surface = std::max(surface, b.max.z());
  }
  T.translation().z() = std::max(c.z(), surface + kClearance_m);
  return T;
}

void LabRenderer::render(CameraId id, const SceneState& scene, cv::Mat& bgr) {
  CameraPipeline& p = pipeline(id);
  const int w = p.rays.width(), h = p.rays.height();
  const Eigen::Isometry3d T_world_cam = camera_pose(p, scene.T_world_body);

  teacher_.project(scene, T_world_cam, p.rays.camera(), p.rays.max_radius(), p.teacher);
  const PixelBounds& box = p.teacher.box;
  p.tracer.trace(T_world_cam, box.x0, box.y0, box.x1, box.y1, p.colour.data(), p.depth.data());
  p.stats.tracer = p.tracer.stats();
  p.stats.teacher_drawn = !box.empty();
  if (!box.empty()) teacher_.draw(p.teacher, FrameTarget{w, h, p.colour.data(), p.depth.data()});

  const std::uint32_t* out = p.colour.data();
  p.stats.blur_px = 0;
  if (options_.motion_blur && options_.shutter_s > 0) {
    p.stats.blur_px = p.blur.plan(scene, p.T_body_cam, options_.shutter_s, p.tracer.tile_depth());
    if (p.stats.blur_px >= MotionBlur::kMinMotion_px) {
      p.blur.apply(p.colour.data(), p.blurred.data());
      out = p.blurred.data();
    }
  }
  sensor_.apply(out, w, h, scene.exposure_gain, options_.noise && options_.noise_sigma > 0, frame_key(scene.t, id), bgr);
}

void LabRenderer::set_options(const LabRenderOptions& options) {
  if (options.noise_sigma != options_.noise_sigma) sensor_ = SensorResponse(seed_, options.noise_sigma);
  options_ = options;
}

int LabRenderer::rect_at(CameraId id, const Eigen::Isometry3d& T_world_body, int px, int py) {
  CameraPipeline& p = pipeline(id);
  return p.tracer.rect_at(camera_pose(p, T_world_body), px, py);
}

std::unique_ptr<SceneRenderer> make_lab_renderer(const LabDescription& lab, const CamerasConfig& cameras,
                                                 std::optional<TexturedHeadModel> head, unsigned seed, LabRenderOptions options,
                                                 const CameraMounts& mounts) {
  return std::make_unique<LabRenderer>(lab, cameras, std::move(head), seed, options, mounts);
}

}  // namespace labo::sim
