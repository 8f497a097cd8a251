#pragma once
// StateEstimator: the fused estimate of the drone's pose and velocity that every controller acts on
// (paper §4.1 and §6, after tum_ardrone's filter; notes/tum_ardrone.md).
//
// An extended Kalman filter over s = [x, y, z, vx, vy, vz, roll, pitch, yaw, yaw_rate] in the world
// frame (z up, yaw counter-clockwise, SI units), propagated with the AR.Drone's response to the
// commands sent (MotionModelConstants), corrected by:
//   navdata: roll/pitch, yaw increments, bottom-camera velocities (body frame, rotated by yaw), vertical
//            velocity, ultrasound altitude through the AltitudeTracker (floor steps vs true motion);
//   vision:  SLAM poses through the map-to-world similarity (scale from ScaleEstimator), planar objects
//            through the object's world pose (placed at first sighting, refined later), the face.
//
// Delay compensation: inputs are queued with their timestamps. Navdata received at t describes the
// drone at t - navdata_delay; a frame received at t shows it at t - video_delay; a command sent at t
// acts from t + control_delay. The persistent filter advances to each vision result's time, fuses it,
// and otherwise trails the newest navdata by video_delay + vision_latency_allowance. predict(t) runs
// a copy through the queued navdata and commands to any later t (at most 2 s past the newest navdata:
// the returned state is stamped with the time it reached); a controller asks for
// predict_for_control(now) = predict(now + control_delay), the pose when its command takes effect.
//
// Bad input (non-finite values, timestamps out of order or far in the future, vision poses that jump
// by more than D or beta between consecutive frames, late vision results) is rejected and counted in
// statistics(). Deterministic, single-threaded, no wall clock; steady-state updates do not allocate.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/observations.hpp"
#include "localization/estimation/scale_estimator.hpp"
#include "localization/estimation/surface_map.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::estimation {

// State indices.
namespace est {
inline constexpr int X = 0, Y = 1, Z = 2, VX = 3, VY = 4, VZ = 5, ROLL = 6, PITCH = 7, YAW = 8, YAW_RATE = 9;
inline constexpr int N = 10;
}  // namespace est

using StateVector = Eigen::Matrix<double, est::N, 1>;
using StateCovariance = Eigen::Matrix<double, est::N, est::N>;

struct FusedState {
  Seconds t = 0;
  bool initialized = false;           // false until the first navdata
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();
  double roll = 0, pitch = 0, yaw = 0, yaw_rate = 0;
  StateVector state = StateVector::Zero();
  StateCovariance covariance = StateCovariance::Identity();
  LocalizationSource source = LocalizationSource::DeadReckoning;
  SourceColour colour = SourceColour::Red;
  double quality = 0;                 // 0..1: the driving source's quality, 0 in dead reckoning
  double position_sigma_m = 0;        // sqrt of the largest position variance
  double altitude_sigma_m = 0;        // sqrt of the altitude's variance (ultrasound-measured: no drift)
  // How far dead reckoning may have carried the estimate off the lab's frame since its last fix
  // there (DriftBoundSettings): a bound, not a sigma, and not in the covariance.
  double drift_bound_m = 0;
  // Seconds of flight the navdata did not see (the longest gap in flight beyond the firmware's
  // command hold) since the last fix on the lab's frame (SLAM or a planar target) or a set-down: the
  // estimate bridged them on an assumption (the last command, then the firmware's hover), so where
  // the drone is has not been confirmed. 0: confirmed.
  double unobserved_flight_s = 0;
};

// Counts of accepted and rejected inputs, by kind ("navdata", "rejected_nonfinite", ...).
struct EstimatorStatistics {
  std::map<std::string, std::uint64_t> counters;
  std::uint64_t count(const std::string& key) const {
    const auto it = counters.find(key);
    return it == counters.end() ? 0 : it->second;
  }
};

class StateEstimator {
 public:
  StateEstimator(const EstimatorConfig& config = {}, const VisionThresholds& thresholds = {});
  ~StateEstimator();
  StateEstimator(StateEstimator&&) noexcept;
  StateEstimator& operator=(StateEstimator&&) noexcept;
  StateEstimator(const StateEstimator&) = delete;
  StateEstimator& operator=(const StateEstimator&) = delete;

  // Starts over at a known pose (take-off from the base), velocity zero.
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t);
  // Starts over at a known pose whose time is not known yet: the filter is placed there at the
  // measurement time of the next navdata sample, whatever its clock says. A server's clock has run
  // for seconds before the link delivers its first navdata; reset(T, 0) would make every sample look
  // like an input from the future and the filter would never move.
  void start_at_first_navdata(const Eigen::Isometry3d& T_world_body);
  // The drone was set down at a known pose (someone put it on its platform): the filter moves there at
  // the next navdata sample, and keeps the SLAM map's placement and scale and the objects' places,
  // which start_at_first_navdata() forgets.
  void set_down_at_next_navdata(const Eigen::Isometry3d& T_world_body);
  void set_surface_map(const SurfaceMap& map);

  // Inputs; each returns whether it was accepted (rejections are counted by reason).
  bool add_navdata(const NavdataSample& sample);
  bool add_command(const MoveCommand& command, Seconds t_sent);
  bool add_slam_pose(const SlamObservation& observation);
  bool add_object_pose(const ObjectObservation& observation);
  bool add_face_pose(const FaceObservation& observation);

  // The estimate at drone time t (no implicit delay): queued navdata and commands up to t are used,
  // then the motion model alone. For t at or before filter_time() it is the filtered state, stamped
  // with filter_time() (the filter does not run backwards).
  FusedState predict(Seconds t) const;
  // predict(now + control_delay): the state when a command computed now takes effect.
  FusedState predict_for_control(Seconds now) const;
  // The persistent filter (at time filter_time(), all vision fused so far).
  FusedState filtered() const;
  Seconds filter_time() const;

  // Map, objects, face.
  const ScaleStatus& scale_status() const;
  const MapToWorld& map_to_world() const;
  std::optional<Eigen::Isometry3d> T_world_object(int object_index) const;
  std::optional<Eigen::Isometry3d> T_world_face() const;

  LocalizationSource source() const;
  SourceColour colour() const;
  const EstimatorConfig& config() const;
  EstimatorStatistics statistics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::estimation
