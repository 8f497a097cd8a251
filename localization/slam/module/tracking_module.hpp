#pragma once
// TrackingModule: every frame once the map exists (PTAM's tracker). track() is these steps, in order:
//   follow_map_corrections        a loop closure moved the map: the motion model's poses follow it
//   predict_pose                  where to search from: the relocalizer's pose when lost, else the
//                                 caller's prior, else the motion model (and whether to search coarse)
//   search_map                    FrameTracker: coarse search, fine search, pose update
//   follow_concurrent_correction  the mapper corrected the map during the search: carry the pose
//                                 over when it moved little, else search again
//   widen_search                  the motion model said "still" but the view jumped: coarse to fine
//   judge_quality                 Good, Dodgy or Lost, from found / attempted and the points found
//   lose_frame | accept_pose      Lost frames count towards relocalizing; a pose moves the model on
//   keyframe_wanted               module/keyframe_policy, the interval, the map's size, the mapper's queue
//   make_keyframe                 the frame and its matches, for the caller to hand to the mapper
// The tracking state (Initializing until the map starts) lives here; the map and the mapper are
// read only.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/module/frame_tracker.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/module/motion_model.hpp"
#include "localization/slam/module/relocalizer.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam {

// The frame being tracked, as the feature extractor left it.
struct CurrentFrame {
  const cv::Mat& gray;
  Seconds t = 0;
  const FrameFeatures& features;
  const FeatureGrid& grid;
  const std::vector<cv::Mat>& pyramid;
  const std::optional<Eigen::Vector3d>& down_cam;  // the IMU's gravity direction, when the prior is on
};

struct TrackedFrame {
  SlamResult result;
  std::optional<Keyframe> new_keyframe;  // for the mapper
};

class TrackingModule {
 public:
  TrackingModule(const IdealCamera& camera, const SlamSettings& settings, const SlamMap& map, const LocalMapper& mapper);

  TrackingState state() const { return state_; }
  const std::optional<Eigen::Isometry3d>& last_pose() const { return motion_.last(); }

  // The map was just started (initialize/map_start): Good, moving as from keyframe 0 to keyframe 1.
  void start(Seconds reference_t, Seconds t);
  // prior_T_cam_map, when given, replaces the motion model's prediction.
  TrackedFrame track(const CurrentFrame& frame, const std::optional<Eigen::Isometry3d>& prior_T_cam_map);
  // The map was cleared: Initializing.
  void clear();
  // Another map was loaded: Lost until the relocalizer finds it.
  void relocalize_in_new_map();

 private:
  struct PosePrediction {
    Eigen::Isometry3d T_cam_map = Eigen::Isometry3d::Identity();
    bool coarse = true;  // start with the coarse search
  };

  std::optional<Similarity3> follow_map_corrections();
  std::optional<GravityPrior> gravity_prior(const CurrentFrame& frame) const;
  std::optional<PosePrediction> predict_pose(const CurrentFrame& frame, const std::optional<Eigen::Isometry3d>& prior);
  TrackOutcome search_map(const CurrentFrame& frame, const Eigen::Isometry3d& T_cam_map, bool coarse,
                          const std::optional<GravityPrior>& gravity);
  void follow_concurrent_correction(const CurrentFrame& frame, const std::optional<GravityPrior>& gravity,
                                    PosePrediction& prediction, TrackOutcome& o);
  void widen_search(const CurrentFrame& frame, const std::optional<GravityPrior>& gravity, const PosePrediction& prediction,
                    TrackOutcome& o);
  TrackingState judge_quality(const TrackOutcome& o, double quality) const;
  void lose_frame(const TrackOutcome& o, SlamResult& result);
  void accept_pose(const TrackOutcome& o, TrackingState frame_state, Seconds t, SlamResult& result);
  bool keyframe_wanted(const TrackOutcome& o, TrackingState frame_state, Seconds t) const;
  Keyframe make_keyframe(const TrackOutcome& o, const CurrentFrame& frame);
  void clear_tracking();

  const IdealCamera& camera_;
  SlamSettings settings_;
  const SlamMap& map_;
  const LocalMapper& mapper_;
  FrameTracker tracker_;
  Relocalizer relocalizer_;
  MotionModel motion_;

  TrackingState state_ = TrackingState::Initializing;
  int bad_frames_ = 0;
  bool relocalizing_ = false;
  int reference_keyframe_ = -1;
  int map_generation_ = 0;  // the last map correction this tracker's poses follow
  Seconds last_keyframe_t_ = -1e9;
};

}  // namespace labo::slam
