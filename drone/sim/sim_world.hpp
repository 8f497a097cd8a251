#pragma once
// SimWorld: the simulated lab as it really is for one run. The flight software is built from the
// configuration alone (the lab file, the cameras' calibration, the estimator's delays); the world it
// flies in is this. The nominal world is exactly the configuration; a randomized world is drawn per
// seed around it, within WorldRanges (docs/sim.md, "The world"):
//  - the drone: mass and inertia, rotor and air drag, the inner loops' time constants, each rotor's
//    thrust, the battery's charge and internal resistance (QuadrotorParams::deviation, battery);
//  - its sensors' biases (SensorBiases);
//  - the instruments' and the platform's placements off the lab file (the drone starts on the
//    platform where it really is);
//  - the cameras' intrinsics and distortion off the configured calibration, their mounting tilt;
//  - the video and navdata delays;
//  - light: exposure changes and the lamps' flicker; Wi-Fi: link-loss bursts and video stalls;
//  - the teacher's walk (unless the ranges leave it out): random legs over the free floor, random
//    pauses, a walking speed and a head sway (teacher_walk.hpp) instead of the lab file's path.
// The draws come from their own generator (seeded from the run's seed), so a randomized world leaves
// the sensors' and the link's noise streams as they are.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "drone/sim/teacher_walk.hpp"

namespace labo::sim {

// The parts of a randomized world that can be kept at the configuration's values, to measure what each
// costs the flight alone ("--nominal-factors", docs/sim.md).
enum class WorldFactor { Drone, Sensors, Placements, Lens, Mounting, Delays, Lighting, Link, Teacher };
inline constexpr std::array<WorldFactor, 9> kWorldFactors{WorldFactor::Drone,    WorldFactor::Sensors, WorldFactor::Placements,
                                                          WorldFactor::Lens,     WorldFactor::Mounting, WorldFactor::Delays,
                                                          WorldFactor::Lighting, WorldFactor::Link,    WorldFactor::Teacher};
std::string to_string(WorldFactor factor);
// "drone", "sensors", "placements", "lens", "mounting", "delays", "lighting", "link", "teacher";
// anything else is nullopt.
std::optional<WorldFactor> parse_world_factor(std::string_view text);

// A set of factors (a bit per factor).
class WorldFactorSet {
 public:
  void insert(WorldFactor f) { bits_ |= bit(f); }
  bool contains(WorldFactor f) const { return (bits_ & bit(f)) != 0; }
  bool empty() const { return bits_ == 0; }
  bool operator==(const WorldFactorSet&) const = default;

 private:
  static unsigned bit(WorldFactor f) { return 1u << static_cast<unsigned>(f); }
  unsigned bits_ = 0;
};

// A symmetric range is ± the value; an interval is [min, max].
struct WorldInterval {
  double min = 0, max = 0;
};

struct WorldRanges {
  // The drone (fractions of the nominal value).
  double mass = 0.10;             // mass and inertia together
  double drag = 0.30;             // rotor drag and air drag, each
  double inner_loop_lag = 0.30;   // motor, attitude, yaw-rate and vertical-speed time constants, each
  double rotor_thrust = 0.03;     // each rotor's thrust per demand
  WorldInterval battery_start_percent{60, 100};
  WorldInterval battery_resistance_ohm{0.04, 0.16};
  // Sensor biases.
  double attitude_bias_deg = 0.3;       // roll, pitch, each
  double velocity_scale = 0.05;
  double velocity_bias_mps = 0.02;      // forward, left, each
  double ultrasound_scale = 0.02;
  double ultrasound_bias_m = 0.01;
  double gyro_bias_radps = 0.01;
  double accel_bias_mps2 = 0.05;
  // Placements: an offset in a ball of this radius, a rotation in a ball of this angle (the platform
  // shifts on the floor and turns about the vertical only).
  double placement_m = 0.05;
  double placement_deg = 3.0;
  // Cameras.
  double focal_fraction = 0.03;         // fx and fy by one factor: the focal length
  double aspect_fraction = 0.005;       // fx / fy: the pixels' aspect ratio, known far better
  double principal_point_px = 5.0;      // cx, cy, each
  double k1 = 0.03, k2 = 0.03, tangential = 0.002;        // front: residuals of its calibration
  double bottom_k1 = 0.05;              // bottom: configured without distortion, it has some
  double mounting_tilt_deg = 2.0;       // each camera: a rotation in a ball of this angle
  // Link.
  WorldInterval video_delay_s{0.050, 0.150};
  WorldInterval navdata_delay_s{0.020, 0.060};
  // Events, drawn as Poisson processes over the first `horizon_s` of the run.
  double horizon_s = 600;
  double lighting_interval_s = 40;      // mean time between exposure changes
  WorldInterval lighting_gain{0.6, 1.6};
  WorldInterval lighting_duration_s{1.0, 5.0};
  WorldInterval flicker_amplitude{0.02, 0.08};  // the whole run
  WorldInterval flicker_hz{0.5, 10.0};
  double link_loss_interval_s = 20;     // Wi-Fi bursts: nothing gets through
  WorldInterval link_loss_s{0.1, 0.6};
  double video_stall_interval_s = 30;   // the video stream alone stalls
  WorldInterval video_stall_s{0.2, 1.0};
  // The teacher's walk, drawn; empty: the teacher keeps to the lab file's path (the flight software
  // has no obstacle avoidance: inspect's and perturb's campaigns keep the teacher in the strip the lab
  // file keeps clear of the stand-offs).
  std::optional<TeacherWalkRanges> teacher_walk = TeacherWalkRanges{};
  // Factors drawn as usual and then set back to the configuration's values: every other factor keeps
  // the value it has in the whole randomized world of the same seed.
  WorldFactorSet nominal;
};

// Where one object really is: its offset (world, m) and rotation (world, axis × angle, rad) from the
// lab file's placement.
struct PlacementDraw {
  std::string id;
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();
};

struct SimWorld {
  WorldMode mode = WorldMode::Nominal;
  std::uint64_t seed = 1;
  lab::LabDescription lab;              // the placements as they are, the teacher's walk as walked
  CamerasConfig cameras;           // the cameras as they are
  CameraMounts mounts;
  SimulatedLabSettings settings;   // the drone, its sensors' biases, the events
  SimLinkSettings link;            // the delays
  std::vector<PlacementDraw> placements;        // randomized: every instrument, then the platform
  Eigen::Vector3d front_tilt_rad = Eigen::Vector3d::Zero();   // mounting rotations (camera frame)
  Eigen::Vector3d bottom_tilt_rad = Eigen::Vector3d::Zero();
  WorldFactorSet nominal_factors;  // randomized: the factors kept at the configuration's values
};

// The world of a run seeded `sim.lab.seed`: the configuration itself when `sim.world` is nominal, a
// draw around it when randomized. Deterministic: the same inputs give the same world.
SimWorld make_sim_world(const lab::LabDescription& lab_file, const CamerasConfig& calibration, const SimConfig& sim,
                        const WorldRanges& ranges = {});

}  // namespace labo::sim
