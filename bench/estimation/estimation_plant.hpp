#pragma once
// EstimationPlant: what the estimation experiments (`labodrone-bench sim estimate`) fly: a drone that takes
// commands, advances in lockstep, delivers navdata (and, when asked for, camera frames) as they arrive
// on the link, and exposes its ground truth. Implemented by LabPlant (the simulated lab behind
// SimDroneLink, lab_plant.hpp) and SurrogatePlant (a stand-in with its own physics, kept for
// comparison).
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/estimation/surface_map.hpp"

namespace labo::bench {

struct GroundTruth {
  Seconds t = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();
  double yaw_rate = 0;
};

// The instrument the servo experiments face: its id (for the real planar front-end) and its panel's
// pose (object frame: x to the panel's right, y down, z into the panel).
struct PlantInstrument {
  std::string id;
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
};

// How a plant for one run is made.
struct PlantRequest {
  unsigned seed = 1;
  Seconds navdata_period = 1.0 / 200.0;
  bool video = false;  // render and deliver camera frames (real vision); otherwise none are made
  bool flat_trim = true;  // calibrate the IMU's roll/pitch on the ground before the take-off
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
  // The camera frames that arrived during the last step(), in order (empty without video).
  virtual const std::vector<VideoFrame>& frames_of_last_step() const = 0;
  virtual GroundTruth truth() const = 0;
  // What the drone crashed into (a wall, a bench...), empty while it has not crashed.
  virtual std::string crash() const = 0;
  // An external push: an instantaneous change of the world velocity.
  virtual void push(const Eigen::Vector3d& delta_v_world) = 0;
  // The upward push that lifts this plant's drone by about `metres` under the experiments' z loop
  // (its vertical response differs per plant; the results report the peak displacement reached).
  virtual double vertical_push_for(double metres) const = 0;
  // The surfaces below the flight area (floor, benches, platform), for the altitude tracker.
  virtual estimation::SurfaceMap surfaces() const = 0;
  virtual PlantInstrument instrument() const = 0;
  // The true link timing: from move() until the motors act (mean), from capture to a frame's arrival.
  virtual Seconds command_latency() const = 0;
  virtual Seconds video_delay() const = 0;
  // From measurement to a navdata packet's arrival.
  virtual Seconds navdata_delay() const = 0;
};

}  // namespace labo::bench
