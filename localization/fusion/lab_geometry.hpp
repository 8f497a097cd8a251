#pragma once
// What flight control needs to know of the lab: the room (geofence), the base (home), the instruments
// that can be inspected and the landing platform, each with what its vision front-end needs (template
// image, physical size, the paper's per-object lambda and N), and the surfaces over the floor. Built
// from the lab description (drone/lab/lab_description.hpp) by lab_geometry_from(), so control does not
// depend on how the lab file is laid out; tests and the model experiments build one by hand.
// Nothing of the teacher: where they walk and how fast is no part of what the flight software knows
// (face-follow finds and follows them from the face alone; tests/bench/experiments/world_separation_test.cpp).
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "localization/estimation/surface_map.hpp"

namespace labo::lab {
struct LabDescription;
struct InstrumentSpec;
}  // namespace labo::lab

namespace labo::fusion {

// A planar target: object frame at the panel's centre, x right, y down, z into the panel.
struct PlanarTarget {
  std::string id;
  std::string name;
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
  double width_m = 0;
  double height_m = 0;
  // For the vision front-end: the panel's template image (empty: no template known, e.g. the model
  // lab, where perception is modelled) and the object's own lambda (SIFT closer, template matching
  // farther) and N (minimum SIFT inliers); unset means the "vision" section's defaults.
  std::filesystem::path template_path;
  std::optional<double> sift_switch_distance_m;
  std::optional<int> sift_min_inliers;
};

struct LabGeometry {
  Eigen::Vector3d room_min = Eigen::Vector3d(-3, -3, 0);
  Eigen::Vector3d room_max = Eigen::Vector3d(3, 3, 2.5);
  Eigen::Vector3d base = Eigen::Vector3d::Zero();  // the charging platform's centre, world frame
  double base_yaw_rad = 0;
  std::vector<PlanarTarget> instruments;
  PlanarTarget platform;
  // The tops the ultrasound sees (benches, the platform, instrument housings) over the floor, for the
  // altitude tracker to tell a floor step from a climb; empty: floor only, steps told by gamma alone.
  estimation::SurfaceMap surfaces;

  const PlanarTarget* find_instrument(const std::string& id) const;
};

// The room, the base (the drone's pose on the platform's top), every instrument's front panel and
// the platform's top as planar targets with their templates and per-object thresholds, and the
// surfaces under the drone (bench, platform and housing tops).
LabGeometry lab_geometry_from(const lab::LabDescription& lab);
// One instrument of a lab description as a planar target.
PlanarTarget planar_target_of(const lab::InstrumentSpec& spec);

}  // namespace labo::fusion
