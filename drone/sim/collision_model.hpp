#pragma once
// CollisionModel: what the simulated AR.Drone's hull can touch in the lab. The hull is a vertical
// cylinder (the indoor hull seen from above is a disc about 0.52 m across) standing on its underside,
// whose centre is the body origin of the simulation (so the ultrasound range is the underside's
// height above the surface below). Walls, ceiling, benches, instrument housings, the platform's sides
// and the teacher's body are obstacles; a top face the hull is above is a support, not an obstacle,
// so the drone can land on the platform or a bench and take off again.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "drone/lab/lab_description.hpp"

namespace labo::sim {

struct HullShape {
  double radius_m = 0.26;  // indoor hull, 0.52 m across
  double height_m = 0.12;
};

class CollisionModel {
 public:
  CollisionModel(const lab::LabDescription& lab, HullShape hull);

  // The teacher's body, a vertical cylinder on the floor; absent by default.
  void set_teacher(const std::optional<Eigen::Vector2d>& floor_xy, double radius_m, double height_m);

  // What the hull with its underside centre at `p` penetrates ("wall_xmax", "ceiling", a bench's or
  // instrument's id, "platform", "teacher"), or nothing.
  std::optional<std::string> obstacle_hit(const Eigen::Vector3d& p) const;
  // The highest top face under the hull's footprint that the underside at `p` is above (within
  // 2 cm): where the drone rests when it touches down. The floor when nothing else is below.
  double support_height(const Eigen::Vector3d& p) const;

  const HullShape& hull() const { return hull_; }
  const lab::Box3& room() const { return room_; }

 private:
  struct Obstacle {
    std::string id;
    lab::Box3 box;
  };
  bool footprint_overlaps(const Eigen::Vector3d& p, const lab::Box3& box) const;

  HullShape hull_;
  lab::Box3 room_;
  std::vector<Obstacle> obstacles_;
  std::optional<Eigen::Vector2d> teacher_xy_;
  double teacher_radius_m_ = 0, teacher_height_m_ = 0;
};

}  // namespace labo::sim
