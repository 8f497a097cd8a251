#pragma once
// LockstepDroneLink: a DroneLink that runs a simulated drone on a simulated clock, driven by its
// caller: advance_to(t) runs the drone, the link and the listener's callbacks up to t. The lockstep
// experiments fly either model through it (SimDroneLink: the AR.Drone 2.0; SimTelloLink: the Tello).
#include "drone/drone_link.hpp"

namespace labo::sim {

class LockstepDroneLink : public DroneLink {
 public:
  virtual void advance_to(Seconds t) = 0;
  virtual Seconds now() const = 0;
};

}  // namespace labo::sim
