#include "localization/fusion/lab_pipelines.hpp"

#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/frames.hpp"
#include "localization/fusion/face_front_end.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::fusion {

namespace {
constexpr int kPlatformIndex = 0;  // object indices: platform 0, instruments 1..n in lab order
// Beyond this 1-sigma position uncertainty a predicted distance could pick the wrong detector or
// narrow the template search away from the target: the planar front-end then searches at every scale.
constexpr double kMaxSigmaForDistanceM = 0.5;
// Beyond this the prediction is a worse prior for SLAM than its own motion model.
constexpr double kMaxSigmaForSlamPriorM = 0.3;

FeedbackSource feedback_of(estimation::LocalizationSource s) {
  switch (s) {
    case estimation::LocalizationSource::Slam: return FeedbackSource::Slam;
    case estimation::LocalizationSource::Homography: return FeedbackSource::Homography;
    case estimation::LocalizationSource::Face: return FeedbackSource::Face;
    case estimation::LocalizationSource::DeadReckoning: return FeedbackSource::DeadReckoning;
  }
  return FeedbackSource::DeadReckoning;
}
}  // namespace

Eigen::Isometry3d flip_about_y() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}

LabPipelines::LabPipelines(LabGeometry lab, const estimation::EstimatorConfig& config, const VisionThresholds& thresholds)
    : lab_(std::move(lab)),
      estimator_(config, thresholds),
      instrument_fes_(lab_.instruments.size()),
      slam_points_(Eigen::AlignedBox3d(lab_.room_min, lab_.room_max)) {
  if (!lab_.surfaces.empty()) estimator_.set_surface_map(lab_.surfaces);
}

void LabPipelines::set_face_front_end(std::unique_ptr<TargetFrontEnd> front_end) {
  face_fe_ = std::move(front_end);
  face_person_fe_ = dynamic_cast<FaceFrontEnd*>(face_fe_.get());
}

bool LabPipelines::follow_person(const face::PersonShape& person) {
  if (!face_person_fe_) return false;
  face_person_fe_->follow(person);
  return true;
}

void LabPipelines::set_instrument_front_end(const std::string& id, std::unique_ptr<TargetFrontEnd> front_end) {
  const int index = instrument_index(id);
  if (index < 0) throw std::invalid_argument("LabPipelines: no instrument '" + id + "' in the lab");
  instrument_fes_[static_cast<std::size_t>(index - 1)] = std::move(front_end);
}

bool LabPipelines::add_instrument(const PlanarTarget& instrument) {
  if (instrument_index(instrument.id) >= 0) throw std::invalid_argument("LabPipelines: instrument '" + instrument.id + "' is in the lab already");
  // The front-end first: a template it refuses leaves the lab as it was. Front-ends already handed to
  // a vision job stay where they are (the vector holds pointers).
  std::unique_ptr<TargetFrontEnd> front_end = make_instrument_fe_ && !instrument.template_path.empty() ? make_instrument_fe_(instrument) : nullptr;
  lab_.instruments.push_back(instrument);
  instrument_fes_.push_back(std::move(front_end));
  return true;
}

int LabPipelines::instrument_index(const std::string& id) const {
  for (std::size_t i = 0; i < lab_.instruments.size(); ++i)
    if (lab_.instruments[i].id == id) return static_cast<int>(i) + 1;
  return -1;
}

void LabPipelines::reset(const Eigen::Isometry3d& T_world_body, Seconds t) { estimator_.reset(T_world_body, t); }

void LabPipelines::start_at_first_navdata(const Eigen::Isometry3d& T_world_body) {
  estimator_.start_at_first_navdata(T_world_body);
}

void LabPipelines::set_down_at_next_navdata(const Eigen::Isometry3d& T_world_body) {
  estimator_.set_down_at_next_navdata(T_world_body);
}

void LabPipelines::on_navdata(const NavdataSample& sample) {
  estimator_.add_navdata(sample);
  attitude_.add(sample.t - estimator_.config().navdata_delay_s, {sample.roll_rad, sample.pitch_rad});
}

std::optional<Eigen::Vector3d> LabPipelines::gravity_in_front_camera(Seconds frame_t) const {
  const std::optional<Attitude> a = attitude_.at(frame_t - estimator_.config().video_delay_s);
  if (!a) return std::nullopt;
  return slam::gravity_down_in_camera(a->roll_rad, a->pitch_rad, T_body_cam_front());
}

void LabPipelines::on_command(const MoveCommand& command, Seconds t) { estimator_.add_command(command, t); }

void LabPipelines::on_video(const VideoFrame& frame) {
  if (!prepare_vision(frame, job_)) return;
  run_vision_job(job_, results_);
  apply_vision(results_);
}

std::optional<double> LabPipelines::expected_distance(const Eigen::Isometry3d& T_world_target, CameraId camera,
                                                      Seconds t) const {
  const estimation::FusedState f = estimator_.predict(t);
  if (!f.initialized || f.position_sigma_m > kMaxSigmaForDistanceM) return std::nullopt;
  const Eigen::Isometry3d T_body_cam = camera == CameraId::Front ? T_body_cam_front() : T_body_cam_bottom();
  return ((f.T_world_body * T_body_cam).inverse() * T_world_target).translation().norm();
}

std::optional<Eigen::Isometry3d> LabPipelines::slam_prior(Seconds t) const {
  const estimation::MapToWorld& map = estimator_.map_to_world();
  if (!map.initialized() || !estimator_.scale_status().estimated || slam_map_id_ != slam_fe_map_id_) return std::nullopt;
  const estimation::FusedState f = estimator_.predict(t);
  if (!f.initialized || f.position_sigma_m > kMaxSigmaForSlamPriorM) return std::nullopt;
  // p_world = R * scale * p_map + t, inverted for the camera.
  const Eigen::Isometry3d T_world_cam = f.T_world_body * T_body_cam_front();
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  T_map_cam.linear() = map.R_world_map().transpose() * T_world_cam.linear();
  T_map_cam.translation() = map.R_world_map().transpose() * (T_world_cam.translation() - map.t_world_map()) / map.scale();
  return T_map_cam.inverse();
}

bool LabPipelines::prepare_vision(const VideoFrame& frame, VisionJob& job) {
  job.clear();
  // BGR as decoded; grey passes through; anything else is no camera frame (the front-ends refuse
  // wrong sizes themselves).
  if (frame.bgr.empty() || (frame.bgr.type() != CV_8UC3 && frame.bgr.type() != CV_8UC1)) return false;
  job.t = frame.t;
  job.camera = frame.camera;
  if (frame.camera == CameraId::Front) prepare_front_camera(job);
  else prepare_bottom_camera(job);
  if (!job.has_work()) return false;
  // Into the job's own buffer (reused at a steady frame size): the frame's may be reused meanwhile.
  if (frame.bgr.type() == CV_8UC1) frame.bgr.copyTo(job.gray);
  else cv::cvtColor(frame.bgr, job.gray, cv::COLOR_BGR2GRAY);
  return true;
}

void LabPipelines::prepare_front_camera(VisionJob& job) {
  if (slam_fe_ && focus_.slam) {
    job.slam = slam_fe_.get();
    job.slam_prior_T_cam_map = slam_prior(job.t);
    job.gravity_down_cam = gravity_in_front_camera(job.t);
  }
  if (const int index = focus_.instrument_id.empty() ? -1 : instrument_index(focus_.instrument_id); index > 0) {
    if (auto& fe = instrument_fes_[static_cast<std::size_t>(index - 1)]) {
      const Eigen::Isometry3d T_world_object = estimator_.T_world_object(index).value_or(
          lab_.instruments[static_cast<std::size_t>(index - 1)].T_world_object);
      job.instrument = fe.get();
      job.instrument_id = focus_.instrument_id;
      job.instrument_distance_m = expected_distance(T_world_object, CameraId::Front, job.t);
    }
  }
  if (face_fe_ && focus_.face) job.face = face_fe_.get();
}

void LabPipelines::prepare_bottom_camera(VisionJob& job) {
  // SLAM sees nothing while the bottom camera streams: reported off, not as its last state.
  if (slam_fe_) {
    job.slam = slam_fe_.get();
    job.slam_pause = true;
  }
  if (!platform_fe_ || !focus_.platform) return;
  const Eigen::Isometry3d T_world_platform = estimator_.T_world_object(kPlatformIndex).value_or(lab_.platform.T_world_object);
  job.platform = platform_fe_.get();
  job.platform_distance_m = expected_distance(T_world_platform, CameraId::Bottom, job.t);
}

void LabPipelines::apply_vision(const VisionResults& r) {
  if (r.has_slam) {
    slam_fe_map_id_ = r.slam.map_id;
    add_slam_result(r.slam.T_map_cam, r.slam.summary, r.slam.map_id, r.t);
    if (r.has_slam_points) apply_slam_points(r);
  }
  if (r.has_instrument) apply_instrument(r.instrument_id, r.instrument);
  if (r.has_platform) add_platform_result(r.platform);
  if (r.has_face) add_face_result(r.face);
}

void LabPipelines::add_instrument_result(const TargetObservation& obs) { apply_instrument(focus_.instrument_id, obs); }

void LabPipelines::apply_instrument(const std::string& id, const TargetObservation& obs) {
  instrument_ = obs;
  const int index = instrument_index(id);
  if (index < 0) return;
  if (obs.state == TrackState::Tracking && focus_.feedback == FeedbackSource::Homography) {
    estimation::ObjectObservation o;
    o.t = obs.t;
    o.object_index = index;
    o.camera = CameraId::Front;
    o.T_cam_object = obs.T_cam_target;
    o.T_world_object_surveyed = lab_.instruments[static_cast<std::size_t>(index - 1)].T_world_object;
    o.quality = obs.quality;
    o.rotation_sigma_rad = obs.rotation_sigma_rad;
    estimator_.add_object_pose(o);
  }
  if (auto placed = estimator_.T_world_object(index)) {
    instrument_.T_world_target = *placed;
    instrument_.placed_in_world = true;
  }
}

void LabPipelines::add_platform_result(const TargetObservation& obs) {
  platform_ = obs;
  platform_.offset_heading_m.reset();
  if (obs.state == TrackState::Tracking) {
    if (const std::optional<Attitude> a = attitude_.at(obs.t - estimator_.config().video_delay_s)) {
      const Eigen::Vector3d in_body = (T_body_cam_bottom() * obs.T_cam_target).translation();
      platform_.offset_heading_m = offset_along_heading(in_body, a->pitch_rad, a->roll_rad);
    }
  }
  if (obs.state == TrackState::Tracking && focus_.feedback == FeedbackSource::Homography) {
    estimation::ObjectObservation o;
    o.t = obs.t;
    o.object_index = kPlatformIndex;
    o.camera = CameraId::Bottom;
    o.T_cam_object = obs.T_cam_target;
    o.T_world_object_surveyed = lab_.platform.T_world_object;
    o.quality = obs.quality;
    o.rotation_sigma_rad = obs.rotation_sigma_rad;
    estimator_.add_object_pose(o);
  }
  if (auto placed = estimator_.T_world_object(kPlatformIndex)) {
    platform_.T_world_target = *placed;
    platform_.placed_in_world = true;
  }
}

void LabPipelines::add_face_result(const TargetObservation& obs) {
  face_ = obs;
  // A followed head has no orientation to correct the drone's pose with.
  if (obs.state == TrackState::Tracking && !obs.position_only && focus_.feedback == FeedbackSource::Face) {
    estimation::FaceObservation f;
    f.t = obs.t;
    f.T_cam_face = obs.T_cam_target * flip_about_y();
    f.quality = obs.quality;
    estimator_.add_face_pose(f);
  }
}

void LabPipelines::add_slam_result(const Eigen::Isometry3d& T_map_cam, const SlamSummary& summary, int map_id, Seconds t) {
  slam_ = summary;
  const bool good = summary.state == SlamState::Good;
  if (!good || !focus_.slam) return;
  slam_map_id_ = map_id;  // the estimator's map from now on
  estimation::SlamObservation s;
  s.t = t;
  s.T_map_cam = T_map_cam;
  s.map_id = map_id;
  s.tracking_good = true;
  s.quality = summary.points_attempted > 0 ? double(summary.points_found) / summary.points_attempted : 1.0;
  estimator_.add_slam_pose(s);
}

void LabPipelines::apply_slam_points(const VisionResults& r) {
  // Until the estimator has placed this map with a scale, its points have no place in the world: the
  // page keeps the last placed ones.
  const estimation::MapToWorld& map = estimator_.map_to_world();
  if (r.slam.map_id != slam_map_id_ || !map.initialized() || !estimator_.scale_status().estimated) return;
  slam_points_.update(r.slam_points_map, map.R_world_map(), map.scale(), map.t_world_map(), r.slam.map_id);
}

SlamSummary LabPipelines::slam() const {
  SlamSummary s = slam_;
  const estimation::ScaleStatus& scale = estimator_.scale_status();
  s.scale_estimated = scale.estimated;
  s.scale = scale.scale;
  s.scale_pairs = scale.inliers;
  s.scale_pairs_needed = estimation::ScaleEstimator::kMinInliers;
  return s;
}

PoseEstimate LabPipelines::predict(Seconds t) const {
  const estimation::FusedState f = estimator_.predict_for_control(t);
  PoseEstimate e;
  e.t = t;
  e.valid = f.initialized;
  e.T_world_body = f.T_world_body;
  e.velocity_world = f.velocity_world;
  e.yaw_rate = f.yaw_rate;
  e.source = feedback_of(f.source);
  e.quality = f.quality;
  e.position_sigma_m = f.position_sigma_m;
  e.altitude_sigma_m = f.altitude_sigma_m;
  e.drift_bound_m = f.drift_bound_m;
  e.unobserved_flight_s = f.unobserved_flight_s;
  return e;
}

}  // namespace labo::fusion
