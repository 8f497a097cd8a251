#pragma once
// EstimationPipeline: what turns a plant's navdata, commands and camera into the fused estimate in
// the estimation experiments: the StateEstimator and the source of its visual poses. Two kinds:
//  - TruthVisionPipeline (this folder): visual poses derived from the plant's ground truth with
//    noise and the video delay (no frames needed);
//  - the real front-ends on the plant's rendered frames (SLAM while hovering, the planar tracker on
//    the instrument): real_vision_pipeline.hpp.
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/estimation/estimation_plant.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo::bench {

// Which visual sources the experiment phase wants fused.
struct VisionWanted {
  bool slam = false;
  bool instrument = false;
};

// A SLAM camera pose as the front-end produced it (map units), for the true map scale.
struct SlamTrackPoint {
  Seconds t = 0;  // frame receive time
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  int map_id = 0;
};

class EstimationPipeline {
 public:
  virtual ~EstimationPipeline() = default;
  // What produced the visual poses, for the report.
  virtual std::string vision_input() const = 0;
  virtual void reset(const Eigen::Isometry3d& T_world_body, Seconds t) = 0;
  virtual void on_navdata(const NavdataSample& sample) = 0;
  virtual void on_command(const MoveCommand& command, Seconds t) = 0;
  // A camera frame arrived (pixels valid during the call).
  virtual void on_frame(const VideoFrame& frame) = 0;
  // The plant's truth, once per control tick at `now` (truth-derived vision only).
  virtual void on_truth(const GroundTruth& truth, Seconds now) = 0;
  virtual void set_vision(const VisionWanted& wanted) = 0;
  virtual const estimation::StateEstimator& estimator() const = 0;
  // Every good SLAM pose given to the estimator so far.
  virtual const std::vector<SlamTrackPoint>& slam_track() const = 0;
};

// Makes the pipeline of one run: the estimator's configuration, the plant it watches, the run's seed.
using PipelineFactory =
    std::function<std::unique_ptr<EstimationPipeline>(const estimation::EstimatorConfig& config, const EstimationPlant& plant, unsigned seed)>;

// A kind of pipeline for the experiments: its factory and whether its plants must render frames.
struct PipelineKind {
  std::string name;  // "truth", "real"
  bool needs_frames = false;
  PipelineFactory make;
};

}  // namespace labo::bench
