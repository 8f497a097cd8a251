#pragma once
// EstimationPlant: what the estimation experiments (`labodrone sim estimate`) fly: a drone that takes
// commands, advances in lockstep, delivers navdata as it arrives on the link, and exposes its ground
// truth. Implemented by SurrogatePlant (this folder, a stand-in with its own physics until the
// simulated lab's SimDroneLink is merged) and meant to be implemented over SimDroneLink.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/estimation/surface_map.hpp"

namespace labo {

struct GroundTruth {
  Seconds t = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();
  double yaw_rate = 0;
};

class EstimationPlant {
 public:
  virtual ~EstimationPlant() = default;
  virtual std::string name() const = 0;
  virtual Seconds now() const = 0;
  // A command sent now (it reaches the motors after the link's and the firmware's delay).
  virtual void move(const MoveCommand& command) = 0;
  // Advances by dt; navdata packets arriving meanwhile are appended to `arrived` (receive stamps).
  virtual void step(Seconds dt, std::vector<NavdataSample>& arrived) = 0;
  virtual GroundTruth truth() const = 0;
  // An external push: an instantaneous change of the world velocity.
  virtual void push(const Eigen::Vector3d& delta_v_world) = 0;
  // The surfaces below the flight area (floor, benches, platform), for the altitude tracker.
  virtual SurfaceMap surfaces() const = 0;
};

}  // namespace labo
