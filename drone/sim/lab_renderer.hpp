#pragma once
// LabRenderer: the simulated lab's cameras. A software renderer of the lab description (room, benches,
// instruments with their template panels, the landing platform) and the teacher (body and textured
// head), seen through the front and bottom cameras of config (intrinsics and distortion), with motion
// blur over the shutter time, exposure gain and sensor noise. Deterministic: an image is a function of
// the lab, the cameras, the head, the seed and the SceneState only. docs/sim_rendering.md.
//
// Per frame: the static rectangles are ray traced tile by tile (render_tracer.hpp), the teacher's
// meshes rasterized over them with a depth test (scene_teacher.hpp), then blur and sensor
// (render_effects.hpp). Nothing is allocated per frame once each camera has rendered once.
#include <memory>
#include <optional>

#include "core/camera_config.hpp"
#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "drone/sim/render_camera_rays.hpp"
#include "drone/sim/render_effects.hpp"
#include "drone/sim/render_tracer.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/scene_surfaces.hpp"
#include "drone/sim/scene_teacher.hpp"

namespace labo::sim {

struct LabRenderOptions {
  double shutter_s = 0.010;     // exposure time: motion blur integrates over it
  double noise_sigma = 2.0;     // grey levels
  bool motion_blur = true;
  bool noise = true;
};

// Where the cameras sit on the body (core/frames.hpp's mountings unless a randomized world tilts them).
struct CameraMounts {
  Eigen::Isometry3d front = T_body_cam_front();
  Eigen::Isometry3d bottom = T_body_cam_bottom();
};

class LabRenderer final : public SceneRenderer {
 public:
  // `head` is the teacher's face (localization/face/teacher_head.hpp builds it from a photograph);
  // without it the teacher's head is drawn untextured. Throws std::runtime_error or
  // std::invalid_argument naming the problem (a missing template image, bad camera intrinsics, a bad
  // head model).
  LabRenderer(const lab::LabDescription& lab, const CamerasConfig& cameras, std::optional<TexturedHeadModel> head,
              unsigned seed, LabRenderOptions options = {}, const CameraMounts& mounts = {});

  void render(CameraId camera, const SceneState& scene, cv::Mat& bgr) override;
  // Its panel and housing appended to the scene; the cameras' tracers are rebuilt over it.
  void add_instrument(const lab::InstrumentSpec& instrument) override;

  const LabRenderOptions& options() const { return options_; }
  // Redraws the noise table when noise_sigma changes (not per frame).
  void set_options(const LabRenderOptions& options);
  const LabScene& scene() const { return scene_; }
  const PinholeCamera& camera(CameraId id) const;
  // The camera's nominal pose on the drone (core/frames.hpp mountings; a renderer draws through its
  // CameraMounts). A camera is never drawn lower than 1 cm above the surface under it: on the ground
  // the bottom camera's mounting is below the hull's underside, the body frame's origin.
  static Eigen::Isometry3d T_body_cam(CameraId id);
  // What the last render of `camera` did, for benchmarks.
  struct FrameStats {
    SceneTracer::Stats tracer;
    float blur_px = 0;       // largest motion over the shutter
    bool teacher_drawn = false;
  };
  const FrameStats& last_stats(CameraId camera) const;
  // The rectangle of LabScene::rects the pixel sees at this body pose (-1: none); for tests.
  int rect_at(CameraId camera, const Eigen::Isometry3d& T_world_body, int px, int py);

 private:
  struct CameraPipeline {
    CameraPipeline(const PinholeCamera& camera, const LabScene& scene, Eigen::Isometry3d T_body_cam);
    CameraRays rays;
    SceneTracer tracer;
    MotionBlur blur;
    Eigen::Isometry3d T_body_cam;
    std::vector<std::uint32_t> colour, blurred;
    std::vector<float> depth;
    TeacherProjection teacher;
    FrameStats stats;
  };
  CameraPipeline& pipeline(CameraId id);

  Eigen::Isometry3d camera_pose(const CameraPipeline& p, const Eigen::Isometry3d& T_world_body) const;

  LabRenderOptions options_;
  lab::Box3 room_;
  std::vector<lab::Box3> solids_;  // what a camera stays above, boxed once (surface_height() recomputes the boxes per call)
  LabScene scene_;
  TeacherFigure teacher_;
  unsigned seed_;
  SensorResponse sensor_;
  std::unique_ptr<CameraPipeline> front_, bottom_;
};

std::unique_ptr<SceneRenderer> make_lab_renderer(const lab::LabDescription& lab, const CamerasConfig& cameras,
                                                 std::optional<TexturedHeadModel> head, unsigned seed,
                                                 LabRenderOptions options = {}, const CameraMounts& mounts = {});

}  // namespace labo::sim
