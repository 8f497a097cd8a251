#pragma once
// FilterCore: the part of the estimator that moves with time and is copied for predictions: the EKF,
// the navdata observations (roll/pitch, yaw increments, bottom-camera and vertical velocities, the
// ultrasound through the AltitudeTracker), the active command, and the metric odometry the scale
// estimator pairs with SLAM displacements. A value type without heap members: copying it for
// predict() does not allocate.
#include <optional>

#include "drone/drone_link.hpp"
#include "localization/estimation/altitude_tracker.hpp"
#include "localization/estimation/drone_ekf.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/velocity_dropout_detector.hpp"

namespace labo::estimation {

// Metric displacement integrated from navdata since the filter started (world axes).
struct MetricOdometry {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // integrated bottom-camera velocities
  double z = 0;                                  // accepted ultrasound increments
  int floor_steps = 0;
  Seconds max_gap = 0;                           // largest navdata interval since reset_gap()
  void reset_gap() { max_gap = 0; }
};

struct NavdataCounters {
  int floor_steps = 0;
  int fused_as_motion = 0;
  int short_echoes = 0;
  int velocity_dropouts = 0;         // onsets of a bottom-camera velocity dropout
  int velocity_dropout_packets = 0;  // packets whose horizontal velocity was not fused
};

class FilterCore {
 public:
  FilterCore(const EstimatorConfig& config, double gamma_m);

  void reset(const StateVector& s, const StateCovariance& P, Seconds t);
  Seconds time() const { return t_; }
  bool initialized() const { return initialized_; }

  // Propagates the model to t (no-op when t <= time()).
  void predict_to(Seconds t);
  // Predicts to t under the firmware's own hover (DroneEkf::predict_firmware_hover), then takes a
  // hover as the command from t on: the link was down and the drone held itself still.
  void hover_to(Seconds t, double stop_time_s);
  void set_command(const MoveCommand& command, Seconds effect_time);
  // A navdata sample whose measurement time is time() (predict_to first). `vision_holding` selects the
  // looser velocity noise and the per-packet yaw anchor (notes: tum_ardrone's PTAM-valid mode).
  void apply_navdata(const NavdataSample& sample, bool vision_holding, const SurfaceMap* map);

  // How far dead reckoning may have drifted since the last fix on the lab's frame
  // (DriftBoundSettings); grows with each navdata packet applied without vision holding.
  double drift_bound_m() const { return drift_bound_m_; }
  void set_drift_bound(double m) { drift_bound_m_ = m; }

  DroneEkf& ekf() { return ekf_; }
  const DroneEkf& ekf() const { return ekf_; }
  const MetricOdometry& odometry() const { return odometry_; }
  MetricOdometry& odometry() { return odometry_; }
  const NavdataCounters& counters() const { return counters_; }
  const AltitudeTracker& altitude() const { return altitude_; }
  const VelocityDropoutDetector& velocity_dropout() const { return dropout_; }

 private:
  void observe_attitude(const NavdataSample& n);
  void observe_yaw(const NavdataSample& n, bool vision_holding, Seconds gap);
  void observe_velocity(const NavdataSample& n, bool vision_holding);
  // Asks the dropout detector whether this packet's horizontal velocity may be fused; at an onset,
  // takes back what the failing measurements pulled the estimate off by.
  bool velocity_usable(const NavdataSample& n);
  void fuse_horizontal_velocity(const NavdataSample& n, bool vision_holding);
  void observe_altitude(const NavdataSample& n, const SurfaceMap* map);
  void observe_landed();

  EstimatorConfig config_;
  DroneEkf ekf_;
  AltitudeTracker altitude_;
  VelocityDropoutDetector dropout_;
  Seconds t_ = 0;
  bool initialized_ = false;
  std::optional<MoveCommand> command_;
  Seconds command_effect_t_ = 0;
  // Yaw increments: the filter's yaw and the navdata's yaw at the anchor.
  bool yaw_anchored_ = false;
  double yaw_anchor_filter_ = 0;
  double yaw_anchor_navdata_ = 0;
  double last_navdata_yaw_ = 0;
  bool last_nav_valid_ = false;
  Seconds last_nav_t_ = 0;
  MetricOdometry odometry_;
  NavdataCounters counters_;
  double drift_bound_m_ = 0;
};

}  // namespace labo::estimation
