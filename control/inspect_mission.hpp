#pragma once
// Inspect an instrument: the paper's §6.2, stages 1-6.
//  1 init: take off, climb, wait for SLAM to initialize, slow up/down manoeuvre for the scale;
//  2 detect: face the instrument (from a viewpoint on its normal when it would be seen too
//    obliquely from where the drone is), detect it (template matching far, SIFT near) and place it in the world;
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
  // Where stage 2 looks from: here, turned towards the panel, or (seen more obliquely than
  // detect_max_oblique_deg) a point on the panel's normal at the cruise altitude, facing it.
  // Sets view_ (None when the search starts where the drone is).
  PoseTarget detection_viewpoint(const MissionContext& ctx);
  // The panel's outward normal, horizontal, not normalized (zero for a panel lying flat).
  Eigen::Vector3d outward_normal() const;
  // The angle between the panel's outward normal and the line from it to `from`, horizontally.
  double oblique_rad(const Eigen::Vector3d& from) const;
  // Stage 2 on the way to its viewpoint: false while flying there (heading kept) or turning there
  // (each phase ends when reached, or after kViewpointTimeoutS).
  bool at_detection_viewpoint(MissionContext& ctx);
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
  // Stage 2's viewpoint: flown to with the heading the map was built with (a monocular map does not
  // survive a 90-degree turn, and the safety monitor would stop a flight on dead reckoning), then
  // turned to the panel, which gives the homography once detected.
  enum class View { None, Travel, Turn };
  View view_ = View::None;
  bool from_viewpoint_ = false;  // stage 2 flies to a viewpoint and searches from there
  PoseTarget viewpoint_;
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
