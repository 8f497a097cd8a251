#pragma once
// FlightStack: LaboDrone's flight brain. Deterministic and single-threaded: it is fed timestamped
// navdata and frames, it is ticked at the control rate and returns the one action to send, and it
// takes requests from users (missions and manual commands), accepting or refusing each with a reason.
// It owns the localization pipelines, the missions (stage machines of the paper's §6.2 and §6.4),
// the autopilot with its PID controllers, and the safety monitor. It never reads the wall clock: the
// real-time runtime (server/) and the lockstep experiments (bench/experiments/) both drive it with
// the timestamps of their own clock, so the same inputs give the same flight.
//
// Usage, from one thread:
//   FlightStack stack(setup);                  // or with your own LocalizationPipelines
//   link listener -> stack.on_navdata / on_video / on_link_state
//   every 1/control_rate_hz: out = stack.tick(now); send out (move/hover/takeoff/land/emergency)
//   user -> stack.request(req, now) -> accepted or refused with the reason
//   UI   -> stack.status()
#include <memory>
#include <optional>

#include "control/control_config.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "control/flight_types.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/localization_pipelines.hpp"
#include "core/camera_config.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::control {

struct FlightStackSetup {
  ControlConfig control;
  fusion::LabGeometry lab;
  CamerasConfig cameras = ardrone2_cameras();
  VisionThresholds vision;
  estimation::EstimatorConfig estimation;
  // Set: LabPipelines runs the real vision front-ends on the frames (fusion::make_lab_pipelines()). Unset:
  // vision results come only through LabPipelines::add_*_result() (tests, the perception model).
  std::optional<fusion::FrontEndSettings> front_ends;
};

class FlightStack {
 public:
  // Builds the lab's pipelines: LabPipelines (the StateEstimator), with the real vision front-ends
  // when setup.front_ends is set.
  explicit FlightStack(FlightStackSetup setup);
  // With given pipelines (tests, replay).
  FlightStack(FlightStackSetup setup, std::unique_ptr<fusion::LocalizationPipelines> pipelines);
  ~FlightStack();
  FlightStack(const FlightStack&) = delete;
  FlightStack& operator=(const FlightStack&) = delete;

  void on_navdata(const NavdataSample& sample);
  void on_video(const VideoFrame& frame);
  // on_video in steps, for a runtime that runs the vision on a worker (localization/fusion/vision_job.hpp).
  bool prepare_vision(const VideoFrame& frame, fusion::VisionJob& job);
  void apply_vision(const fusion::VisionResults& results);
  void on_link_state(LinkState state, Seconds t);
  // Simulated runs only: the true pose, reported in status() for plots and the UI.
  void set_ground_truth(const Eigen::Isometry3d& T_world_body, Seconds t);

  // The action to send now. Call at the control rate; every call advances the missions and safety.
  FlightOutput tick(Seconds t);
  // Accepted or refused with the reason. EmergencyStop is always accepted.
  CommandResult request(const MissionRequest& request, Seconds t);
  FlightStatus status() const;
  // Places an instrument in the lab (an admin's upload): inspectable from now on, its front-end made
  // like the lab file's instruments'. Refused (with the reason) for an id the lab has, a panel
  // outside the room, or pipelines that cannot add one (their template refused, ...).
  CommandResult add_instrument(const fusion::PlanarTarget& instrument);
  // No longer inspectable: refused while a mission inspects it. Its id stays taken until the stack is
  // rebuilt (its front-end may still be on a vision job: it is kept, unused).
  CommandResult remove_instrument(const std::string& id);
  // Someone set the drone on its charging platform (an admin, after a landing elsewhere): the pose is
  // the base's again from the next navdata on, confirmed, with the SLAM map and the instruments'
  // places kept. Refused while the drone flies or a mission runs.
  CommandResult set_down_on_platform();

  const FlightStackSetup& setup() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::control
