#pragma once
// Stage 5's search for the charging platform when the bottom camera does not see it above the
// estimated base: the estimate after the way home (dead reckoning while SLAM relocalizes) can be off
// by more than the camera's footprint, and hovering on over the wrong spot finds nothing. The drone
// flies square rings round the estimated base, each `step_m` wider than the last, so that
// neighbouring views overlap when step_m is below the footprint's short side (about 0.8 m from the
// return altitude with the AR.Drone's or the Tello EDU's bottom camera), and ends back above the base.
#include <Eigen/Core>
#include <vector>

namespace labo::control {

// Offsets from the estimated base (m, in the world's x-y), ring by ring, the base itself last; empty
// when step_m <= 0 or rings <= 0 (no search).
std::vector<Eigen::Vector2d> platform_search_offsets(double step_m, int rings);

}  // namespace labo::control
