#pragma once
// The lab as every layer sees it: the room, benches, instruments (planar front panels with a template
// image and a physical size), the base with its landing platform, fixed observer cameras and the
// teacher's scripted walk. Read from config/lab.json by load_lab_description(), which refuses
// overlapping objects, missing or mis-sized textures, cameras outside the room, non-positive sizes and
// a teacher path through a wall or an object, naming the file, the key and the reason.
//
// Object frame of a planar object: origin at the panel's centre, x to the panel's right, y down (as in
// the template image), z into the panel (away from a viewer in front of it). Template pixel (u, v)
// maps to (((u + 0.5) / w_px - 0.5) * width_m, ((v + 0.5) / h_px - 0.5) * height_m, 0).
#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::lab {

// An axis-aligned box in world coordinates (m).
struct Box3 {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();

  Eigen::Vector3d size() const { return max - min; }
  Eigen::Vector3d centre() const { return 0.5 * (min + max); }
  bool contains(const Eigen::Vector3d& p, double margin = 0.0) const;
  // True when the boxes share a volume thicker than `tolerance_m` along every axis (touching is fine).
  bool overlaps(const Box3& other, double tolerance_m = 0.005) const;
};

struct BenchSpec {
  std::string id;
  Box3 box;
};

struct InstrumentSpec {
  std::string id, name;
  std::filesystem::path template_path;  // absolute (resolved against the lab file's folder)
  double width_m = 0, height_m = 0;     // the panel (template) size
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
  double sift_switch_distance_m = 2.0;  // closer than this: template tracking; farther: SIFT
  int sift_min_inliers = 20;
  double depth_m = 0.3;                 // the housing behind the panel, along object z

  // Corners of the panel in world coordinates: top-left, top-right, bottom-right, bottom-left.
  // Fixed size, so the sensor model can ask for surface heights every step without allocating.
  std::array<Eigen::Vector3d, 4> corners_world() const;
  // Axis-aligned bounds of panel + housing.
  Box3 bounds() const;
};

// The landing platform: its top is a planar object seen by the bottom camera (object z points down
// into the platform, object y towards world -x so that the template appears upright to a drone
// facing +x), raised `thickness_m` above the floor so the ultrasound sees a step.
struct PlatformSpec : InstrumentSpec {
  double thickness_m = 0.10;
  Box3 box() const;
};

// A fixed camera in the room (the overview webcam of the web page, the face benchmark's viewpoint).
struct ObserverCameraSpec {
  std::string id;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d look_at = Eigen::Vector3d::UnitX();
  double horizontal_fov_deg = 70;
  // OpenCV camera frame (x right, y down, z forward) in world coordinates.
  Eigen::Isometry3d T_world_cam() const;
};

struct HeadMotionSpec {
  // Head angles relative to the walking direction, as sinusoids: amplitude (deg) and period (s).
  double yaw_amplitude_deg = 35, yaw_period_s = 7;
  double pitch_amplitude_deg = 10, pitch_period_s = 5;
  double roll_amplitude_deg = 8, roll_period_s = 9;
};

// How the simulated teacher keeps out of a hovering drone's way (a person stops or steps aside
// rather than walk into one; drone/sim/teacher_walker.hpp): walking, with the drone's centre in
// the corridor their body sweeps and within keep_clear_m ahead of its front, they stop until it is
// clear; with side_step_m > 0 they also step up to that far aside, away from the drone, where the
// floor is free, and walk on from there.
struct GiveWaySpec {
  double keep_clear_m = 0.6;
  double side_step_m = 0.0;
};

struct TeacherSpec {
  std::vector<Eigen::Vector2d> waypoints;  // floor positions (m), walked in order, then looped
  double speed_mps = 0.4;
  double pause_s = 3.0;                    // standing still at each waypoint
  // A walk drawn for one run (drone/sim/teacher_walk.hpp) rather than the lab file's path: each
  // waypoint's own pause (empty: pause_s at each), and no loop (the teacher stays at the last one).
  std::vector<double> pauses_s;
  bool loop = true;
  double interpupillary_distance_m = 0.063;
  double eye_height_m = 1.65;
  double body_radius_m = 0.25;
  std::string face_image;                  // the photograph the head is textured from (assets/)
  HeadMotionSpec head;
  GiveWaySpec give_way;
};

// Floor or wall rectangles rendered without texture (the bottom camera's velocity fails above them,
// SLAM finds no corners there).
struct BareArea {
  std::string surface;             // "floor", "wall_xmin", "wall_xmax", "wall_ymin", "wall_ymax"
  Eigen::Vector2d min, max;        // in the surface's 2D coordinates (floor: x, y; walls: along, z)
};

struct LabDescription {
  std::filesystem::path source;
  Box3 room;
  std::vector<BenchSpec> benches;
  std::vector<InstrumentSpec> instruments;
  PlatformSpec platform;
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();  // drone's start: on the platform
  std::vector<ObserverCameraSpec> cameras;
  TeacherSpec teacher;
  unsigned texture_seed = 1;
  std::vector<BareArea> bare_areas;

  const InstrumentSpec* find_instrument(const std::string& id) const;
  // Height of the highest surface under (x, y): floor 0, a bench top, the platform, an instrument top.
  double surface_height(double x, double y) const;
  bool floor_is_bare(double x, double y) const;
};

// A panel's object frame from its centre, the yaw of its outward normal (the direction a viewer looks
// from, the lab file's facing_deg) and its tilt (top leaning away from the viewer).
Eigen::Isometry3d panel_pose(const Eigen::Vector3d& centre, double facing_rad, double tilt_rad = 0.0);

// Throws ConfigError "<file>: <key path>: <reason>".
LabDescription load_lab_description(const std::filesystem::path& file);
LabDescription read_lab_description(const ConfigReader& root, const std::filesystem::path& base_dir);
// config/lab.json of the source tree.
std::filesystem::path default_lab_path();

}  // namespace labo::lab
