#include "server/runtime/lab_outline.hpp"

#include <cmath>

namespace labo::server {

using lab::BenchSpec;
using lab::Box3;
using lab::LabDescription;


namespace {

LabFootprint footprint(const std::string& id, const Box3& box) {
  return {id, box.min.x(), box.min.y(), box.max.x(), box.max.y(), box.min.z(), box.max.z()};
}

}  // namespace

LabOutline lab_outline_from(const LabDescription& lab) {
  LabOutline o;
  o.known = true;
  o.room = footprint("room", lab.room);
  for (const BenchSpec& b : lab.benches) o.benches.push_back(footprint(b.id, b.box));
  o.platform = footprint(lab.platform.id.empty() ? "platform" : lab.platform.id, lab.platform.box());
  const Eigen::Matrix3d R = lab.T_world_base.linear();
  o.base_x_m = lab.T_world_base.translation().x();
  o.base_y_m = lab.T_world_base.translation().y();
  o.base_yaw_rad = std::atan2(R(1, 0), R(0, 0));
  return o;
}

}  // namespace labo::server
