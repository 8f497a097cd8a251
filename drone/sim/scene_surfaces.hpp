#pragma once
// The lab's static geometry as the renderer traces it: textured rectangles. The room's six inner faces
// (the shell, behind everything else), the benches' faces, each instrument's front panel (its template
// image at its physical size) and housing, and the landing platform (its pattern on top, 10 cm sides).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "drone/lab/lab_description.hpp"
#include "drone/sim/texture_map.hpp"

namespace labo::sim {

// A rectangle seen from the side its normal points to: point = origin + a * axis_u + b * axis_v with
// a in [0, size_u], b in [0, size_v]. Texel of (a, b): (a * texels_per_m_u - 0.5, b * texels_per_m_v - 0.5).
struct SceneRect {
  std::string name;  // "floor", "wall_xmin", "bench_east.top", "oscilloscope.panel", ...
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX(), axis_v = Eigen::Vector3d::UnitY();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double size_u = 1, size_v = 1;
  int texture = 0;
  double texels_per_m_u = 1, texels_per_m_v = 1;
  bool room_shell = false;  // a face of the room: every other surface is in front of it
};

struct LabScene {
  std::vector<SceneRect> rects;
  std::vector<TextureMap> textures;

  // Index of the rect named `name`, -1 when none.
  int find(const std::string& name) const;
};

// Builds the static scene; procedural textures drawn from lab.texture_seed. Throws std::runtime_error
// naming the file when an instrument's template image is missing or cannot be decoded.
LabScene build_lab_scene(const lab::LabDescription& lab);
// An instrument placed after the scene was built (an admin's upload): its panel and housing appended,
// the housing's textures drawn from `seed`. Throws as build_lab_scene does.
void append_instrument(LabScene& scene, const lab::InstrumentSpec& instrument, unsigned seed);

}  // namespace labo::sim
