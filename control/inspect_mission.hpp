#pragma once
// Inspect an instrument: the paper's §6.2, stages 1-6.
//  1 init: take off, climb, wait for SLAM to initialize, slow up/down manoeuvre for the scale;
//  2 detect: face the instrument, detect it (template matching far, SIFT near) and place it in the world;
//  3 inspect: approach to the standoff with the panel centred (homography feedback near), hold for
//    the requested time; if the instrument is lost, re-detect (never push blindly): back off along the
//    line of sight, or, when a vertical push took the panel out of view, return to the standoff's
//    altitude first;
//  4-6 return, platform, land (HomeLanding).
#include "control/home_landing.hpp"
#include "control/take_off_and_scale.hpp"

namespace labo::control {

class InspectMission final : public Mission {
 public:
  InspectMission(fusion::PlanarTarget instrument, double hold_s, double standoff_m, Seconds t);
  std::string name() const override { return "inspect"; }
  MissionOutcome step(MissionContext& ctx) override;
  int stage_index() const override;
  int stage_count() const override { return 6; }
  std::string stage() const override { return stage_text_; }
  bool needs_visual_localization() const override;
  bool tolerates_dead_reckoning() const override;
  std::string inspected_instrument() const override { return instrument_.id; }

  double held_s() const { return held_s_; }

 private:
  enum class Step { Init, Detect, Approach, Hold, Redetect, Leave, Home };
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    fresh_ = true;
  }
  void step_detect(MissionContext& ctx);
  void step_inspect(MissionContext& ctx);
  bool instrument_seen(const MissionContext& ctx) const;
  // The estimate is above or below the standoff by more than the panel's view allows.
  bool lost_vertically(const MissionContext& ctx, const PoseTarget& standoff) const;
  // The estimate has run on dead reckoning (no vision source) too long for stages that need the panel.
  bool on_dead_reckoning_too_long(const MissionContext& ctx);
  // Camera to the panel's plane, horizontally along the panel's normal (m).
  double distance_along_line_of_sight(const MissionContext& ctx) const;
  std::string describe(Seconds t) const;

  fusion::PlanarTarget instrument_;
  double hold_s_;
  double standoff_m_;
  Step step_ = Step::Init;
  Seconds since_ = 0;
  bool fresh_ = true;
  TakeOffAndScale init_;
  int placements_ = 0;
  Eigen::Isometry3d T_world_instrument_ = Eigen::Isometry3d::Identity();
  double held_s_ = 0;
  Seconds last_t_ = -1;
  Seconds lost_since_ = -1;
  Seconds dead_reckoning_since_ = -1;
  bool backed_off_ = false;  // re-detection: backed off along the line of sight (else realigned first)
  bool heading_back_ = false;  // re-detection: the panel was seen again, flying to the standoff
  HomeLanding home_;
  std::string stage_text_ = "1 init: taking off";
};

}  // namespace labo::control
