#include "bench/experiments/model_lab.hpp"

namespace labo::bench {

Eigen::Isometry3d facing_base(const Eigen::Vector3d& at) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = at;
  return T;
}

fusion::LabGeometry model_lab() {
  fusion::LabGeometry lab;
  lab.room_min = {-1.0, -3.0, 0.0};
  lab.room_max = {5.0, 3.0, 2.6};
  lab.base = {0, 0, 0};
  fusion::PlanarTarget osc;
  osc.id = "oscilloscope";
  osc.name = "Oscilloscope";
  osc.T_world_object = facing_base({3.5, 0.3, 1.0});
  osc.width_m = 0.4;
  osc.height_m = 0.25;
  lab.instruments.push_back(osc);
  lab.platform.id = "platform";
  lab.platform.name = "Charging platform";
  lab.platform.T_world_object.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();  // z down into the platform
  lab.platform.width_m = 0.6;
  lab.platform.height_m = 0.6;
  return lab;
}

}  // namespace labo::bench
