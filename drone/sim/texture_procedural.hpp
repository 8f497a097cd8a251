#pragma once
// Procedural textures of the simulated lab's surfaces: painted walls with notice boards, sockets and
// cable ducts; a tiled floor with scuffs; ceiling tiles with lights; bench laminate; instrument housings;
// the platform's sides. All rich in corners at every scale the cameras see them (SLAM and the bottom
// camera's optical flow need texture), except the bare areas, painted one flat colour (vision must fail
// there). Deterministic: the same seed draws the same pixels.
#include <opencv2/core.hpp>
#include <vector>

namespace labo::sim {

enum class SurfaceMaterial { Wall, Floor, Ceiling, BenchTop, BenchSide, Housing, PlatformSide };

struct SurfaceTextureRequest {
  SurfaceMaterial material = SurfaceMaterial::Wall;
  double width_m = 1, height_m = 1;   // the surface, along the texture's u (right) and v (down)
  double metres_per_texel = 0.005;
  unsigned seed = 1;
  std::vector<cv::Rect2d> bare_m;     // rectangles (metres, texture axes from the top-left) left untextured
};

// BGR, ceil(width_m / metres_per_texel) x ceil(height_m / metres_per_texel) texels.
// Throws std::invalid_argument for a non-positive size or a texture over 4096 texels a side.
cv::Mat draw_surface_texture(const SurfaceTextureRequest& request);

// The texel size used for each material (finer where the drone flies close).
double metres_per_texel(SurfaceMaterial material);

}  // namespace labo::sim
