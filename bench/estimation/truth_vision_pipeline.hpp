#pragma once
// TruthVisionPipeline: the StateEstimator fed with visual poses derived from the plant's ground truth,
// with noise and the plant's video delay: SLAM in an arbitrary map frame and scale (0.4-2.5 m per
// unit), 1.5 cm / 0.5 deg per frame; the instrument with 3 mm + 4 mm d^2 / 0.7 deg while its panel
// is in the front camera's view (30 fps). No frames are rendered.
#include <deque>
#include <random>

#include "bench/estimation/estimation_pipeline.hpp"

namespace labo::bench {

class TruthVisionPipeline final : public EstimationPipeline {
 public:
  TruthVisionPipeline(const estimation::EstimatorConfig& config, const VisionThresholds& thresholds, const EstimationPlant& plant,
                      unsigned seed);

  std::string vision_input() const override;
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t) override { estimator_.reset(T_world_body, t); }
  void on_navdata(const NavdataSample& sample) override { estimator_.add_navdata(sample); }
  void on_command(const MoveCommand& command, Seconds t) override { estimator_.add_command(command, t); }
  void on_frame(const VideoFrame&) override {}
  void on_truth(const GroundTruth& truth, Seconds now) override;
  void set_vision(const VisionWanted& wanted) override { wanted_ = wanted; }
  const estimation::StateEstimator& estimator() const override { return estimator_; }
  const std::vector<SlamTrackPoint>& slam_track() const override { return slam_track_; }

 private:
  void deliver(Seconds t_arrival, const Eigen::Isometry3d& T_world_body);

  estimation::StateEstimator estimator_;
  PlantInstrument instrument_;
  Seconds video_delay_;
  std::mt19937 rng_;
  Eigen::Isometry3d T_map_world_;
  double metres_per_unit_;
  VisionWanted wanted_;
  std::deque<std::pair<Seconds, Eigen::Isometry3d>> frames_;  // arrival time, body pose at capture
  std::vector<SlamTrackPoint> slam_track_;
};

}  // namespace labo::bench
