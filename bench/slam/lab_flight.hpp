#pragma once
// SLAM benchmark flights in the simulated lab (drone/sim's LabRenderer, config/lab.json): the images
// the inspect mission's SLAM sees (the room's real textures, motion blur over the shutter, sensor
// noise), on a scripted ground-truth path shaped like that mission's: take-off from the platform,
// a vertical scale manoeuvre, a turn towards the instrument and an approach at up to ~1.4 m/s with
// the body pitching to accelerate and brake, down to the 0.8 m standoff.
#include <memory>
#include <opencv2/core.hpp>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "bench/slam/bench_flights.hpp"

namespace labo::sim {
class LabRenderer;
}  // namespace labo::sim

namespace labo::bench {

// The inspect mission's path towards `instrument`, front-camera poses at `fps`.
Flight lab_inspect_flight(const lab::LabDescription& lab, const lab::InstrumentSpec& instrument, double fps = 30.0);

// Face-follow's search where it took off: off the platform, up to a standing adult's face height
// (1.6 m), the same scale manoeuvre, then `sweeps` full turns at `yaw_rate` rad/s where it is
// (`orbit_m` 0) or with the camera looking out from a circle of that radius round it.
Flight lab_sweep_flight(const lab::LabDescription& lab, double yaw_rate, int sweeps, double orbit_m, double fps = 30.0);

// Renders a flight's front-camera frames in the simulated lab, 8-bit grey.
class SimulatedLabFrames {
 public:
  SimulatedLabFrames(const lab::LabDescription& lab, const CamerasConfig& cameras, bool noise);
  ~SimulatedLabFrames();
  SimulatedLabFrames(const SimulatedLabFrames&) = delete;
  SimulatedLabFrames& operator=(const SimulatedLabFrames&) = delete;

  // Frame i of the flight; the body's velocities for the motion blur come from the neighbouring frames.
  cv::Mat render(const Flight& flight, std::size_t i);

 private:
  std::unique_ptr<sim::LabRenderer> renderer_;
  cv::Mat bgr_;
};

}  // namespace labo::bench
