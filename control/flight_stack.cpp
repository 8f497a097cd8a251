#include "control/flight_stack.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "control/autopilot.hpp"
#include "control/command_hold_envelope.hpp"
#include "localization/fusion/lab_pipelines.hpp"
#include "localization/fusion/lab_pipelines_factory.hpp"
#include "control/level_hold.hpp"
#include "control/find_teacher_mission.hpp"
#include "control/inspect_mission.hpp"
#include "localization/fusion/localization_switch.hpp"
#include "control/request_policy.hpp"
#include "control/safety_monitor.hpp"
#include "core/frames.hpp"

namespace labo::control {

struct FlightStack::Impl {
  Impl(FlightStackSetup s, std::unique_ptr<fusion::LocalizationPipelines> p)
      : setup(std::move(s)),
        pipelines(std::move(p)),
        autopilot(setup.control, Geofence(setup.lab.room_min, setup.lab.room_max, setup.control.safety.geofence_margin_m)),
        source_switch(setup.control.mission.source_switch),
        safety(setup.control.safety),
        envelope(setup.lab.room_min, setup.lab.room_max, std::max(0.0, setup.control.safety.hold_clearance_m),
                 setup.estimation.firmware_command_hold_s, setup.estimation.model) {
    if (!pipelines) throw std::invalid_argument("FlightStack: no localization pipelines");
    // On the platform at the base; the time is the first navdata's (a server's clock has run for
    // seconds before the link connects, a lockstep flight's starts at 0).
    pipelines->start_at_first_navdata(make_pose(setup.lab.base, setup.lab.base_yaw_rad));
  }

  FlightStackSetup setup;
  std::unique_ptr<fusion::LocalizationPipelines> pipelines;
  Autopilot autopilot;
  fusion::LocalizationSwitch source_switch;
  SafetyMonitor safety;
  CommandHoldEnvelope envelope;
  std::unique_ptr<Mission> mission;
  fusion::PerceptionFocus focus;
  CameraId camera = CameraId::Front;
  std::optional<CameraId> camera_sent;
  LinkState link = LinkState::Connected;
  NavdataSample nav;
  bool have_nav = false;
  std::optional<Eigen::Isometry3d> ground_truth;
  std::string last_event;
  int missions_ended = 0;
  std::string last_mission_result;
  SafetyAlerts alerts;  // this tick's, formatted only for status()
  std::optional<FlightOutput> pending;  // an action decided by a request, sent at the next tick
  std::optional<PoseTarget> level_hold;  // altitude and yaw the safety's level hold keeps, while it lasts
  Seconds last_tick = 0;

  void finish_mission(const std::string& why) {
    if (!mission) return;
    last_event = "mission '" + mission->name() + "' ended: " + why;
    last_mission_result = why;
    ++missions_ended;
    mission.reset();
    clear_focus();
  }

  void start_mission(std::unique_ptr<Mission> next) {
    mission = std::move(next);
    clear_focus();
  }

  // A mission's focus ends with it: idle and the next mission start from SLAM alone. Kept, the
  // landing's platform focus made the next inspection's source switch watch the platform instead of
  // the panel (the homography never taken: "lost during inspection" on every mission after the first),
  // and a find-teacher's face kept the face front-end running through the missions after it. Test
  // "control: a second inspection after a landing, and one after a find-teacher, fly as the first".
  void clear_focus() {
    const fusion::FeedbackSource feedback = focus.feedback;
    focus = fusion::PerceptionFocus{};
    focus.feedback = feedback;
    pipelines->set_focus(focus);
  }

  RequestContext request_context(Seconds t) const {
    RequestContext c;
    c.phase = autopilot.phase();
    if (mission) {
      c.running_mission = mission->name();
      c.running_stage = mission->stage();
      c.mission_accepts_stop_face_follow = mission->accepts_stop_face_follow();
    }
    c.link = link;
    c.battery_percent = have_nav ? nav.battery_percent : 100.0;
    const fusion::PoseEstimate pose = pipelines->predict(t);
    c.position = pose.T_world_body.translation();
    c.yaw = ypr_from_rotation(pose.T_world_body.linear())[0];
    c.unobserved_flight_s = pose.unobserved_flight_s;
    if (const auto& tg = autopilot.target()) {
      c.has_target = true;
      c.current_target << tg->position, tg->yaw;
    }
    return c;
  }

  std::optional<double> near_target_distance(const fusion::TargetObservation& obs) const {
    if (obs.state != fusion::TrackState::Tracking) return std::nullopt;
    return camera_distance(obs);
  }

  void update_source(Seconds t) {
    fusion::SwitchInputs in;
    in.t = t;
    const fusion::TargetObservation near = focus.platform ? pipelines->platform() : pipelines->instrument();
    in.target_state = near.state;
    in.target_distance_m = near_target_distance(near);
    const fusion::SlamSummary slam = pipelines->slam();
    in.slam = slam.state;
    in.slam_scaled = slam.scale_estimated;
    // The face is feedback only when configured so: fused as a landmark, a walking teacher's motion is
    // taken for the drone's (with SLAM lost at a watch point, the estimate would drift with the
    // teacher's walk and the drone fly into them). Without SLAM the drone follows on navdata odometry,
    // the face as the target.
    in.face_mode = focus.face && setup.control.mission.face_as_feedback;
    const fusion::TargetObservation& face = pipelines->face();
    in.face_state = face.position_only ? fusion::TrackState::Lost : face.state;
    focus.feedback = source_switch.update(in);
    pipelines->set_focus(focus);
  }

  FlightOutput apply_safety(const fusion::PoseEstimate& pose, Seconds t, bool& paused) {
    SafetyInputs in;
    in.t = t;
    in.landing = autopilot.phase() == FlightPhase::Landing;
    in.airborne = in.landing || autopilot.phase() == FlightPhase::Flying || autopilot.phase() == FlightPhase::TakingOff;
    in.link = link;
    in.battery_percent = have_nav ? nav.battery_percent : 100.0;
    in.localization_required = mission && mission->needs_visual_localization();
    in.localization_ok = pose.valid && pose.source != fusion::FeedbackSource::DeadReckoning;
    if (mission && mission->tolerates_dead_reckoning()) in.localization_grace_s = setup.control.safety.return_dead_reckoning_s;
    in.returning_home = mission && mission->name() == "return_home";
    in.flying = autopilot.phase() == FlightPhase::Flying;
    if (have_nav) in.ultrasound_m = nav.altitude_m;
    if (pose.valid) {
      in.position_m = pose.T_world_body.translation();
      in.outside_fence_m = autopilot.fence().horizontal_distance_outside_m(*in.position_m);
    }
    in.velocity_mps = pose.velocity_world;
    const SafetyVerdict v = safety.evaluate(in);
    alerts = v.alerts;
    if (v.action != SafetyAction::HoldLevel) level_hold.reset();
    FlightOutput out;
    switch (v.action) {
      case SafetyAction::None:
        break;
      case SafetyAction::Hover:
        paused = true;
        out.action = FlightOutput::Action::Hover;
        break;
      case SafetyAction::HoldLevel:
        paused = true;
        out = hold_level(pose);
        break;
      case SafetyAction::Climb:
        paused = true;
        out.action = FlightOutput::Action::Move;
        out.move = climb_command(pose, setup.control.gains);
        break;
      case SafetyAction::ReturnHome: {
        const std::string reason = to_string(v.reason);
        finish_mission("safety: " + reason);
        start_mission(std::make_unique<ReturnHomeMission>(t, reason));
        last_event = "safety: " + reason;
        break;
      }
      case SafetyAction::Land: {
        if (in.landing && link != LinkState::Lost && link != LinkState::Disconnected) break;  // already landing
        const std::string why = "safety: " + to_string(v.reason);
        finish_mission(why);
        last_event = why;
        paused = true;
        // Land is repeated while the link is down, so it gets through when the link comes back.
        out = autopilot.land(t);
        break;
      }
    }
    return out;
  }

  // The safety's level hold: the altitude and yaw of the target being flown (the mission's set point:
  // a push away from it is corrected even while the mission waits), else of the pose when it began.
  // Outside normal flight (taking off, landing) the firmware's hover, as before.
  FlightOutput hold_level(const fusion::PoseEstimate& pose) {
    FlightOutput out;
    if (autopilot.phase() != FlightPhase::Flying || !pose.valid) {
      out.action = FlightOutput::Action::Hover;
      return out;
    }
    if (!level_hold) {
      level_hold = autopilot.target().value_or(
          PoseTarget{pose.T_world_body.translation(), ypr_from_rotation(pose.T_world_body.linear())[0]});
    }
    out.action = FlightOutput::Action::Move;
    out.move = level_hold_command(pose, level_hold->position.z(), level_hold->yaw, setup.control.gains);
    return out;
  }

  FlightOutput tick(Seconds t) {
    last_tick = t;
    const fusion::PoseEstimate pose = pipelines->predict(t);
    if (pending) {
      FlightOutput out = *pending;
      pending.reset();
      return finish_tick(out, pose, t);
    }
    // The source switch runs even while safety holds the mission: a paused mission must be able to
    // regain its visual source (a hover waiting for localization would otherwise never end).
    update_source(t);
    bool paused = false;
    FlightOutput safety_out = apply_safety(pose, t, paused);
    if (paused) return finish_tick(safety_out, pose, t);

    FlightOutput out;
    if (mission) {
      const CameraIntrinsics& k = setup.cameras.front;
      MissionContext ctx{t, pose, *pipelines, autopilot, setup.lab, setup.control, focus, camera,
                         image_centre_ray(k.fx, k.fy, k.cx, k.cy, k.width, k.height), std::nullopt};
      const MissionOutcome outcome = mission->step(ctx);
      if (outcome != MissionOutcome::Running) {
        const std::string verdict = outcome == MissionOutcome::Succeeded ? "succeeded: " : "failed: ";
        finish_mission(verdict + mission->result());
        if (autopilot.flying() && !autopilot.target()) autopilot.hold_here(pose, t);
      }
      if (ctx.phase_action) return finish_tick(*ctx.phase_action, pose, t);
    }
    update_source(t);  // the mission may have changed the focus
    out = autopilot.step(pose, t);
    return finish_tick(out, pose, t);
  }

  FlightOutput finish_tick(FlightOutput out, const fusion::PoseEstimate& pose, Seconds t) {
    if (out.action == FlightOutput::Action::Move) keep_inside_hold_envelope(out, pose);
    if (!camera_sent || *camera_sent != camera) {
      out.select_camera = camera;
      camera_sent = camera;
    }
    if (out.action == FlightOutput::Action::Move) pipelines->on_command(out.move, t);
    else if (out.action == FlightOutput::Action::Hover) pipelines->on_command(MoveCommand{}, t);
    return out;
  }

  void keep_inside_hold_envelope(FlightOutput& out, const fusion::PoseEstimate& pose) {
    if (setup.control.safety.hold_clearance_m < 0 || !pose.valid || autopilot.phase() != FlightPhase::Flying) return;
    const HoldEnvelopeInputs state{pose.T_world_body.translation(), pose.velocity_world,
                                   ypr_from_rotation(pose.T_world_body.linear())[0]};
    const HoldEnvelopeResult r = envelope.limit(out.move, state);
    if (!r.limited()) return;
    if (r.hover) out.action = FlightOutput::Action::Hover;
    out.move = r.move;
    alerts.push_back(r.hover ? SafetyAlert{SafetyAlertKind::LinkCutHover} : SafetyAlert{SafetyAlertKind::LinkCutScaled, r.scale});
  }

  CommandResult request(const MissionRequest& r, Seconds t) {
    const CommandResult verdict =
        check_request(r, request_context(t), setup.lab, autopilot.fence(), setup.control);
    if (!verdict.accepted) {
      last_event = "refused: " + verdict.reason;
      return verdict;
    }
    last_event = verdict.reason;
    const fusion::PoseEstimate pose = pipelines->predict(t);
    switch (r.kind) {
      case RequestKind::EmergencyStop:
        finish_mission("emergency stop");
        pending = autopilot.emergency(t);
        break;
      case RequestKind::Takeoff:
        pending = autopilot.takeoff(t);
        break;
      case RequestKind::Land:
        finish_mission("land requested");
        camera = CameraId::Front;
        pending = autopilot.land(t);
        break;
      case RequestKind::Hover:
        finish_mission("hover requested");
        autopilot.hold_here(pose, t);
        break;
      case RequestKind::Goto:
        autopilot.go_to({r.target.head<3>(), r.target[3]}, t);
        break;
      case RequestKind::MoveBy: {
        const PoseTarget from = autopilot.target().value_or(
            PoseTarget{pose.T_world_body.translation(), ypr_from_rotation(pose.T_world_body.linear())[0]});
        const Eigen::Vector2d d(std::cos(from.yaw) * r.target.x() - std::sin(from.yaw) * r.target.y(),
                                std::sin(from.yaw) * r.target.x() + std::cos(from.yaw) * r.target.y());
        autopilot.go_to({from.position + Eigen::Vector3d(d.x(), d.y(), r.target.z()), from.yaw + r.target[3]}, t);
        break;
      }
      case RequestKind::Inspect: {
        const fusion::PlanarTarget& inst = *setup.lab.find_instrument(r.instrument_id);
        const double hold = r.hold_s > 0 ? r.hold_s : setup.control.mission.default_hold_s;
        const double standoff = r.standoff_m > 0 ? r.standoff_m : setup.control.mission.standoff_m;
        start_mission(std::make_unique<InspectMission>(inst, hold, standoff, t));
        camera = CameraId::Front;  // its take-off and SLAM need the front camera from the first tick
        break;
      }
      case RequestKind::FindTeacher:
        if (r.person) {
          if (!pipelines->follow_person(*r.person)) {
            const std::string why = "find_teacher: these pipelines have no face front-end to follow " + r.person->name;
            last_event = "refused: " + why;
            return CommandResult::refused(why);
          }
          last_event = "searching for " + r.person->name;
        }
        start_mission(std::make_unique<FindTeacherMission>(t));
        camera = CameraId::Front;
        return {true, last_event};
      case RequestKind::SelectCamera:
        camera = r.camera;
        break;
      case RequestKind::StopFaceFollow:
        mission->stop_face_follow();
        break;
      case RequestKind::ReturnHome:
        finish_mission("return home requested");
        start_mission(std::make_unique<ReturnHomeMission>(t, "requested"));
        break;
    }
    return verdict;
  }
};

namespace {
std::unique_ptr<fusion::LabPipelines> pipelines_for(const FlightStackSetup& setup) {
  if (setup.front_ends) return fusion::make_lab_pipelines(setup.lab, setup.cameras, setup.vision, setup.estimation, *setup.front_ends);
  return std::make_unique<fusion::LabPipelines>(setup.lab, setup.estimation, setup.vision);
}
}  // namespace

FlightStack::FlightStack(FlightStackSetup setup) : FlightStack(setup, pipelines_for(setup)) {}

FlightStack::FlightStack(FlightStackSetup setup, std::unique_ptr<fusion::LocalizationPipelines> pipelines)
    : impl_(std::make_unique<Impl>(std::move(setup), std::move(pipelines))) {}

FlightStack::~FlightStack() = default;

void FlightStack::on_navdata(const NavdataSample& sample) {
  impl_->nav = sample;
  impl_->have_nav = true;
  impl_->pipelines->on_navdata(sample);
  impl_->autopilot.on_control_state(sample.control_state, sample.t);
}

void FlightStack::on_video(const VideoFrame& frame) { impl_->pipelines->on_video(frame); }

bool FlightStack::prepare_vision(const VideoFrame& frame, fusion::VisionJob& job) { return impl_->pipelines->prepare_vision(frame, job); }

void FlightStack::apply_vision(const fusion::VisionResults& results) { impl_->pipelines->apply_vision(results); }

void FlightStack::on_link_state(LinkState state, Seconds) { impl_->link = state; }

void FlightStack::set_ground_truth(const Eigen::Isometry3d& T_world_body, Seconds) { impl_->ground_truth = T_world_body; }

FlightOutput FlightStack::tick(Seconds t) { return impl_->tick(t); }

CommandResult FlightStack::request(const MissionRequest& request, Seconds t) { return impl_->request(request, t); }

const FlightStackSetup& FlightStack::setup() const { return impl_->setup; }

CommandResult FlightStack::add_instrument(const fusion::PlanarTarget& instrument) {
  Impl& m = *impl_;
  fusion::LabGeometry& lab = m.setup.lab;
  if (lab.find_instrument(instrument.id)) return CommandResult::refused("instrument '" + instrument.id + "' is in the lab already");
  const Eigen::Vector3d c = instrument.T_world_object.translation();
  if ((c.array() < lab.room_min.array()).any() || (c.array() > lab.room_max.array()).any())
    return CommandResult::refused("instrument '" + instrument.id + "': its panel's centre is outside the room");
  try {
    if (!m.pipelines->add_instrument(instrument))
      return CommandResult::refused("instrument '" + instrument.id + "': these localization pipelines cannot add instruments");
  } catch (const std::exception& e) {
    return CommandResult::refused("instrument '" + instrument.id + "': " + e.what());
  }
  lab.instruments.push_back(instrument);
  m.last_event = "instrument '" + instrument.id + "' placed in the lab";
  return CommandResult::ok(m.last_event);
}

CommandResult FlightStack::set_down_on_platform() {
  Impl& m = *impl_;
  const FlightPhase phase = m.autopilot.phase();
  // The navdata's own control state too: the autopilot may think it landed a drone whose firmware
  // still flies (a land command lost in a cut).
  const bool motors_on = m.have_nav && control_state::motors_on(m.nav.control_state);
  if (phase == FlightPhase::TakingOff || phase == FlightPhase::Flying || phase == FlightPhase::Landing)
    return CommandResult::refused("set-down: the drone is flying (" + to_string(phase) +
                                  "); land it, then set it on its platform");
  if (motors_on)
    return CommandResult::refused("set-down: the drone reports its motors on (navdata control state " +
                                  std::to_string(m.nav.control_state) + "); land it, then set it on its platform");
  if (m.mission) return CommandResult::refused("set-down: mission '" + m.mission->name() + "' is running; stop it first");
  m.pipelines->set_down_at_next_navdata(make_pose(m.setup.lab.base, m.setup.lab.base_yaw_rad));
  m.last_event = "the drone was set on its platform: its place is the base's again";
  return CommandResult::ok(m.last_event);
}

CommandResult FlightStack::remove_instrument(const std::string& id) {
  Impl& m = *impl_;
  auto& instruments = m.setup.lab.instruments;
  const auto it = std::find_if(instruments.begin(), instruments.end(), [&](const fusion::PlanarTarget& p) { return p.id == id; });
  if (it == instruments.end()) return CommandResult::refused("no instrument '" + id + "' in the lab");
  if (m.mission && m.mission->inspected_instrument() == id)
    return CommandResult::refused("instrument '" + id + "' is being inspected: stop the mission first");
  instruments.erase(it);
  m.last_event = "instrument '" + id + "' removed from the lab";
  return CommandResult::ok(m.last_event);
}

FlightStatus FlightStack::status() const {
  const Impl& m = *impl_;
  FlightStatus s;
  s.t = m.last_tick;
  s.phase = m.autopilot.phase();
  s.mission = m.mission ? m.mission->name() : "idle";
  s.stage = m.mission ? m.mission->stage() : "";
  s.stage_index = m.mission ? m.mission->stage_index() : 0;
  s.stage_count = m.mission ? m.mission->stage_count() : 0;
  s.last_event = m.last_event;
  s.missions_ended = m.missions_ended;
  s.last_mission_result = m.last_mission_result;
  s.pose = m.pipelines->predict(m.last_tick);
  if (const auto& tg = m.autopilot.target()) s.desired = Eigen::Vector4d(tg->position.x(), tg->position.y(), tg->position.z(), tg->yaw);
  s.source = s.pose.source;
  s.source_colour = fusion::colour_of(s.source);
  s.last_command = m.autopilot.last_command();
  s.battery_percent = m.nav.battery_percent;
  s.altitude_m = m.nav.altitude_m;
  s.link = m.link;
  s.safety_alerts.clear();
  for (const SafetyAlert& a : m.alerts) s.safety_alerts.push_back(to_string(a));
  s.slam = m.pipelines->slam();
  s.slam_points = m.pipelines->slam_points();
  s.instrument = m.pipelines->instrument();
  s.platform = m.pipelines->platform();
  s.face = m.pipelines->face();
  s.ground_truth_T_world_body = m.ground_truth;
  return s;
}

}  // namespace labo::control
