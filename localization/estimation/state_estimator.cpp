#include "localization/estimation/state_estimator.hpp"

#include <cmath>
#include <limits>

#include "core/frames.hpp"
#include "localization/estimation/filter_core.hpp"
#include "localization/estimation/landmark.hpp"
#include "localization/estimation/reacquisition_gate.hpp"
#include "localization/estimation/scale_pair_sampler.hpp"
#include "localization/estimation/source_selector.hpp"
#include "localization/estimation/timed_queue.hpp"
#include "localization/estimation/vision_gate.hpp"

namespace labo::estimation {

using namespace est;

namespace {
constexpr std::size_t kNavdataCapacity = 2048;
constexpr std::size_t kCommandCapacity = 512;
constexpr Seconds kFaceForgetS = 2.0;          // a face unseen this long is placed anew
constexpr int kForcedAcceptAfter = 10;         // innovation-gated frames in a row before re-sync
constexpr int kMapRotationFrames = 30;         // first SLAM frames averaging the map's rotation
// predict()'s reach beyond the newest navdata: the link's default lost_after_s, after which the
// safety monitor, not the model's extrapolation, decides what the drone does.
constexpr Seconds kMaxExtrapolationS = 2.0;

bool finite_pose(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return false;
  const Eigen::Matrix3d R = T.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-3 && std::abs(R.determinant() - 1.0) < 1e-3;
}

Eigen::Isometry3d T_body_cam(CameraId camera) {
  return camera == CameraId::Front ? T_body_cam_front() : T_body_cam_bottom();
}

Eigen::Isometry3d body_pose(const StateVector& s) {
  return make_pose(s.segment<3>(X), s(YAW), s(PITCH), s(ROLL));
}

double position_var(const StateCovariance& P) { return P.block<3, 3>(X, X).trace() / 3.0; }

// A vision fix's noise: its position covariance and yaw sigma, each sigma scaled by `scale` (the
// frame's quality, an inactive source's factor).
Eigen::Matrix<double, 4, 4> measurement_noise(const Eigen::Matrix3d& position_cov, double sigma_yaw, double scale) {
  Eigen::Matrix<double, 4, 4> R = Eigen::Matrix<double, 4, 4>::Zero();
  R.topLeftCorner<3, 3>() = position_cov * (scale * scale);
  R(3, 3) = sigma_yaw * sigma_yaw * scale * scale;
  return R;
}

Eigen::Matrix3d isotropic(double sigma) { return Eigen::Matrix3d::Identity() * (sigma * sigma); }

// An orientation error of `rotation_var` (rad^2, about any axis) in a pose taken across `offset`
// turns the far end about the near one: a covariance of |offset|^2 rotation_var across the line of
// sight, none along it. At 2.5 m, 2 deg is 8.7 cm sideways.
Eigen::Matrix3d sideways_cov(const Eigen::Vector3d& offset, double rotation_var) {
  return rotation_var * (offset.squaredNorm() * Eigen::Matrix3d::Identity() - offset * offset.transpose());
}

// Variance of an object's measured orientation: the localizer's own sigma when it reports one, else
// object_yaw_rad growing with the distance (a panel's tilt is worse determined the smaller it looks).
double object_rotation_var(const EstimatorNoise& noise, const ObjectObservation& o, double distance_m) {
  const double sigma = o.rotation_sigma_rad > 0 ? o.rotation_sigma_rad : noise.object_yaw_rad * std::max(1.0, distance_m);
  return sigma * sigma;
}

enum Counter {
  kNavdata, kCommands, kSlam, kObject, kFace, kRejectedNonfinite, kRejectedOutOfOrder, kRejectedFuture,
  kRejectedLate, kRejectedJumpDistance, kRejectedJumpAngle, kRejectedInnovation, kRejectedNotTracking,
  kRejectedBadInput, kCommandsNonfinite, kNavdataOverflow, kSlamMaps, kObjectsPlaced, kScalePairs,
  kVisionSettling, kScalePairsNoCoverage, kRejectedReacquisition, kReacquisitionConfirmed, kNavdataResumedAfterGap,
  kFlightUnobserved, kSetDown, kCounterCount
};
constexpr const char* kCounterNames[kCounterCount] = {
    "navdata", "commands", "slam_fused", "object_fused", "face_fused", "rejected_nonfinite",
    "rejected_out_of_order", "rejected_future", "rejected_late", "rejected_jump_distance", "rejected_jump_angle",
    "rejected_innovation", "rejected_not_tracking", "rejected_bad_input", "commands_nonfinite_hover",
    "navdata_queue_overflow", "slam_maps", "objects_placed", "scale_pairs", "vision_settling", "scale_pairs_navdata_gap",
    "rejected_reacquisition", "reacquisition_confirmed", "navdata_resumed_after_gap",
    "flight_unobserved", "set_down"};

int source_index(LocalizationSource s) { return static_cast<int>(s); }

Eigen::Vector3d scale_weights(const EstimatorConfig& c) {
  return {c.scale_weight_xy, c.scale_weight_xy, c.scale_weight_z};
}
}  // namespace

struct StateEstimator::Impl {
  Impl(const EstimatorConfig& c, const VisionThresholds& th)
      : config(c), thresholds(th), core(c, th.ultrasound_step_gamma_m), navdata(kNavdataCapacity),
        commands(kCommandCapacity), selector(c.source_enter_count, c.source_timeout_s),
        reacquisition{ReacquisitionGate(c.reacquisition), ReacquisitionGate(c.reacquisition),
                      ReacquisitionGate(c.reacquisition)},
        scale(c.scale), pair_sampler(c.scale_interval_min_s, c.scale_interval_max_s, scale_weights(c),
                                               c.scale.min_displacement_m, c.scale_max_navdata_gap_s) {}

  EstimatorConfig config;
  VisionThresholds thresholds;
  FilterCore core;
  TimedQueue<NavdataSample> navdata;  // at measurement time (receive - navdata delay)
  TimedQueue<MoveCommand> commands;   // at effect time (sent + control delay)
  SourceSelector selector;
  std::array<ReacquisitionGate, 3> reacquisition;  // per vision source, while it is not established
  ScaleEstimator scale;
  MapToWorld map;
  int map_id = 0;
  int map_frames = 0;
  bool map_is_metric = false;
  // A SLAM map is placed where dead reckoning had the camera: its fixes carry that drift with them.
  double map_drift_bound_m = 0;
  double map_unobserved_flight_s = 0;  // ... and where the estimate was not confirmed, that too
  ScalePairSampler pair_sampler;
  std::map<int, Landmark> objects;
  std::map<int, Seconds> object_last_t;
  std::optional<Landmark> face;
  SurfaceMap surfaces;
  bool has_surfaces = false;
  std::array<VisionGate, 3> gates{};
  std::array<Seconds, 3> last_obs_t{-1e18, -1e18, -1e18};
  std::array<int, 3> gated_in_row{};
  Seconds latest_input_t = -std::numeric_limits<double>::infinity();
  std::optional<Seconds> gap_witness_t;  // a navdata time refused as far-future, kept to confirm a gap
  Seconds last_navdata_t = -std::numeric_limits<double>::infinity();
  std::uint32_t last_navdata_sequence = 0;
  std::optional<Eigen::Isometry3d> start_pose;  // start_at_first_navdata(): placed at the next sample
  std::optional<Eigen::Isometry3d> set_down_pose;  // set_down_at_next_navdata(): moved there at the next sample
  bool last_navdata_airborne = false;
  // The longest navdata gap in flight, beyond the firmware's command hold, since the last fix on the
  // lab's frame: the drone's motion in it was assumed, not seen (FusedState::unobserved_flight_s).
  Seconds unobserved_flight_s = 0;
  Seconds last_command_t = -std::numeric_limits<double>::infinity();
  std::array<std::uint64_t, kCounterCount> counters{};

  // The filter at a known pose from t on, with everything tied to the old one dropped (queued inputs,
  // the sources' consistency, the face); the map's placement, its scale and the objects' stay.
  void relocate(const Eigen::Isometry3d& T_world_body, Seconds t);

  void count(Counter c) { ++counters[c]; }

  // Replays queued inputs into `c` up to time `target` (measurement time). `consume` pops them.
  void run(FilterCore& c, Seconds target, bool consume, Seconds vision_t) {
    std::size_t ni = 0, ci = 0;
    while (true) {
      const Seconds tn = ni < navdata.size() ? navdata.at(ni).t : std::numeric_limits<double>::infinity();
      const Seconds tc = ci < commands.size() ? commands.at(ci).t : std::numeric_limits<double>::infinity();
      const Seconds te = std::min(tn, tc);
      if (te > target) break;
      c.predict_to(te);
      if (tc <= tn) {
        c.set_command(commands.at(ci).item, tc);
        ++ci;
      } else {
        if (te >= c.time()) c.apply_navdata(navdata.at(ni).item, selector.any_fused_recently(vision_t),
                                            has_surfaces ? &surfaces : nullptr);
        ++ni;
      }
    }
    c.predict_to(target);
    if (consume) {
      for (; ci > 0; --ci) commands.pop();
      for (; ni > 0; --ni) navdata.pop();
    }
  }

  void advance(Seconds target) {
    if (target > core.time()) run(core, target, true, target);
  }

  bool accept_time(Seconds t) {
    if (!std::isfinite(t)) {
      count(kRejectedNonfinite);
      return false;
    }
    if (std::isfinite(latest_input_t) && t > latest_input_t + config.max_future_s) {
      count(kRejectedFuture);
      return false;
    }
    return true;
  }

  // A navdata packet far ahead of every input so far is a corrupt time or the link back after a gap
  // longer than max_future_s (a Wi-Fi cut, an emulator or drone restart). Alone it is refused and
  // kept as a witness; the next packet within max_future_s after it confirms that the clock moved on,
  // and the filter resumes from there. Refusing them all would freeze the estimate for good after
  // the first long gap, while the drone flies on.
  enum class NavdataTime { Refused, Accepted, AfterGap };
  NavdataTime accept_navdata_time(Seconds t) {
    if (!std::isfinite(t) || !std::isfinite(latest_input_t) || t <= latest_input_t + config.max_future_s) {
      gap_witness_t.reset();
      return accept_time(t) ? NavdataTime::Accepted : NavdataTime::Refused;
    }
    if (gap_witness_t && t >= *gap_witness_t && t <= *gap_witness_t + config.max_future_s) {
      gap_witness_t.reset();
      latest_input_t = t;
      count(kNavdataResumedAfterGap);
      return NavdataTime::AfterGap;
    }
    gap_witness_t = t;
    count(kRejectedFuture);
    return NavdataTime::Refused;
  }

  // Across the gap: the commands sent into the silence never reached the drone, which flew the last
  // one it had received for the firmware's command watchdog, then hovered. Carrying the unsent ones
  // over the gap flew the estimate metres away from a drone that had stopped. So the filter moves to
  // the last packet before the gap, the commands after it are dropped, the last one it had is flown
  // until the watchdog fires, and from there the firmware's hover holds the drone still (its velocity
  // dies away with firmware_hover_stop_s: a hover command on the tilt model alone coasted on at the
  // drag's pace, 4-6 m across an 8-s cut). The uncertainty grows by the motion model.
  void bridge_gap(Seconds t_last_packet, Seconds t_meas_resumed) {
    const Seconds t_last = t_last_packet - config.navdata_delay_s;
    // Beyond the command hold the bridge is a guess: a drone that restarted, was caught or drifted
    // in a draught did not fly it. Say so, until a fix on the lab's frame (or a set-down) confirms.
    if (last_navdata_airborne && t_meas_resumed - t_last > config.firmware_command_hold_s) {
      unobserved_flight_s = std::max(unobserved_flight_s, t_meas_resumed - t_last);
      count(kFlightUnobserved);
    }
    advance(t_last);
    commands.clear();
    const Seconds t_hover = std::max(core.time(), std::min(t_last + config.firmware_command_hold_s, t_meas_resumed));
    core.predict_to(t_hover);
    core.hover_to(t_meas_resumed, config.firmware_hover_stop_s);
  }

  enum class VisionOutcome { Inconsistent, Settling, Gated, Fused };

  // Vision: consistency (D, beta), settling, innovation gate, fusion of position and yaw. With
  // `may_fuse` false (SLAM before its scale is known) a consistent frame only counts as settling.
  VisionOutcome fuse_vision(LocalizationSource source, Seconds t_meas, const Eigen::Isometry3d& T_world_body,
                            const Eigen::Matrix3d& position_cov, double sigma_yaw, double quality,
                            bool may_fuse = true) {
    const int i = source_index(source);
    const VisionGate::Verdict verdict = gates[i].check(T_world_body, t_meas, thresholds.distance_jump_m,
                                                        thresholds.angle_jump_beta_rad);
    if (verdict != VisionGate::Verdict::Consistent) {
      count(verdict == VisionGate::Verdict::JumpDistance ? kRejectedJumpDistance : kRejectedJumpAngle);
      selector.on_inconsistent(source);
      return VisionOutcome::Inconsistent;
    }
    if (!may_fuse) {
      count(kVisionSettling);
      return VisionOutcome::Settling;
    }
    const bool was_established = selector.established(source, t_meas);
    const StateVector& s = core.ekf().state();
    Eigen::Matrix<double, 4, 1> y;
    y.head<3>() = T_world_body.translation() - s.segment<3>(X);
    y(3) = wrap_angle(ypr_from_rotation(T_world_body.linear())(0) - s(YAW));
    Eigen::Matrix<double, 4, N> H = Eigen::Matrix<double, 4, N>::Zero();
    H(0, X) = H(1, Y) = H(2, Z) = H(3, YAW) = 1.0;
    const double q = std::clamp(quality, 0.2, 1.0);
    if (!was_established && !admit_reacquisition(source, t_meas, y, H, measurement_noise(position_cov, sigma_yaw, 1.0 / q)))
      return VisionOutcome::Gated;
    selector.on_consistent(source, t_meas, quality);
    if (selector.consecutive(source) < config.source_enter_count) {
      count(kVisionSettling);
      return VisionOutcome::Settling;
    }
    const double factor = selector.active(t_meas) == source ? 1.0 : config.inactive_source_noise_factor;
    const Eigen::Matrix<double, 4, 4> R = measurement_noise(position_cov, sigma_yaw, factor / q);
    if (was_established && gated_in_row[i] < kForcedAcceptAfter &&
        core.ekf().mahalanobis<4>(y, H, R) > config.vision_gate_chi2) {
      ++gated_in_row[i];
      count(kRejectedInnovation);
      return VisionOutcome::Gated;
    }
    gated_in_row[i] = 0;
    core.ekf().update<4>(y, H, R);
    selector.on_fused(source, t_meas);
    // A fix on the lab's frame ends the dead-reckoning drift (down to the map's own, for SLAM); the
    // face moves with the teacher and fixes nothing.
    if (source == LocalizationSource::Slam) core.set_drift_bound(std::min(core.drift_bound_m(), map_drift_bound_m));
    if (source == LocalizationSource::Homography) core.set_drift_bound(0.0);
    if (source == LocalizationSource::Slam) unobserved_flight_s = std::min(unobserved_flight_s, map_unobserved_flight_s);
    if (source == LocalizationSource::Homography) unobserved_flight_s = 0;
    return VisionOutcome::Fused;
  }

  // A source that is not established (acquired anew, or re-acquired after a loss) must agree with
  // the dead-reckoned estimate, or persist, before it may correct it (reacquisition_gate.hpp). A
  // refused frame also restarts the source's run of consistent frames, so it cannot become the
  // driving source without passing here.
  bool admit_reacquisition(LocalizationSource source, Seconds t_meas, const Eigen::Matrix<double, 4, 1>& y,
                           const Eigen::Matrix<double, 4, N>& H, const Eigen::Matrix<double, 4, 4>& R) {
    const double d2 = core.ekf().mahalanobis<4>(y, H, R);
    switch (reacquisition[source_index(source)].check(y, d2, t_meas, config.source_timeout_s)) {
      case ReacquisitionGate::Verdict::Accepted: return true;
      case ReacquisitionGate::Verdict::Confirmed: {
        // The vision persisted: the estimate is what was wrong, by about y. Its variance grows by
        // that much so the next fusions re-sync it, instead of the established source's innovation
        // gate fighting them.
        StateCovariance P = core.ekf().covariance();
        for (int k = 0; k < 3; ++k) P(X + k, X + k) += y(k) * y(k);
        P(YAW, YAW) += y(3) * y(3);
        core.ekf().reset(core.ekf().state(), P);
        count(kReacquisitionConfirmed);
        return true;
      }
      case ReacquisitionGate::Verdict::Refused: break;
    }
    count(kRejectedReacquisition);
    selector.on_inconsistent(source);
    return false;
  }

  // The common front of every vision input: time checks, then the filter advanced to its time.
  bool admit_vision(LocalizationSource source, Seconds t, Seconds& t_meas) {
    if (!accept_time(t)) return false;
    const int i = source_index(source);
    if (source != LocalizationSource::Homography && t <= last_obs_t[i]) {
      count(kRejectedOutOfOrder);
      return false;
    }
    t_meas = t - config.video_delay_s;
    if (!core.initialized() || t_meas < core.time()) {
      count(kRejectedLate);
      return false;
    }
    if (source != LocalizationSource::Homography) last_obs_t[i] = t;
    advance(t_meas);
    return true;
  }

  void update_scale_pairs(const SlamObservation& o) {
    const StateVector& s = core.ekf().state();
    const Eigen::Vector3d lever = body_pose(s).linear() * T_body_cam_front().translation();
    const MetricOdometry& odo = core.odometry();
    ScaleSample sample;
    sample.t = core.time();
    sample.p_map = o.T_map_cam.translation();
    // The camera's metric position = integrated body odometry + the lever arm to the camera.
    sample.metric = Eigen::Vector3d(odo.xy.x(), odo.xy.y(), odo.z) + lever;
    sample.floor_steps = odo.floor_steps;
    sample.navdata_gap = odo.max_gap;
    core.odometry().reset_gap();
    const std::optional<ScalePair> pair = pair_sampler.add(sample);
    if (!pair) return;
    if (!pair->coverage_ok) {
      count(kScalePairsNoCoverage);
      return;
    }
    const Eigen::Vector3d map_d = map.rotate_to_world(pair->map_displacement);
    Eigen::Vector3d w = scale_weights(config);
    if (pair->z_corrupted) w.z() = 0.0;
    if (scale.add_pair(w.cwiseProduct(map_d), w.cwiseProduct(pair->metric_displacement))) {
      count(kScalePairs);
      map.set_scale(scale.scale());
    }
  }

  FusedState make_state(const FilterCore& c, Seconds t) const {
    FusedState f;
    const StateVector& s = c.ekf().state();
    f.t = t;
    f.initialized = c.initialized();
    f.state = s;
    f.covariance = c.ekf().covariance();
    f.position_world = s.segment<3>(X);
    f.velocity_world = s.segment<3>(VX);
    f.roll = s(ROLL);
    f.pitch = s(PITCH);
    f.yaw = s(YAW);
    f.yaw_rate = s(YAW_RATE);
    f.T_world_body = body_pose(s);
    f.source = selector.active(t);
    f.colour = selector.colour(t);
    f.quality = selector.quality(t);
    f.position_sigma_m = std::sqrt(f.covariance.block<3, 3>(X, X).diagonal().maxCoeff());
    f.altitude_sigma_m = std::sqrt(std::max(0.0, f.covariance(Z, Z)));
    f.drift_bound_m = c.drift_bound_m();
    f.unobserved_flight_s = unobserved_flight_s;
    return f;
  }
};

StateEstimator::StateEstimator(const EstimatorConfig& config, const VisionThresholds& thresholds)
    : impl_(std::make_unique<Impl>(config, thresholds)) {}
StateEstimator::~StateEstimator() = default;
StateEstimator::StateEstimator(StateEstimator&&) noexcept = default;
StateEstimator& StateEstimator::operator=(StateEstimator&&) noexcept = default;

void StateEstimator::Impl::relocate(const Eigen::Isometry3d& T_world_body, Seconds t) {
  StateVector s = StateVector::Zero();
  s.segment<3>(X) = T_world_body.translation();
  const Eigen::Vector3d ypr = ypr_from_rotation(T_world_body.linear());
  s(YAW) = ypr(0);
  s(PITCH) = ypr(1);
  s(ROLL) = ypr(2);
  StateCovariance P = StateCovariance::Zero();
  P.diagonal() << 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-3, 1e-3, 1e-4, 1e-4;
  core.reset(s, P, t);
  navdata.clear();
  commands.clear();
  selector.reset();
  face.reset();
  gates = {};
  for (ReacquisitionGate& g : reacquisition) g.reset();
  last_obs_t = {-1e18, -1e18, -1e18};
  latest_input_t = t;
  gap_witness_t.reset();
  last_navdata_t = last_command_t = -std::numeric_limits<double>::infinity();
  last_navdata_airborne = false;
  unobserved_flight_s = 0;
  start_pose.reset();
  set_down_pose.reset();
}

void StateEstimator::reset(const Eigen::Isometry3d& T_world_body, Seconds t) {
  Impl& m = *impl_;
  m.relocate(T_world_body, t);
  m.scale.reset(m.config.scale.initial_scale);
  m.map.reset();
  m.pair_sampler.reset();
  m.objects.clear();
  m.object_last_t.clear();
}

void StateEstimator::start_at_first_navdata(const Eigen::Isometry3d& T_world_body) {
  reset(T_world_body, 0.0);  // clears everything; the time is set again by the first sample
  impl_->start_pose = T_world_body;
}

void StateEstimator::set_down_at_next_navdata(const Eigen::Isometry3d& T_world_body) {
  impl_->set_down_pose = T_world_body;
}

void StateEstimator::set_surface_map(const SurfaceMap& map) {
  impl_->surfaces = map;
  impl_->has_surfaces = true;
}

bool StateEstimator::add_navdata(const NavdataSample& n) {
  Impl& m = *impl_;
  for (double v : {n.roll_rad, n.pitch_rad, n.yaw_rad, n.altitude_m, n.vx_mps, n.vy_mps, n.vz_mps}) {
    if (!std::isfinite(v)) {
      m.count(kRejectedNonfinite);
      return false;
    }
  }
  if (m.start_pose && std::isfinite(n.t)) reset(*m.start_pose, n.t - m.config.navdata_delay_s);
  if (m.set_down_pose && std::isfinite(n.t)) {
    m.relocate(*m.set_down_pose, n.t - m.config.navdata_delay_s);
    m.count(kSetDown);
  }
  const Impl::NavdataTime verdict = m.accept_navdata_time(n.t);
  if (verdict == Impl::NavdataTime::Refused) return false;
  // Packets received in one burst share a receive time (the link keeps their order): only an older
  // time, or the same packet again, is out of order.
  if (n.t < m.last_navdata_t || (n.t == m.last_navdata_t && n.sequence == m.last_navdata_sequence)) {
    m.count(kRejectedOutOfOrder);
    return false;
  }
  const Seconds t_meas = n.t - m.config.navdata_delay_s;
  if (!m.core.initialized()) {
    // No reset(): start where the navdata says, at the world origin with the navdata's attitude.
    reset(make_pose(Eigen::Vector3d(0, 0, n.altitude_m), 0.0, n.pitch_rad, n.roll_rad), t_meas);
  }
  if (t_meas < m.core.time()) {
    m.count(kRejectedLate);
    return false;
  }
  if (verdict == Impl::NavdataTime::AfterGap && std::isfinite(m.last_navdata_t)) m.bridge_gap(m.last_navdata_t, t_meas);
  m.last_navdata_t = n.t;
  m.last_navdata_sequence = n.sequence;
  m.last_navdata_airborne = control_state::motors_on(n.control_state);
  m.latest_input_t = std::max(m.latest_input_t, n.t);
  if (m.navdata.full()) {
    m.count(kNavdataOverflow);
    m.advance(m.navdata.front().t);
  }
  m.navdata.push(t_meas, n);
  m.count(kNavdata);
  // Move on, leaving room for vision results that may still arrive for recent frames.
  m.advance(n.t - m.config.video_delay_s - m.config.vision_latency_allowance_s);
  return true;
}

bool StateEstimator::add_command(const MoveCommand& command, Seconds t_sent) {
  Impl& m = *impl_;
  if (!m.accept_time(t_sent)) return false;
  if (t_sent < m.last_command_t) {
    m.count(kRejectedOutOfOrder);
    return false;
  }
  MoveCommand c = command;
  if (!std::isfinite(c.roll) || !std::isfinite(c.pitch) || !std::isfinite(c.gaz) || !std::isfinite(c.yaw_rate)) {
    c = MoveCommand{};  // the link sends a hover for a non-finite command
    m.count(kCommandsNonfinite);
  }
  const Seconds t_effect = t_sent + m.config.control_delay_s;
  if (t_effect < m.core.time()) {
    m.count(kRejectedLate);
    return false;
  }
  m.last_command_t = t_sent;
  if (m.commands.full()) m.advance(m.commands.front().t);
  m.commands.push(t_effect, c);
  m.count(kCommands);
  return true;
}

bool StateEstimator::add_slam_pose(const SlamObservation& o) {
  Impl& m = *impl_;
  if (!finite_pose(o.T_map_cam) || !std::isfinite(o.quality)) {
    m.count(kRejectedNonfinite);
    return false;
  }
  if (!o.tracking_good) {
    if (std::isfinite(o.t)) m.selector.on_inconsistent(LocalizationSource::Slam);
    m.count(kRejectedNotTracking);
    return false;
  }
  Seconds t_meas = 0;
  if (!m.admit_vision(LocalizationSource::Slam, o.t, t_meas)) return false;
  const StateVector& s = m.core.ekf().state();
  const Eigen::Isometry3d T_world_cam_est = body_pose(s) * T_body_cam_front();
  if (!m.map.initialized() || o.map_id != m.map_id) {
    // A new map: place it where the filter says the camera is; its scale starts from scratch.
    m.map_id = o.map_id;
    m.scale.reset(o.map_is_metric ? 1.0 : m.config.scale.initial_scale);
    m.map_is_metric = o.map_is_metric;
    m.map.initialize(o.T_map_cam, T_world_cam_est, m.scale.scale());
    m.map_drift_bound_m = m.core.drift_bound_m();
    m.map_unobserved_flight_s = m.unobserved_flight_s;
    m.map_frames = 1;
    m.pair_sampler.reset();
    m.gates[source_index(LocalizationSource::Slam)] = {};
    m.count(kSlamMaps);
    return true;
  }
  if (m.map_frames < kMapRotationFrames) {
    ++m.map_frames;
    m.map.refine_rotation(o.T_map_cam, T_world_cam_est, 1.0 / m.map_frames);
  }
  const Eigen::Isometry3d T_world_body = m.map.T_world_cam(o.T_map_cam) * T_body_cam_front().inverse();
  // Until a few displacement pairs fix the scale, SLAM poses are metric nonsense: they only feed the
  // scale estimator (the paper's stage 1), the drone flies on navdata.
  const bool scale_known = m.map_is_metric || m.scale.status().estimated;
  const auto outcome = m.fuse_vision(LocalizationSource::Slam, t_meas, T_world_body, isotropic(m.config.noise.slam_position_m),
                                     m.config.noise.slam_yaw_rad, o.quality, scale_known);
  if (outcome == Impl::VisionOutcome::Inconsistent) return false;
  if (!m.map_is_metric) m.update_scale_pairs(o);
  if (outcome == Impl::VisionOutcome::Fused) m.count(kSlam);
  return outcome != Impl::VisionOutcome::Gated;
}

bool StateEstimator::add_object_pose(const ObjectObservation& o) {
  Impl& m = *impl_;
  if (!finite_pose(o.T_cam_object) || !std::isfinite(o.quality) || !std::isfinite(o.rotation_sigma_rad) ||
      (o.T_world_object_surveyed && !finite_pose(*o.T_world_object_surveyed))) {
    m.count(kRejectedNonfinite);
    return false;
  }
  if (o.object_index < 0 || o.rotation_sigma_rad < 0) {
    m.count(kRejectedBadInput);
    return false;
  }
  const auto last = m.object_last_t.find(o.object_index);
  if (std::isfinite(o.t) && last != m.object_last_t.end() && o.t <= last->second) {
    m.count(kRejectedOutOfOrder);
    return false;
  }
  Seconds t_meas = 0;
  if (!m.admit_vision(LocalizationSource::Homography, o.t, t_meas)) return false;
  m.object_last_t[o.object_index] = o.t;
  const Eigen::Isometry3d T_bc = T_body_cam(o.camera);
  const StateVector& s = m.core.ekf().state();
  const double distance = o.T_cam_object.translation().norm();
  const double sigma_obs = m.config.noise.object_position_m * std::max(1.0, distance);
  PoseWithVariance cascade;
  cascade.T = body_pose(s) * T_bc * o.T_cam_object;
  // The object's place inherits the drone's yaw error turned across the distance to it.
  const StateCovariance& P = m.core.ekf().covariance();
  const Eigen::Vector3d drone_to_object = cascade.T.translation() - s.segment<3>(X);
  const Eigen::Vector3d drone_to_object_flat(drone_to_object.x(), drone_to_object.y(), 0.0);
  cascade.position_var = position_var(P) + sigma_obs * sigma_obs +
                         sideways_cov(drone_to_object_flat, P(est::YAW, est::YAW)).trace() / 3.0;
  const double object_rot_var = object_rotation_var(m.config.noise, o, distance);
  cascade.rotation_var = P(est::YAW, est::YAW) + object_rot_var;
  auto it = m.objects.find(o.object_index);
  if (it == m.objects.end()) {
    std::optional<PoseWithVariance> surveyed;
    if (o.T_world_object_surveyed)
      surveyed = PoseWithVariance{*o.T_world_object_surveyed, std::pow(m.config.noise.survey_position_m, 2),
                                  std::pow(m.config.noise.survey_rotation_rad, 2)};
    it = m.objects.emplace(o.object_index, place_landmark(cascade, surveyed ? &*surveyed : nullptr, t_meas)).first;
    m.count(kObjectsPlaced);
  } else if (it->second.refinements < m.config.object_placement_frames &&
             m.selector.active(t_meas) == LocalizationSource::Slam) {
    // SLAM localizes the drone independently of the object: refine the object, not the drone.
    it->second.fuse(cascade);
    it->second.last_seen = t_meas;
    m.selector.on_consistent(LocalizationSource::Homography, t_meas, o.quality);
    return true;
  }
  it->second.last_seen = t_meas;
  const Eigen::Isometry3d T_world_body = it->second.T_world_landmark * o.T_cam_object.inverse() * T_bc.inverse();
  // The drone's place from the panel: the panel's position error, the object's own, and the panel's
  // orientation error turning the drone about the panel (the weak part of a far panel's pose). The
  // placed object's own rotation error is left out on purpose: it is one bias shared by every frame,
  // which the relative hold in front of the panel does not see and no frame weighting can average.
  const Eigen::Matrix3d position_cov =
      isotropic(std::sqrt(sigma_obs * sigma_obs + it->second.position_var)) +
      sideways_cov(T_world_body.translation() - it->second.T_world_landmark.translation(), object_rot_var);
  // The drone's yaw from the panel is as good as the panel's measured orientation (at range, or with
  // two IPPE branches in play, degrees), never better than object_yaw_rad.
  const double sigma_yaw = std::max(m.config.noise.object_yaw_rad, o.rotation_sigma_rad);
  const auto outcome = m.fuse_vision(LocalizationSource::Homography, t_meas, T_world_body, position_cov, sigma_yaw, o.quality);
  if (outcome == Impl::VisionOutcome::Fused) m.count(kObject);
  return outcome == Impl::VisionOutcome::Fused || outcome == Impl::VisionOutcome::Settling;
}

bool StateEstimator::add_face_pose(const FaceObservation& o) {
  Impl& m = *impl_;
  if (!finite_pose(o.T_cam_face) || !std::isfinite(o.quality)) {
    m.count(kRejectedNonfinite);
    return false;
  }
  Seconds t_meas = 0;
  if (!m.admit_vision(LocalizationSource::Face, o.t, t_meas)) return false;
  const Eigen::Isometry3d T_bc = T_body_cam_front();
  const StateVector& s = m.core.ekf().state();
  const double sigma_obs = m.config.noise.face_position_m * std::max(1.0, o.T_cam_face.translation().norm());
  if (!m.face || t_meas - m.face->last_seen > kFaceForgetS) {
    const PoseWithVariance cascade{body_pose(s) * T_bc * o.T_cam_face,
                                   position_var(m.core.ekf().covariance()) + sigma_obs * sigma_obs, 0.0};
    m.face = place_landmark(cascade, nullptr, t_meas);
  }
  const Eigen::Isometry3d T_world_body = m.face->T_world_landmark * o.T_cam_face.inverse() * T_bc.inverse();
  const double sigma_pos = std::sqrt(sigma_obs * sigma_obs + m.face->position_var);
  const bool fused = m.fuse_vision(LocalizationSource::Face, t_meas, T_world_body, isotropic(sigma_pos),
                                   m.config.noise.face_yaw_rad, o.quality) == Impl::VisionOutcome::Fused;
  // The teacher moves: the face's world pose follows the cascade, fast while another source holds the
  // drone, with the face memory's time constant while the face itself is the reference.
  const Seconds dt = std::max(0.0, t_meas - m.face->last_seen);
  const bool face_is_reference = m.selector.active(t_meas) == LocalizationSource::Face;
  const double k = face_is_reference ? 1.0 - std::exp(-dt / m.config.face_memory_s) : 0.5;
  m.face->blend(body_pose(m.core.ekf().state()) * T_bc * o.T_cam_face, k);
  m.face->last_seen = t_meas;
  if (fused) m.count(kFace);
  return fused;
}

FusedState StateEstimator::predict(Seconds t) const {
  Impl& m = *impl_;
  // The filter cannot run backwards: for a time it has already passed, the state it holds is the
  // best there is, and it is stamped with its own time so no caller takes it for the pose at t.
  if (!(t > m.core.time())) return m.make_state(m.core, m.core.time());
  // Nor can the motion model alone carry it far: without navdata (a link down, a drone not yet
  // connected, an empty replay) each call would integrate the whole gap since the last packet in
  // 10 ms steps - an hour without a drone makes every control tick 360 000 steps and stalls the
  // server's flight thread. Past kMaxExtrapolationS beyond the newest navdata (or the filter's
  // time, when newer) the state is the one extrapolated that far, stamped with that time. Test
  // "estimation: without navdata a prediction reaches at most 2 s past the newest packet, stamped
  // where it stopped".
  const Seconds newest = std::max(m.core.time(), m.last_navdata_t - m.config.navdata_delay_s);
  const Seconds target = std::min(t, newest + kMaxExtrapolationS);
  FilterCore copy = m.core;
  m.run(copy, target, false, target);
  return m.make_state(copy, target);
}

FusedState StateEstimator::predict_for_control(Seconds now) const {
  return predict(now + impl_->config.control_delay_s);
}

FusedState StateEstimator::filtered() const { return impl_->make_state(impl_->core, impl_->core.time()); }
Seconds StateEstimator::filter_time() const { return impl_->core.time(); }
const ScaleStatus& StateEstimator::scale_status() const { return impl_->scale.status(); }
const MapToWorld& StateEstimator::map_to_world() const { return impl_->map; }

std::optional<Eigen::Isometry3d> StateEstimator::T_world_object(int object_index) const {
  const auto it = impl_->objects.find(object_index);
  if (it == impl_->objects.end()) return std::nullopt;
  return it->second.T_world_landmark;
}

std::optional<Eigen::Isometry3d> StateEstimator::T_world_face() const {
  if (!impl_->face) return std::nullopt;
  return impl_->face->T_world_landmark;
}

LocalizationSource StateEstimator::source() const { return impl_->selector.active(impl_->core.time()); }
SourceColour StateEstimator::colour() const { return impl_->selector.colour(impl_->core.time()); }
const EstimatorConfig& StateEstimator::config() const { return impl_->config; }

EstimatorStatistics StateEstimator::statistics() const {
  EstimatorStatistics st;
  for (int i = 0; i < kCounterCount; ++i) st.counters[kCounterNames[i]] = impl_->counters[i];
  st.counters["scale_pairs_outliers_at_arrival"] = static_cast<std::uint64_t>(impl_->scale.outliers_at_arrival());
  st.counters["scale_changes"] = static_cast<std::uint64_t>(impl_->scale.scale_changes());
  st.counters["covariance_repairs"] = static_cast<std::uint64_t>(impl_->core.ekf().repairs());
  st.counters["floor_steps"] = static_cast<std::uint64_t>(impl_->core.counters().floor_steps);
  st.counters["ultrasound_fused_as_motion"] = static_cast<std::uint64_t>(impl_->core.counters().fused_as_motion);
  st.counters["ultrasound_short_echoes"] = static_cast<std::uint64_t>(impl_->core.counters().short_echoes);
  st.counters["velocity_dropouts"] = static_cast<std::uint64_t>(impl_->core.counters().velocity_dropouts);
  st.counters["velocity_dropout_packets"] = static_cast<std::uint64_t>(impl_->core.counters().velocity_dropout_packets);
  return st;
}

}  // namespace labo::estimation
