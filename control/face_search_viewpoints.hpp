#pragma once
// Where find-teacher looks for a face when it has none: viewpoints over the free floor, each swept
// with a full turn of yaw. The face detector finds a frontal face within about 2.5 m
// (docs/control.md), and the teacher may be anywhere on the floor, walking anywhere: the viewpoints
// are the centres of a grid of cells no larger than `spacing_m` over the fence's floor, dropped where
// a bench, an instrument or the platform lies within `clearance_m` (the teacher walks the free floor,
// and a drone hovering over a bench top reads a step on the ultrasound). Toured nearest first.
#include <Eigen/Core>
#include <vector>

#include "control/geofence.hpp"
#include "localization/estimation/surface_map.hpp"

namespace labo::control {

std::vector<Eigen::Vector3d> face_search_viewpoints(const Geofence& fence, const estimation::SurfaceMap& surfaces,
                                                    double height_m, double spacing_m, double clearance_m);

// The viewpoints in the order a tour from `start` visits them: each time the nearest not yet visited.
std::vector<Eigen::Vector3d> tour_from(const Eigen::Vector3d& start, std::vector<Eigen::Vector3d> viewpoints);

}  // namespace labo::control
