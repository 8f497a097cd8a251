#include "control/platform_search_pattern.hpp"

namespace labo::control {

std::vector<Eigen::Vector2d> platform_search_offsets(double step_m, int rings) {
  std::vector<Eigen::Vector2d> out;
  if (step_m <= 0 || rings <= 0) return out;
  // Each ring counter-clockwise from its +x side: the corners and the sides' middles, so that no
  // leg is longer than the ring's radius.
  const Eigen::Vector2d unit[] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  for (int k = 1; k <= rings; ++k)
    for (const auto& u : unit) out.push_back(u * (k * step_m));
  out.emplace_back(0, 0);
  return out;
}

}  // namespace labo::control
