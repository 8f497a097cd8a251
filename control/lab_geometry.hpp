#pragma once
// What flight control needs to know of the lab: the room (geofence), the base (home), the instruments
// that can be inspected and the landing platform. Built from the sim's LabDescription
// (drone/lab/lab_description.hpp) by lab_geometry_from() so control does not depend on how the lab
// file is laid out.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace labo {

// A planar target: object frame at the panel's centre, x right, y down, z into the panel.
struct PlanarTarget {
  std::string id;
  std::string name;
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
  double width_m = 0;
  double height_m = 0;
};

struct LabGeometry {
  Eigen::Vector3d room_min = Eigen::Vector3d(-3, -3, 0);
  Eigen::Vector3d room_max = Eigen::Vector3d(3, 3, 2.5);
  Eigen::Vector3d base = Eigen::Vector3d::Zero();  // the charging platform's centre, world frame
  double base_yaw_rad = 0;
  std::vector<PlanarTarget> instruments;
  PlanarTarget platform;

  const PlanarTarget* find_instrument(const std::string& id) const;
};

}  // namespace labo
