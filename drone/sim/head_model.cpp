#include "drone/sim/head_model.hpp"

#include <stdexcept>
#include <string>

namespace labo::sim {

void validate(const TexturedHeadModel& head) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("teacher head model: " + what); };
  if (head.vertices_face_m.empty()) fail("no vertices");
  if (head.triangles.empty()) fail("no triangles");
  if (head.texture_px.size() != head.vertices_face_m.size()) {
    fail(std::to_string(head.texture_px.size()) + " texture coordinates for " +
         std::to_string(head.vertices_face_m.size()) + " vertices (expected one per vertex)");
  }
  for (const auto& v : head.vertices_face_m) {
    if (!v.allFinite()) fail("a vertex is not finite");
    if (v.norm() > 1.0) fail("a vertex lies more than 1 m from the face origin (expected metres, not model units)");
  }
  const int n = static_cast<int>(head.vertices_face_m.size());
  for (const auto& t : head.triangles) {
    for (int i : t) {
      if (i < 0 || i >= n) fail("triangle index " + std::to_string(i) + " outside [0, " + std::to_string(n) + ")");
    }
  }
  if (head.texture_bgr.empty() || head.texture_bgr.type() != CV_8UC3) fail("the texture must be a non-empty 8-bit BGR image");
}

}  // namespace labo::sim
