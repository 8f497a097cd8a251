#pragma once
// Triangle meshes drawn over the traced scene with a depth test: the teacher's body and head. Vertices
// are projected through the real camera model (distortion included); inside a triangle, depth and
// texture coordinates are interpolated perspective-correctly. Meshes are small on screen, so the
// straight edges between projected vertices are a fine approximation of the lens' curvature.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera_model.hpp"
#include "drone/sim/texture_map.hpp"

namespace labo::sim {

struct RenderMesh {
  enum class Culling {
    Outward,      // a closed surface: triangles wound counter-clockwise seen from outside
    TextureSide,  // a textured sheet: a triangle is seen from the front when its image and its
                  // texture coordinates have the same orientation (the photograph saw it from the front)
  };
  std::vector<Eigen::Vector3f> vertices;  // the mesh's own frame, metres
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::uint32_t> colours;      // per vertex, when not textured
  std::vector<Eigen::Vector2f> texture_px; // per vertex, when textured
  TextureMap texture;
  bool textured = false;
  Culling culling = Culling::Outward;
  float depth_bias_m = 0;  // added to the depth it writes: a positive bias lets nearer meshes draw over it
};

struct PixelBounds {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  void include(float x, float y);
};

// A mesh's vertices in one camera: pixel, depth, and whether the vertex can be drawn (in front of the
// camera and within the lens' field).
struct ProjectedMesh {
  std::vector<Eigen::Vector2f> px;
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<std::uint8_t> front;  // per triangle: facing the camera
};

// Colour and depth planes of one frame (row-major, width x height).
struct FrameTarget {
  int width = 0, height = 0;
  std::uint32_t* colour = nullptr;
  float* depth = nullptr;
};

// Projects `mesh` placed at T_cam_mesh; grows `box` by the triangles that will be drawn.
// `max_radius` is CameraRays::max_radius(): vertices farther off-axis are not drawn.
void project_mesh(const RenderMesh& mesh, const Eigen::Isometry3d& T_cam_mesh, const PinholeCamera& camera, float max_radius,
                  ProjectedMesh& out, PixelBounds& box);

// Draws the front-facing triangles whose three vertices are valid, where nearer than `target.depth`.
void rasterize_mesh(const RenderMesh& mesh, const ProjectedMesh& projected, FrameTarget target);

}  // namespace labo::sim
