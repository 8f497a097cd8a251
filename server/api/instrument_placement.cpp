#include "server/api/instrument_placement.hpp"

#include <cstdio>

namespace labo::server {

using lab::Box3;
using lab::InstrumentSpec;


namespace {

Box3 box_of(const LabFootprint& f) { return {{f.min_x_m, f.min_y_m, f.min_z_m}, {f.max_x_m, f.max_y_m, f.max_z_m}}; }

std::string metres(const Eigen::Vector3d& p) {
  char text[64];
  std::snprintf(text, sizeof text, "[%.2f, %.2f, %.2f] m", p.x(), p.y(), p.z());
  return text;
}

}  // namespace

std::string placement_problem(const InstrumentSpec& instrument, const LabOutline& lab) {
  if (!lab.known) return {};
  const Box3 bounds = instrument.bounds();
  const Box3 room = box_of(lab.room);
  if (!room.contains(bounds.min, 1e-6) || !room.contains(bounds.max, 1e-6))
    return "the panel and its housing (" + metres(bounds.min) + " to " + metres(bounds.max) + ") are not inside the room (" +
           metres(room.min) + " to " + metres(room.max) + ")";
  for (const LabFootprint& bench : lab.benches)
    if (bounds.overlaps(box_of(bench)))
      return "the panel and its housing overlap bench '" + bench.id + "' (" + metres(box_of(bench).min) + " to " +
             metres(box_of(bench).max) + "): on a bench, its bottom edge is at or above the top";
  if (bounds.overlaps(box_of(lab.platform))) return "the panel and its housing overlap the landing platform";
  return {};
}

}  // namespace labo::server
