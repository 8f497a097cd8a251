#include "bench/estimation/real_vision_pipeline.hpp"

#include <memory>
#include <stdexcept>

#include "bench/experiments/experiment_common.hpp"
#include "localization/fusion/lab_pipelines.hpp"
#include "localization/fusion/planar_front_end.hpp"
#include "localization/fusion/slam_front_end.hpp"

namespace labo::bench {

namespace {

// The SLAM front-end, recording each good pose it hands on (for the map's true scale).
class RecordingSlamFrontEnd final : public fusion::SlamFrontEnd {
 public:
  RecordingSlamFrontEnd(std::unique_ptr<fusion::SlamFrontEnd> inner, std::vector<SlamTrackPoint>& track)
      : inner_(std::move(inner)), track_(track) {}
  const fusion::SlamFrame& process(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior,
                           const std::optional<Eigen::Vector3d>& gravity_down_cam) override {
    const fusion::SlamFrame& f = inner_->process(gray, t, prior, gravity_down_cam);
    if (f.has_pose && f.summary.state == fusion::SlamState::Good) track_.push_back({t, f.T_map_cam, f.map_id});
    return f;
  }
  const fusion::SlamFrame& pause() override { return inner_->pause(); }
  int map_id() const override { return inner_->map_id(); }

 private:
  std::unique_ptr<fusion::SlamFrontEnd> inner_;
  std::vector<SlamTrackPoint>& track_;
};

class RealVisionPipeline final : public EstimationPipeline {
 public:
  RealVisionPipeline(const control::FlightStackSetup& setup, const estimation::EstimatorConfig& config, const std::string& instrument_id)
      : pipelines_(setup.lab, config, setup.vision), instrument_id_(instrument_id) {
    const fusion::PlanarTarget* target = setup.lab.find_instrument(instrument_id);
    if (!target) throw std::invalid_argument("sim estimate: the lab has no instrument '" + instrument_id + "'");
    const PinholeCamera front(setup.cameras.front);
    pipelines_.set_instrument_front_end(
        instrument_id, std::make_unique<fusion::PlanarFrontEnd>(*target, front, setup.vision, setup.front_ends->planar));
    pipelines_.set_slam_front_end(std::make_unique<RecordingSlamFrontEnd>(
        std::make_unique<fusion::SlamSystemFrontEnd>(std::make_unique<slam::SlamSystem>(front, setup.front_ends->slam)), track_));
    track_.reserve(4096);
    set_vision({});
  }

  std::string vision_input() const override {
    return "the real front-ends on LabRenderer's frames through SimDroneLink: SlamSystem (synchronous mapping) while "
           "hovering, PlanarFrontEnd on '" + instrument_id_ + "' while servoing, via control's LabPipelines";
  }
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t) override { pipelines_.reset(T_world_body, t); }
  void on_navdata(const NavdataSample& sample) override { pipelines_.on_navdata(sample); }
  void on_command(const MoveCommand& command, Seconds t) override { pipelines_.on_command(command, t); }
  void on_frame(const VideoFrame& frame) override { pipelines_.on_video(frame); }
  void on_truth(const GroundTruth&, Seconds) override {}
  void set_vision(const VisionWanted& wanted) override {
    fusion::PerceptionFocus focus;
    focus.slam = wanted.slam;
    focus.instrument_id = wanted.instrument ? instrument_id_ : "";
    focus.feedback = wanted.instrument ? fusion::FeedbackSource::Homography
                                       : (wanted.slam ? fusion::FeedbackSource::Slam : fusion::FeedbackSource::DeadReckoning);
    pipelines_.set_focus(focus);
  }
  const estimation::StateEstimator& estimator() const override { return pipelines_.estimator(); }
  const std::vector<SlamTrackPoint>& slam_track() const override { return track_; }

 private:
  fusion::LabPipelines pipelines_;
  std::string instrument_id_;
  std::vector<SlamTrackPoint> track_;
};

}  // namespace

PipelineKind real_vision_pipelines(const std::filesystem::path& config_file) {
  ExperimentOptions options;
  options.config = config_file;
  options.real_vision = true;
  auto experiment = std::make_shared<const Experiment>(make_experiment(options, /*with_face=*/false));
  return {"real", true,
          [experiment](const estimation::EstimatorConfig& config, const EstimationPlant& plant, unsigned) -> std::unique_ptr<EstimationPipeline> {
            return std::make_unique<RealVisionPipeline>(experiment->setup, config, plant.instrument().id);
          }};
}

}  // namespace labo::bench
