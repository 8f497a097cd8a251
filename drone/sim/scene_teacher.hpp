#pragma once
// The teacher as the cameras see them: a body (a cylinder from the floor to the shoulders, shirt over
// trousers), a neck, the back and sides of the head (an ellipsoid with hair), and the face: the
// CANDIDE-3 mesh textured from a photograph (head_model.hpp). The body stands at
// SceneState::teacher_floor_xy facing where the face looks; the head is at SceneState::T_world_head.
#include <Eigen/Geometry>
#include <optional>

#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "drone/sim/render_mesh_rasterizer.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo::sim {

// The teacher's meshes in one camera for one frame.
struct TeacherProjection {
  ProjectedMesh body, neck, head_back, face;
  bool has_face = false;
  PixelBounds box;  // pixels the teacher may cover; empty when out of view
};

class TeacherFigure {
 public:
  // Without a head model the face is left out (the head is the plain ellipsoid).
  // Throws std::invalid_argument when `head` fails validate().
  TeacherFigure(const lab::TeacherSpec& spec, std::optional<TexturedHeadModel> head);

  // Projects the teacher for a camera at T_world_cam; out.box is empty when the teacher is absent or out of view.
  void project(const SceneState& scene, const Eigen::Isometry3d& T_world_cam, const PinholeCamera& camera, float max_radius,
               TeacherProjection& out) const;
  void draw(const TeacherProjection& projection, FrameTarget target) const;

  bool has_face() const { return face_.has_value(); }
  // The body's pose: at the floor position, turned to where the face looks.
  static Eigen::Isometry3d body_pose(const SceneState& scene);

 private:
  RenderMesh body_, neck_, head_back_;
  std::optional<RenderMesh> face_;
};

}  // namespace labo::sim
