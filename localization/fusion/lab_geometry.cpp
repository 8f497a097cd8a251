#include "localization/fusion/lab_geometry.hpp"

#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"

namespace labo::fusion {

using lab::InstrumentSpec;
using lab::LabDescription;


PlanarTarget planar_target_of(const InstrumentSpec& spec) {
  PlanarTarget t;
  t.id = spec.id;
  t.name = spec.name;
  t.T_world_object = spec.T_world_object;
  t.width_m = spec.width_m;
  t.height_m = spec.height_m;
  t.template_path = spec.template_path;
  t.sift_switch_distance_m = spec.sift_switch_distance_m;
  t.sift_min_inliers = spec.sift_min_inliers;
  return t;
}

const PlanarTarget* LabGeometry::find_instrument(const std::string& id) const {
  for (const auto& i : instruments)
    if (i.id == id) return &i;
  return nullptr;
}

LabGeometry lab_geometry_from(const LabDescription& lab) {
  LabGeometry g;
  g.room_min = lab.room.min;
  g.room_max = lab.room.max;
  g.base = lab.T_world_base.translation();
  g.base_yaw_rad = ypr_from_rotation(lab.T_world_base.linear())[0];
  g.instruments.reserve(lab.instruments.size());
  for (const auto& spec : lab.instruments) g.instruments.push_back(planar_target_of(spec));
  g.platform = planar_target_of(lab.platform);
  g.surfaces = estimation::surface_map_of(lab);
  return g;
}

}  // namespace labo::fusion
