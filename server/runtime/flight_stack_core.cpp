#include "server/runtime/flight_stack_core.hpp"

#include <opencv2/imgcodecs.hpp>

#include "localization/fusion/vision_job.hpp"

namespace labo::server {

using lab::InstrumentSpec;


namespace {

PoseXyzYaw xyz_yaw(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d R = T.linear();
  return {T.translation().x(), T.translation().y(), T.translation().z(), std::atan2(R(1, 0), R(0, 0))};
}

PoseSource source_of(fusion::FeedbackSource s, const control::FlightStatus& status) {
  switch (s) {
    case fusion::FeedbackSource::Slam: return PoseSource::Slam;
    case fusion::FeedbackSource::Homography:
      return status.instrument.state == fusion::TrackState::Lost ? PoseSource::VisionLost : PoseSource::Homography;
    case fusion::FeedbackSource::Face: return PoseSource::Face;
    case fusion::FeedbackSource::DeadReckoning: return PoseSource::DeadReckoning;
  }
  return PoseSource::DeadReckoning;
}

std::optional<AxesPx> project_axes(const PinholeCamera& camera, const Eigen::Isometry3d& T_cam_target, double length_m) {
  const auto o = camera.project(T_cam_target * Eigen::Vector3d::Zero());
  const auto x = camera.project(T_cam_target * Eigen::Vector3d(length_m, 0, 0));
  const auto y = camera.project(T_cam_target * Eigen::Vector3d(0, length_m, 0));
  const auto z = camera.project(T_cam_target * Eigen::Vector3d(0, 0, length_m));
  if (!o || !x || !y || !z) return std::nullopt;
  const auto pt = [](const Eigen::Vector2d& p) { return cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())); };
  return AxesPx{pt(*o), pt(*x), pt(*y), pt(*z)};
}

}  // namespace

const std::vector<std::pair<int, int>>& face_landmark_edges() {
  static const std::vector<std::pair<int, int>> edges = [] {
    std::vector<std::pair<int, int>> e;
    const auto chain = [&](int a, int b, bool closed) {
      for (int i = a; i < b; ++i) e.emplace_back(i, i + 1);
      if (closed) e.emplace_back(b, a);
    };
    chain(0, 16, false);   // jaw
    chain(17, 21, false);  // brows
    chain(22, 26, false);
    chain(27, 30, false);  // nose bridge
    chain(31, 35, false);  // nostrils
    chain(36, 41, true);   // eyes
    chain(42, 47, true);
    chain(48, 59, true);   // outer lip
    chain(60, 67, true);   // inner lip
    return e;
  }();
  return edges;
}

FlightStackCore::FlightStackCore(std::unique_ptr<control::FlightStack> stack, const CamerasConfig& cameras)
    : stack_(std::move(stack)), front_(cameras.front), bottom_(cameras.bottom) {
  for (const fusion::PlanarTarget& p : stack_->setup().lab.instruments) note_template_size(p);
}

// The templates' sizes, for the reading view (the front-ends own the images themselves).
void FlightStackCore::note_template_size(const fusion::PlanarTarget& p) {
  if (p.template_path.empty()) return;
  const cv::Mat image = cv::imread(p.template_path.string(), cv::IMREAD_UNCHANGED);
  if (!image.empty()) template_px_[p.id] = image.size();
}

CommandVerdict FlightStackCore::add_instrument(const InstrumentSpec& spec) {
  const fusion::PlanarTarget target = fusion::planar_target_of(spec);
  const control::CommandResult result = stack_->add_instrument(target);
  if (result.accepted) note_template_size(target);
  return {result.accepted, result.reason};
}

CommandVerdict FlightStackCore::remove_instrument(const std::string& id) {
  const control::CommandResult result = stack_->remove_instrument(id);
  return {result.accepted, result.reason};
}

CommandVerdict FlightStackCore::set_down_on_platform() {
  const control::CommandResult result = stack_->set_down_on_platform();
  return {result.accepted, result.reason};
}

void FlightStackCore::apply_vision(const fusion::VisionResults& results) {
  if (results.has_instrument) measured_instrument_ = results.instrument_id;
  stack_->apply_vision(results);
}

void FlightStackCore::on_navdata(const NavdataSample& sample) { stack_->on_navdata(sample); }

void FlightStackCore::on_video(const VideoFrame& frame) {
  camera_ = frame.camera;
  stack_->on_video(frame);
}

bool FlightStackCore::prepare_vision(const VideoFrame& frame, fusion::VisionJob& job) {
  camera_ = frame.camera;
  return stack_->prepare_vision(frame, job);
}

FlightAction FlightStackCore::tick(Seconds t) {
  if (truth_) {
    if (const auto T_world_body = truth_()) stack_->set_ground_truth(*T_world_body, t);
  }
  const control::FlightOutput out = stack_->tick(t);
  FlightAction a;
  a.move = out.move;
  a.select_camera = out.select_camera;
  switch (out.action) {
    case control::FlightOutput::Action::None: a.kind = FlightAction::Kind::None; break;
    case control::FlightOutput::Action::Move: a.kind = FlightAction::Kind::Move; break;
    case control::FlightOutput::Action::Hover: a.kind = FlightAction::Kind::Hover; break;
    case control::FlightOutput::Action::Takeoff: a.kind = FlightAction::Kind::Takeoff; break;
    case control::FlightOutput::Action::Land: a.kind = FlightAction::Kind::Land; break;
    case control::FlightOutput::Action::Emergency: a.kind = FlightAction::Kind::Emergency; break;
  }
  return a;
}

CommandVerdict FlightStackCore::request(const MissionCommand& c, Seconds t) {
  control::MissionRequest r;
  switch (c.kind) {
    case MissionCommandKind::Takeoff: r.kind = control::RequestKind::Takeoff; break;
    case MissionCommandKind::Inspect: r.kind = control::RequestKind::Inspect; break;
    case MissionCommandKind::FindTeacher: r.kind = control::RequestKind::FindTeacher; break;
    case MissionCommandKind::StopFaceFollow: r.kind = control::RequestKind::StopFaceFollow; break;
    case MissionCommandKind::ReturnHome: r.kind = control::RequestKind::ReturnHome; break;
    case MissionCommandKind::Land: r.kind = control::RequestKind::Land; break;
    // Land cancels the mission first; the drone's own landing holds its place while it descends.
    case MissionCommandKind::Stop: r.kind = control::RequestKind::Land; break;
    case MissionCommandKind::EmergencyStop: r.kind = control::RequestKind::EmergencyStop; break;
    case MissionCommandKind::SelectCamera: r.kind = control::RequestKind::SelectCamera; break;
    // The flight software refuses a move while a mission runs or outside the geofence; the
    // autopilot flies it within its speed limits.
    case MissionCommandKind::Jog:
      r.kind = control::RequestKind::MoveBy;
      r.target = Eigen::Vector4d(c.dx_m, c.dy_m, c.dz_m, c.dyaw_rad);
      break;
  }
  r.camera = c.camera;
  r.instrument_id = c.instrument;
  r.hold_s = c.hold_s;
  r.person = c.person;
  const control::CommandResult result = stack_->request(r, t);
  return {result.accepted, result.reason};
}

FlightSnapshot FlightStackCore::status() {
  const control::FlightStatus s = stack_->status();
  FlightSnapshot snap;
  FlightTelemetry& t = snap.telemetry;
  // After an emergency stop the mission has ended, but what everyone must see is the cut-out.
  t.mission = s.phase == control::FlightPhase::Emergency ? "emergency" : s.mission;
  t.stage = s.stage;
  t.pose = xyz_yaw(s.pose.T_world_body);
  if (s.desired) t.desired = PoseXyzYaw{(*s.desired)(0), (*s.desired)(1), (*s.desired)(2), (*s.desired)(3)};
  if (s.ground_truth_T_world_body) t.ground_truth = xyz_yaw(*s.ground_truth_T_world_body);
  t.source = source_of(s.pose.source, s);
  t.source_quality = s.pose.quality;
  t.unobserved_flight_s = s.pose.unobserved_flight_s;
  t.battery_percent = s.battery_percent;
  t.altitude_m = s.altitude_m;
  t.link_quality = s.link == LinkState::Connected ? 1.0 : s.link == LinkState::Degraded ? 0.5 : 0.0;
  t.flying = s.phase != control::FlightPhase::Landed && s.phase != control::FlightPhase::Emergency;
  t.slam_state = to_string(s.slam.state);
  t.slam_keyframes = s.slam.keyframes;
  t.slam_map_mib = static_cast<double>(s.slam.map_bytes) / (1024.0 * 1024.0);
  t.slam_points = s.slam_points;
  if (s.face.placed_in_world) t.teacher_xy = std::pair{s.face.T_world_target.translation().x(), s.face.T_world_target.translation().y()};

  const PinholeCamera& camera = camera_ == CameraId::Front ? front_ : bottom_;
  // The panel, else the platform (the camera that sees it is the one selected).
  if (s.instrument.state == fusion::TrackState::Tracking && s.instrument.image_points.size() == 4) {
    const auto size = template_px_.find(measured_instrument_);
    snap.overlay.panel = {s.instrument.image_points, project_axes(camera, s.instrument.T_cam_target, 0.15), s.instrument.t,
                          size == template_px_.end() ? cv::Size() : size->second};
  } else if (s.platform.state == fusion::TrackState::Tracking && s.platform.image_points.size() == 4) {
    snap.overlay.platform = {s.platform.image_points, project_axes(camera, s.platform.T_cam_target, 0.15), s.platform.t, {}};
  }
  if (s.face.state == fusion::TrackState::Tracking && !s.face.image_points.empty()) {
    FaceOverlay& face = snap.overlay.face;
    face.points = s.face.image_points;
    if (s.face.position_only) face.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};  // the followed head's box
    else if (s.face.image_points.size() == 68) face.edges = face_landmark_edges();
    if (!s.face.position_only) face.axes = project_axes(camera, s.face.T_cam_target, 0.10);
    face.measured_t = s.face.t;
  }

  snap.progress = {s.mission, s.stage_index, s.stage_count, s.stage, s.missions_ended, s.last_mission_result};
  // An event when a stage begins, not whenever its words change (its counters do at every tick: the
  // timeline carries them).
  const std::string stage_name = split_stage_line(s.stage).name;
  if (s.mission != last_mission_ || stage_name != last_stage_) {
    snap.events.push_back({"stage", s.mission, s.stage, s.mission + ": " + s.stage});
    last_mission_ = s.mission;
    last_stage_ = stage_name;
  }
  if (!s.last_event.empty() && s.last_event != last_event_) {
    snap.events.push_back({"log", s.mission, s.stage, s.last_event});
    last_event_ = s.last_event;
  }
  return snap;
}

std::vector<InstrumentSummary> FlightStackCore::instruments() const {
  std::vector<InstrumentSummary> out;
  for (const fusion::PlanarTarget& p : stack_->setup().lab.instruments) {
    const Eigen::Vector3d into = p.T_world_object.linear().col(2);  // object z points into the panel
    out.push_back({p.id, p.name, p.width_m, p.height_m, p.T_world_object.translation().x(), p.T_world_object.translation().y(),
                   std::atan2(-into.y(), -into.x())});
  }
  return out;
}

}  // namespace labo::server
