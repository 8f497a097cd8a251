#pragma once
// FlightCore over control's FlightStack: converts FlightStack's requests, outputs and status to the
// web layer's types, projects the tracked panel's and the face's axes into the image for the overlay,
// and turns stage changes and FlightStack's event log into FlightEvents.
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include "control/flight_stack.hpp"
#include "core/camera_model.hpp"
#include "server/runtime/flight_core.hpp"

namespace labo::server {

class FlightStackCore final : public FlightCore {
 public:
  FlightStackCore(std::unique_ptr<control::FlightStack> stack, const CamerasConfig& cameras);

  void on_navdata(const NavdataSample& sample) override;
  void on_video(const VideoFrame& frame) override;
  bool prepare_vision(const VideoFrame& frame, fusion::VisionJob& job) override;
  void apply_vision(const fusion::VisionResults& results) override;
  void on_link_state(LinkState state, Seconds t) override { stack_->on_link_state(state, t); }
  FlightAction tick(Seconds t) override;
  CommandVerdict request(const MissionCommand& command, Seconds t) override;
  FlightSnapshot status() override;
  std::vector<InstrumentSummary> instruments() const override;
  CommandVerdict add_instrument(const lab::InstrumentSpec& spec) override;
  CommandVerdict remove_instrument(const std::string& id) override;
  CommandVerdict set_down_on_platform() override;

  control::FlightStack& stack() { return *stack_; }
  // Where the drone truly is, asked at every tick and shown beside the estimate (the simulated lab
  // only: a real flight has no truth). Set before the runtime starts.
  using TruthSource = std::function<std::optional<Eigen::Isometry3d>()>;
  void set_truth_source(TruthSource source) { truth_ = std::move(source); }

 private:
  void note_template_size(const fusion::PlanarTarget& target);

  std::unique_ptr<control::FlightStack> stack_;
  PinholeCamera front_, bottom_;
  CameraId camera_ = CameraId::Front;
  TruthSource truth_;
  std::string last_mission_, last_stage_, last_event_;  // last_stage_: the stage's name (its words change)
  std::map<std::string, cv::Size> template_px_;  // each instrument's template resolution
  std::string measured_instrument_;              // the instrument of the last vision result
};

// The 68-landmark face outline as edges (jaw, brows, nose, eyes, lips), for the overlay.
const std::vector<std::pair<int, int>>& face_landmark_edges();

}  // namespace labo::server
