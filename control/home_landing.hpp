#pragma once
// Return to the base and land on the charging platform: the paper's stages 4-6, shared by the inspect
// mission and return-home. Climb to the return altitude where the drone is, fly above the base (SLAM
// feedback), switch to the bottom camera and find the platform, hover above its centre, land.
#include <vector>

#include "control/mission.hpp"

namespace labo::control {

class HomeLanding {
 public:
  enum class Step { Climb, Travel, FindPlatform, Centre, Land, Landed, Failed };
  void start(Seconds t) {
    enter(Step::Climb, t);
    fresh_ = true;
  }
  // Running until Landed (success) or Failed.
  Step step(MissionContext& ctx);
  Step current() const { return step_; }
  std::string describe(Seconds t) const;
  const std::string& failure() const { return failure_; }
  // Paper stage of the current step: 4 return, 5 platform, 6 landing.
  int paper_stage() const;
  // Seconds since the search round the base began (0 when not searching).
  double searching_s(Seconds t) const {
    return step_ == Step::FindPlatform && search_started_ >= 0 ? t - search_started_ : 0.0;
  }

 private:
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    centred_since_ = -1;
  }
  void step_now(MissionContext& ctx, const Eigen::Vector3d& here, double yaw, const Eigen::Vector3d& base);
  void find_platform(MissionContext& ctx, const Eigen::Vector3d& base);
  // The platform not in view: the next point of the search round the base; false when the search
  // is over (or off) and the drone should land where it is.
  bool search_on(MissionContext& ctx, const Eigen::Vector3d& base);

  Step step_ = Step::Climb;
  Seconds since_ = 0;
  Seconds centred_since_ = -1;  // Centre: settled above the platform's centre since then (-1: not)
  bool fresh_ = true;  // the step was just entered: set its target
  std::string failure_;
  bool platform_placed_ = false;
  std::vector<Eigen::Vector2d> search_;  // FindPlatform: the offsets round the base still to fly
  std::size_t search_next_ = 0;
  Seconds search_leg_since_ = -1;  // the current search point's go_to (-1: still looking from above the base)
  Seconds search_reached_at_ = -1;
  Seconds search_started_ = -1;
  Eigen::Vector3d platform_world_ = Eigen::Vector3d::Zero();
};

}  // namespace labo::control
