#pragma once
// FlatSceneRenderer: the FALLBACK camera renderer of the simulated lab, used until the textured
// LabRenderer (drone/sim/lab_renderer.hpp) is available; drone/sim/sim_setup.hpp picks the renderer.
// It is simple but honest geometry, not a stand-in picture:
//  - the room's floor (a tile pattern with scattered marks, bare areas plain), walls with posters
//    (bare areas plain) and ceiling; benches and instrument housings as flat-shaded boxes; the
//    instrument panels and the landing pattern textured with their real templates through the exact
//    plane-to-image homography (from a mip level that avoids aliasing); the teacher as two boxes;
//  - the camera model of core/camera_model.hpp: a pinhole render on a canvas large enough for the
//    lens, then the Brown-Conrady distortion applied by a precomputed remap, so a point lands where
//    PinholeCamera::project says (cameras mounted as in core/frames.hpp);
//  - polygons clipped to the view frustum, back faces culled, objects painted far to near (no
//    z-buffer: an instrument seen from below its bench's top edge is drawn over the edge).
// What it lacks next to LabRenderer: textured walls and floor rich in corners, the CANDIDE-3 head,
// motion blur, sensor noise. Not thread-safe (scratch buffers); no allocation per frame once warm.
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo {

class FlatSceneRenderer final : public SceneRenderer {
 public:
  FlatSceneRenderer(const LabDescription& lab, const CamerasConfig& cameras);
  void render(CameraId camera, const SceneState& scene, cv::Mat& bgr) override;

 private:
  struct Quad {
    std::array<Eigen::Vector3d, 4> corners;  // world; textured: top-left, top-right, bottom-right, bottom-left
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // outward; zero: never culled
    cv::Scalar colour;
    int texture = -1;
  };
  // A solid: its faces and a centre to sort by.
  struct Solid {
    std::vector<Quad> faces;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    int layer = 0;  // drawn in layer order, then far to near: benches, platform, instruments, teacher
  };
  struct Texture {
    std::vector<cv::Mat> levels;  // mip pyramid
    double width_m = 0, height_m = 0;
  };
  struct View {
    PinholeCamera camera = PinholeCamera::ardrone2_front();
    Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
    cv::Matx33d K_canvas;
    cv::Size canvas_size;
    Eigen::Vector4d frustum = Eigen::Vector4d::Zero();  // normalised x min, x max, y min, y max
    bool distorted = false;
    cv::Mat canvas, map1, map2, warp, mask;
  };

  void build_room(const LabDescription& lab);
  void build_objects(const LabDescription& lab);
  void build_view(View& view, const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& T_body_cam);
  void add_teacher(const SceneState& scene);
  bool project_quad(const View& view, const Eigen::Isometry3d& T_cam_world, const Quad& quad);
  void draw_quad(cv::Mat& target, const View& view, const Eigen::Isometry3d& T_cam_world, const Quad& quad);
  void draw_textured(cv::Mat& target, View& view, const Eigen::Isometry3d& T_cam_world, const Quad& quad);
  // Clips the camera-frame polygon in clip_a_ to the frustum; returns the vertex count (0: invisible).
  int clip_to_frustum(const View& view, int n);

  LabDescription lab_;
  std::vector<Quad> room_;
  std::vector<Solid> solids_;    // fixed ones, then the teacher's (rebuilt per frame)
  std::size_t fixed_solids_ = 0;
  std::vector<Texture> textures_;
  std::array<View, 2> views_;
  double teacher_eye_height_m_ = 1.65, teacher_body_radius_m_ = 0.25;

  // Per-frame scratch.
  std::vector<std::pair<double, std::size_t>> order_;
  std::array<Eigen::Vector3d, 16> clip_a_, clip_b_;
  std::vector<cv::Point> polygon_;
};

}  // namespace labo
