#include "bench/experiments/sim_lab_flight.hpp"

#include <cstdio>
#include <stdexcept>

#include "localization/fusion/lab_pipelines_factory.hpp"
#include "drone/sim/sim_setup.hpp"

namespace labo::bench {

using lab::LabDescription;

using sim::SceneState;
using sim::SimConfig;
using sim::SimDroneLink;
using sim::SimTelloLink;
using sim::SimTelloSettings;
using sim::TexturedHeadModel;
using sim::WorldRanges;
using sim::make_sim_world;
using sim::make_simulated_lab;
using sim::to_string;


// The link's events go straight to the flight stack, frames through the modelled worker when there
// is one (a frame's pixels are valid during on_video only: the stack or the worker takes them there).
struct SimLabFlight::Listener final : DroneLinkListener {
  Listener(control::FlightStack& s, LockstepVisionWorker* w, const Seconds& t) : stack(s), worker(w), now(t) {}
  void on_navdata(const NavdataSample& sample) override { stack.on_navdata(sample); }
  void on_video(const VideoFrame& frame) override {
    if (worker) worker->on_frame(frame, now);
    else stack.on_video(frame);
  }
  void on_link_state(LinkState state, Seconds t) override { stack.on_link_state(state, t); }
  control::FlightStack& stack;
  LockstepVisionWorker* worker;
  const Seconds& now;
};

SimLabFlight::SimLabFlight(const control::FlightStackSetup& setup, const LabDescription& lab, const SimConfig& sim,
                           std::optional<TexturedHeadModel> head, std::optional<VisionLatencyModel> vision_latency,
                           const WorldRanges& ranges, std::optional<SimTelloSettings> tello)
    : geometry_(setup.lab),
      world_(make_sim_world(lab, setup.cameras, sim, ranges)),
      true_lab_{fusion::lab_geometry_from(world_.lab), world_.cameras.front, world_.mounts.front} {
  if (!setup.front_ends) throw std::invalid_argument("SimLabFlight: the setup has no vision front-ends");
  lab_ = make_simulated_lab(world_, std::move(head));
  auto pipelines = fusion::make_lab_pipelines(setup.lab, setup.cameras, setup.vision, setup.estimation, *setup.front_ends);
  pipelines_ = pipelines.get();
  stack_ = std::make_unique<control::FlightStack>(setup, std::move(pipelines));
  if (vision_latency) vision_worker_ = std::make_unique<LockstepVisionWorker>(*stack_, *vision_latency);
  listener_ = std::make_unique<Listener>(*stack_, vision_worker_.get(), t_);
  if (tello) link_ = std::make_unique<SimTelloLink>(*lab_, world_.link, *tello);
  else link_ = std::make_unique<SimDroneLink>(*lab_, world_.link);
  tello_ = tello.has_value();
  telemetry_hz_ = tello ? tello->state_rate_hz : world_.link.full_navdata ? world_.link.full_rate_hz : world_.link.demo_rate_hz;
  link_->set_listener(listener_.get());
  samples_.reserve(20000);
}

SimLabFlight::~SimLabFlight() = default;

std::optional<LockstepVisionStats> SimLabFlight::vision_stats() const {
  if (!vision_worker_) return std::nullopt;
  return vision_worker_->stats();
}

std::optional<Eigen::Isometry3d> SimLabFlight::true_face() const {
  const SceneState scene = lab_->scene();
  if (!scene.teacher_present) return std::nullopt;
  return scene.T_world_head;
}

std::string SimLabFlight::description() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "sim lab as %s, %s world, %.0f fps, %.0f Hz %s, real vision%s",
                tello_ ? "a Tello" : "an AR.Drone 2.0", to_string(world_.mode).c_str(), world_.link.video_fps,
                telemetry_hz_,
                tello_ ? "state" : "navdata", vision_worker_ ? " on a modelled worker" : "");
  return buf;
}

void SimLabFlight::apply(const control::FlightOutput& out) {
  if (out.select_camera) link_->select_camera(*out.select_camera);
  switch (out.action) {
    case control::FlightOutput::Action::Move: link_->move(out.move); break;
    case control::FlightOutput::Action::Hover: link_->hover(); break;
    case control::FlightOutput::Action::Takeoff:
      // The IMU's roll/pitch calibrated on the ground first (as on the real drone: FlightRuntime).
      link_->flat_trim();
      link_->takeoff();
      break;
    case control::FlightOutput::Action::Land: link_->land(); break;
    case control::FlightOutput::Action::Emergency: link_->emergency(); break;
    case control::FlightOutput::Action::None: break;
  }
}

void SimLabFlight::tick() {
  link_->advance_to(t_);
  if (vision_worker_) vision_worker_->advance(t_);
  const Eigen::Isometry3d truth = true_pose();
  stack_->set_ground_truth(truth, t_);
  const control::FlightOutput out = stack_->tick(t_);
  apply(out);
  samples_.push_back(sample_of(stack_->status(), out, pipelines_->estimator(), truth, t_, true_face()));
  t_ += kControlDt;
}

}  // namespace labo::bench
