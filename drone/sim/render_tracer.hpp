#pragma once
// Traces the lab's static rectangles (scene_surfaces.hpp) for one camera: per frame, every rectangle
// facing the camera is moved into the camera frame and binned into the 16x16 tiles its projection
// may touch; then each tile is traced. A tile whose four corner rays hit the same rectangle, with no
// other object binned into it, is covered by that rectangle entirely (the rays that hit a convex
// polygon form a convex cone, and the room's shell is behind everything), so its pixels skip the
// visibility tests; the other tiles test their few candidates per pixel. Textures are sampled
// bilinearly at the mip level of the tile's footprint, except the instrument panels and the landing
// pattern seen from afar: each pixel is the mean of the texels its footprint covers (an area table).
// No allocation per frame.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "drone/sim/render_camera_rays.hpp"
#include "drone/sim/scene_surfaces.hpp"

namespace labo::sim {

class SceneTracer {
 public:
  struct Stats {
    int uniform_tiles = 0;  // covered by one rectangle
    int mixed_tiles = 0;    // traced pixel by pixel
    int empty_tiles = 0;    // no rectangle (the camera outside the room)
  };

  // Both must outlive the tracer.
  SceneTracer(const CameraRays& rays, const LabScene& scene);

  // Colour of every pixel (packed texels, row-major, width x height) and, inside `depth_box` (pixels,
  // may be empty), the depth along the optical axis (m; +inf where nothing is hit).
  void trace(const Eigen::Isometry3d& T_world_cam, int depth_x0, int depth_y0, int depth_x1, int depth_y1,
             std::uint32_t* colour, float* depth);

  // Mean depth of each tile's corner hits in the last frame (0 when none hit).
  const std::vector<float>& tile_depth() const { return tile_depth_; }
  const Stats& stats() const { return stats_; }
  // Which rectangle (index into LabScene::rects) the pixel's ray hits first, -1 for none; for tests.
  int rect_at(const Eigen::Isometry3d& T_world_cam, int px, int py);

 private:
  struct View {
    float nx, ny, nz, ux, uy, uz, vx, vy, vz;  // rectangle axes in the camera frame
    float num, a0, b0;                         // n.(o - c), u.(c - o), v.(c - o)
    float size_u, size_v, tpu, tpv;
    float min_x, max_x, min_y, max_y;          // projection bounds (normalized coordinates)
    int rect, texture;
    bool shell;
  };

  // A view's texture at the mip level chosen for a tile: rectangle metres to level texels.
  struct LevelMap {
    const TextureMap::Level* level;
    float ku, kv;  // level texels per metre along a, b
    // Area filtering (a texture with an area table, minified): level is level 0, and each pixel
    // records the mean of the texels under its footprint, a box of half-sizes half_u x half_v (1/256
    // level-0 texels) about the pixel's texel coordinate; null: one bilinear sample of `level`.
    const TextureMap* area = nullptr;
    std::int32_t half_u = 0, half_v = 0;
  };

  void prepare_views(const Eigen::Isometry3d& T_world_cam);
  void bin_views();
  void trace_tile(int tile, bool want_depth, std::uint32_t* colour, float* depth);
  void fill_uniform(int tile, const View& v, const LevelMap& map, bool want_depth, std::uint32_t* colour,
                    float* depth) const;
  void fill_mixed(int tile, const std::uint16_t* cand, int n, bool want_depth, std::uint32_t* colour, float* depth);
  int closest(const std::uint16_t* cand, int n, float x, float y, float& t, float& a, float& b) const;
  LevelMap level_for(const View& v, int tile) const;

  const CameraRays& rays_;
  const LabScene& scene_;
  std::vector<View> views_;
  std::vector<std::uint16_t> candidates_;   // tiles x rects
  std::vector<int> candidate_count_;
  std::vector<int> object_count_;           // candidates that are not the room's shell
  std::vector<int> first_object_;
  std::vector<float> tile_depth_;
  std::vector<LevelMap> maps_;              // per candidate of the tile being traced
  Stats stats_;
};

}  // namespace labo::sim
