#include "control/experiments/sim_lab_flight.hpp"

#include <stdexcept>

#include "drone/sim/sim_setup.hpp"

namespace labo {

SimLabFlight::SimLabFlight(const FlightStackSetup& setup, const LabDescription& lab, const SimLabFlightOptions& options)
    : geometry_(setup.lab), options_(options) {
  if (!setup.front_ends) throw std::invalid_argument("SimLabFlight: the setup has no vision front-ends");
  if (!(options.video_fps > 0 && options.video_fps <= 60)) throw std::invalid_argument("SimLabFlight: video_fps must be in (0, 60]");
  SimulatedLabSettings settings;
  settings.seed = options.seed;
  lab_ = make_simulated_lab(lab, setup.cameras, settings);
  stack_ = std::make_unique<FlightStack>(setup);
  samples_.reserve(20000);
}

std::optional<Eigen::Isometry3d> SimLabFlight::true_face() const {
  const SceneState scene = lab_->scene();
  if (!scene.teacher_present) return std::nullopt;
  return scene.T_world_head;
}

std::string SimLabFlight::description() const {
  return "simulated lab (drone/sim), rendered cameras at " + std::to_string(static_cast<int>(options_.video_fps)) +
         " fps, real vision front-ends";
}

void SimLabFlight::apply(const FlightOutput& out) {
  if (out.select_camera) lab_->select_camera(*out.select_camera, t_);
  switch (out.action) {
    case FlightOutput::Action::Move: lab_->move(out.move, false, t_); break;
    case FlightOutput::Action::Hover: lab_->move(MoveCommand{}, true, t_); break;
    case FlightOutput::Action::Takeoff: lab_->takeoff(t_); break;
    case FlightOutput::Action::Land: lab_->land(t_); break;
    case FlightOutput::Action::Emergency: lab_->emergency(t_); break;
    case FlightOutput::Action::None: break;
  }
}

void SimLabFlight::tick() {
  lab_->advance_to(t_);
  NavdataSample nav = lab_->telemetry().nav;
  nav.t = t_;
  stack_->on_navdata(nav);
  if (t_ >= next_frame_t_ - 1e-9) {
    frame_.t = t_;
    frame_.camera = lab_->selected_camera();
    frame_.frame_number = static_cast<std::uint32_t>(frames_++);
    lab_->render(frame_.camera, frame_.bgr);
    stack_->on_video(frame_);
    next_frame_t_ += 1.0 / options_.video_fps;
  }
  const Eigen::Isometry3d truth = true_pose();
  stack_->set_ground_truth(truth, t_);
  apply(stack_->tick(t_));
  samples_.push_back(sample_of(stack_->status(), truth, t_));
  t_ += kControlDt;
}

}  // namespace labo
