#include "bench/experiments/experiment_flight.hpp"

#include <cmath>
#include <stdexcept>

#include "core/frames.hpp"

namespace labo::bench {

Eigen::Vector4d xyz_yaw(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d p = T.translation();
  return {p.x(), p.y(), p.z(), ypr_from_rotation(T.linear())[0]};
}

EstimatorCounts estimator_counts(const estimation::StateEstimator& estimator) {
  const estimation::EstimatorStatistics stats = estimator.statistics();
  EstimatorCounts c;
  c.object_fused = stats.count("object_fused");
  c.slam_fused = stats.count("slam_fused");
  c.rejected_reacquisition = stats.count("rejected_reacquisition");
  c.reacquisition_confirmed = stats.count("reacquisition_confirmed");
  c.rejected_innovation = stats.count("rejected_innovation");
  c.rejected_jump = stats.count("rejected_jump_distance") + stats.count("rejected_jump_angle");
  c.velocity_dropouts = stats.count("velocity_dropouts");
  c.velocity_dropout_packets = stats.count("velocity_dropout_packets");
  return c;
}

FlightSample sample_of(const control::FlightStatus& s, const control::FlightOutput& out, const estimation::StateEstimator& estimator,
                       const Eigen::Isometry3d& truth, Seconds t, const std::optional<Eigen::Isometry3d>& true_face) {
  FlightSample sample;
  sample.t = t;
  sample.estimated = xyz_yaw(s.pose.T_world_body);
  sample.estimated_velocity = s.pose.velocity_world.head<2>();
  sample.position_sigma_m = s.pose.position_sigma_m;
  sample.drift_bound_m = s.pose.drift_bound_m;
  sample.truth = xyz_yaw(truth);
  sample.desired = s.desired;
  sample.source = s.source;
  sample.slam = s.slam.state;
  const fusion::TargetObservation& target = s.stage_index == 5 ? s.platform : s.mission == "find_teacher" ? s.face : s.instrument;
  sample.target = target.state;
  if (target.state == fusion::TrackState::Lost) sample.target_reason = target.reason;
  if (target.state == fusion::TrackState::Tracking) sample.target_method = target.method;
  sample.stage_index = s.stage_index;
  sample.stage = s.stage;
  if (true_face) {
    const Eigen::Vector3d p = true_face->translation(), z = true_face->linear().col(2);
    sample.face_true_world = Eigen::Vector4d(p.x(), p.y(), p.z(), std::atan2(z.y(), z.x()));
    sample.face_true_cam = ((truth * T_body_cam_front()).inverse() * *true_face).translation();
  }
  if (s.face.state == fusion::TrackState::Tracking) sample.face_measured_cam = s.face.T_cam_target.translation();
  if (out.action == control::FlightOutput::Action::Move) sample.command = {out.move.roll, out.move.pitch, out.move.gaz, out.move.yaw_rate};
  sample.action = to_string(out.action);
  for (const std::string& alert : s.safety_alerts) sample.alerts += (sample.alerts.empty() ? "" : "; ") + alert;
  sample.estimator = estimator_counts(estimator);
  return sample;
}

Eigen::Isometry3d ExperimentFlight::true_T_cam(const Eigen::Isometry3d& T_world_target) const {
  return (true_pose() * true_lab().T_body_front).inverse() * T_world_target;
}

const fusion::PlanarTarget& ExperimentFlight::true_instrument(const std::string& id) const {
  const fusion::PlanarTarget* target = true_lab().lab.find_instrument(id);
  if (!target) throw std::invalid_argument("the lab has no instrument '" + id + "'");
  return *target;
}

void ExperimentFlight::run(double seconds) {
  const Seconds end = now() + seconds - 1e-9;
  while (now() < end) tick();
}

bool ExperimentFlight::run_until(const std::function<bool()>& done, double timeout_s) {
  const Seconds end = now() + timeout_s;
  while (now() < end) {
    tick();
    if (done()) return true;
  }
  return false;
}

}  // namespace labo::bench
