#pragma once
// Ground-truth flights for the SLAM benchmark and tests, in the synthetic room (8 x 6 x 3 m): each a
// list of front-camera poses at 30 fps. All start with a hover and a 0.3-0.4 m climb (the take-off
// manoeuvre that initializes the map, as tum_ardrone's autoInit does).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace labo::bench {

struct FlightFrame {
  Seconds t;
  Eigen::Isometry3d T_world_cam;
  bool covered = false;  // camera covered (black frame): relocalization test
};

struct Flight {
  std::string name;
  std::vector<FlightFrame> frames;
  Seconds view_returns_at = -1;   // after a covered stretch, when the view comes back
  std::optional<Eigen::Vector3d> target;  // the instrument panel (approach flights): where tracking is lost
};

// Two loops around the room looking outwards at the walls (1.5-3 m), with a 1 s covered-camera
// stretch at 60% of the duration.
Flight tour_flight(Seconds duration_s = 120.0);
// Hover, then a full turn on the spot (the camera, 0.2 m ahead of the body centre, moves on a circle).
Flight yaw_flight();
// From 3.3 m to 0.8 m in front of the instrument panel at (8, 3, 1.3).
Flight approach_flight(const Eigen::Vector3d& panel_center);

}  // namespace labo::bench
