#pragma once
// Return to the base and land on the charging platform: the paper's stages 4-6, shared by the inspect
// mission and return-home. Climb to the return altitude where the drone is, fly above the base (SLAM
// feedback), switch to the bottom camera and find the platform (searching around the base when it
// is not in view there), hover above its centre, land.
#include "control/estimate_correction.hpp"
#include "control/mission.hpp"

namespace labo::control {

class HomeLanding {
 public:
  enum class Step { Climb, Travel, FindPlatform, Centre, Land, Landed, Failed };
  void start(Seconds t) {
    enter(Step::Climb, t);
    fresh_ = true;
    search_restarts_ = 0;
  }
  // Running until Landed (success) or Failed.
  Step step(MissionContext& ctx);
  Step current() const { return step_; }
  std::string describe(Seconds t) const;
  const std::string& failure() const { return failure_; }
  // Paper stage of the current step: 4 return, 5 platform, 6 landing.
  int paper_stage() const;

 private:
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    centred_since_ = -1;
  }
  void step_now(MissionContext& ctx, const Eigen::Vector3d& here, double yaw, const Eigen::Vector3d& base);
  void start_search(Seconds t) {
    search_point_ = -1;
    leg_since_ = t;
    dwell_since_ = t;  // above the base already
  }
  // The platform lost while centring: back above the base as now estimated, and the search from there.
  void restart_search(MissionContext& ctx, const Eigen::Vector3d& base);
  // The platform not in view: the next look of the search pattern around the base, when due.
  void search(MissionContext& ctx, const Eigen::Vector3d& base);

  Step step_ = Step::Climb;
  Seconds since_ = 0;
  Seconds centred_since_ = -1;  // Centre: settled above the platform's centre since then (-1: not)
  bool fresh_ = true;  // the step was just entered: set its target
  std::string failure_;
  Eigen::Vector3d platform_world_ = Eigen::Vector3d::Zero();  // Centre: in the estimate's frame
  EstimateCorrection estimate_correction_;
  Seconds platform_seen_t_ = 0;  // Centre: the platform's last observation
  int search_restarts_ = 0;      // Centre lost the platform and searched again this many times
  // FindPlatform's search: -1 above the base, then the pattern's points, then the base again.
  int search_point_ = -1;
  Seconds leg_since_ = 0;
  Seconds dwell_since_ = -1;  // arrived at the point since then (-1: on the way)
};

}  // namespace labo::control
