#pragma once
// LabPlant: the simulated lab (drone/sim: SimulatedLab with its firmware dynamics, sensor model,
// walking teacher and LabRenderer cameras) behind SimDroneLink, the lockstep DroneLink with the real
// link's timing (navdata 15 Hz demo or 200 Hz full, 30 fps video, delays and jitter, the driver's
// 30 ms AT loop), as an EstimationPlant. The drone starts on the platform and is flown to a hover
// by its own take-off before the run begins. Without video (truth-derived vision), a video dropout
// over the whole run keeps the renderer idle.
#include <memory>
#include <optional>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/sim/sim_drone_link.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "bench/estimation/estimation_plant.hpp"

namespace labo::bench {

using sim::SimConfig;
using sim::SimDroneLink;
using sim::SimLinkSettings;
using sim::SimulatedLab;
using sim::TexturedHeadModel;


// What a LabPlant is built from (config/default.json's lab file, cameras and sim section).
struct LabPlantInputs {
  lab::LabDescription lab;
  CamerasConfig cameras;
  SimConfig sim;
  std::optional<TexturedHeadModel> head;     // the teacher's face texture (untextured without)
  std::string instrument_id = "signal_generator";  // the servo experiments' target
};

class LabPlant final : public EstimationPlant, private DroneLinkListener {
 public:
  // Throws std::invalid_argument when the lab has no instrument `inputs.instrument_id`, and
  // std::runtime_error when the take-off does not end in a hover within 10 s.
  LabPlant(const LabPlantInputs& inputs, const PlantRequest& request);
  ~LabPlant() override;

  std::string name() const override { return "lab"; }
  Seconds now() const override { return link_->now(); }
  void move(const MoveCommand& command) override { link_->move(command); }
  void step(Seconds dt, std::vector<NavdataSample>& arrived) override;
  const std::vector<VideoFrame>& frames_of_last_step() const override { return frames_; }
  GroundTruth truth() const override;
  std::string crash() const override;
  void push(const Eigen::Vector3d& delta_v_world) override { lab_->dynamics().push(delta_v_world, 0.0); }
  double vertical_push_for(double metres) const override;
  estimation::SurfaceMap surfaces() const override { return surfaces_; }
  PlantInstrument instrument() const override { return instrument_; }
  Seconds command_latency() const override;
  Seconds video_delay() const override { return link_settings_.video_delay_s; }
  Seconds navdata_delay() const override { return link_settings_.navdata_delay_s; }

  SimulatedLab& simulated_lab() { return *lab_; }
  const SimDroneLink& link() const { return *link_; }

 private:
  void on_navdata(const NavdataSample& sample) override;
  void on_video(const VideoFrame& frame) override;
  void on_link_state(LinkState, Seconds) override {}

  SimLinkSettings link_settings_;
  std::unique_ptr<SimulatedLab> lab_;
  std::unique_ptr<SimDroneLink> link_;
  estimation::SurfaceMap surfaces_;
  PlantInstrument instrument_;
  std::vector<NavdataSample>* arrived_ = nullptr;  // during step()
  std::vector<cv::Mat> pixels_;                     // copies of the frames' pixels, reused step to step
  std::vector<VideoFrame> frames_;                  // the last step's frames (headers onto pixels_)
};

}  // namespace labo::bench
