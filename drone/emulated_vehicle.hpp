#pragma once
// What the AR.Drone 2.0 emulator (drone/ardrone2/, speaking the protocol on loopback) needs from a
// simulated vehicle (drone/sim/). The emulator decodes AT commands and calls these in LaboDrone's
// conventions (MoveCommand signs, SI units); it reads telemetry and rendered frames back and encodes
// them as navdata and PaVE/H.264. The vehicle owns its physics and firmware behaviour (take-off and
// landing sequences, hover when no command arrives for 2 s, emergency cut-out).
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "drone/drone_link.hpp"

namespace labo {

// Everything a full-mode navdata packet reports, in SI units; `nav` is what the demo option carries.
struct VehicleTelemetry {
  NavdataSample nav;
  Eigen::Vector3d accel_body_mps2 = Eigen::Vector3d::Zero();  // specific force, body frame
  Eigen::Vector3d gyro_body_radps = Eigen::Vector3d::Zero();
  double pressure_pa = 101325.0;
  double magneto_heading_rad = 0.0;
  double wind_speed_mps = 0.0;
  double wind_angle_rad = 0.0;
  double wifi_link_quality = 1.0;  // 0..1
  bool flying = false;
  bool emergency = false;
  bool battery_low = false;
  bool motors_cut = false;
};

class EmulatedVehicle {
 public:
  virtual ~EmulatedVehicle() = default;
  // Commands stamped with the emulator's clock (seconds).
  virtual void takeoff(Seconds t) = 0;
  virtual void land(Seconds t) = 0;
  virtual void emergency(Seconds t) = 0;  // the REF emergency toggle
  virtual void flat_trim(Seconds t) = 0;
  // `hover` = PCMD flag bit 0 clear: the firmware holds position and ignores the values.
  virtual void move(const MoveCommand& command, bool hover, Seconds t) = 0;
  virtual void select_camera(CameraId camera, Seconds t) = 0;

  // Advances physics and sensors to time t (monotonic).
  virtual void advance_to(Seconds t) = 0;
  virtual Seconds now() const = 0;
  virtual VehicleTelemetry telemetry() const = 0;
  // The selected camera's current view, 640x360 BGR, into `bgr` (reallocated only when its size or
  // type differ, so a caller reusing one Mat does not allocate per frame).
  virtual CameraId selected_camera() const = 0;
  virtual void render(CameraId camera, cv::Mat& bgr) = 0;
};

}  // namespace labo
