#include "drone/sim/render_commands.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/camera_config.hpp"
#include "core/config_reader.hpp"
#include "core/frames.hpp"
#include "core/source_tree.hpp"
#include "drone/sim/lab_renderer.hpp"

namespace labo::sim {

using lab::LabDescription;
using lab::load_lab_description;


namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

RenderSetup load_render_setup(const ParsedArgs& args) {
  const std::filesystem::path file = args.value_or("--config", (source_root() / "config" / "default.json").string());
  const ConfigDocument doc = ConfigDocument::load(file);
  const ConfigReader root = doc.root();
  RenderSetup s;
  s.cameras = read_cameras_config(root.object("cameras"));
  const std::filesystem::path lab_file =
      args.value("--lab") ? std::filesystem::path(*args.value("--lab")) : file.parent_path() / root.string_or("lab", "lab.json");
  s.lab = load_lab_description(lab_file);
  return s;
}

namespace {

// "a,b,c" -> numbers; UsageError naming the option and the expected count.
std::vector<double> numbers_of(const ParsedArgs& args, const std::string& option, std::size_t min_count, std::size_t max_count,
                               const std::string& what) {
  const std::string text = *args.value(option);
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size() || !std::isfinite(out.back())) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw UsageError(option + " " + text + ": '" + item + "' is not a number (expected " + what + ")");
    }
  }
  if (out.size() < min_count || out.size() > max_count) throw UsageError(option + " " + text + ": expected " + what);
  return out;
}

}  // namespace

Eigen::Isometry3d teacher_head_pose(const LabDescription& lab, double x, double y, double yaw) {
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0), up = Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = up.cross(forward);  // the subject's left
  T.linear().col(1) = up;
  T.linear().col(2) = forward;
  T.translation() = Eigen::Vector3d(x, y, lab.teacher.eye_height_m);
  return T;
}

namespace {

std::optional<TexturedHeadModel> maybe_head(const ParsedArgs& args, const RenderSetup& s, const TeacherHeadLoader& load_head) {
  if (args.flag("--no-face") || !load_head) return std::nullopt;
  return load_head(s.lab);
}

}  // namespace

const CommandSpec& sim_render_command_spec() {
  static const CommandSpec spec{
      "sim render",
      "",
      "Render the simulated lab's front and bottom cameras at a drone pose (PNG files).",
      {{"--config", "FILE", "cameras and lab (default: config/default.json)"},
       {"--lab", "FILE", "lab description (default: the config's)"},
       {"--pose", "X,Y,Z,YAW[,PITCH,ROLL]", "drone pose, metres and degrees (default: 0,0,1,0)"},
       {"--velocity", "VX,VY,VZ", "world velocity for motion blur, m/s (default: 0,0,0)"},
       {"--rates", "ROLL,PITCH,YAW", "body angular rates for motion blur, deg/s (default: 0,0,0)"},
       {"--teacher", "X,Y,YAW", "teacher's floor position (m) and facing (deg) (default: first waypoint, facing the drone)"},
       {"--no-teacher", "", "leave the teacher out"},
       {"--no-face", "", "draw the teacher's head untextured (no photograph needed)"},
       {"--gain", "G", "exposure gain (default 1)"},
       {"--sharp", "", "no motion blur, no noise"},
       {"--seed", "N", "noise seed (default 1)"},
       {"--out", "PREFIX", "writes PREFIX_front.png and PREFIX_bottom.png (default: render)"}},
      0,
      0};
  return spec;
}

int run_sim_render_command(const ParsedArgs& args, const TeacherHeadLoader& load_head) {
  const RenderSetup s = load_render_setup(args);
  SceneState scene;
  scene.t = 0;
  std::vector<double> pose{0, 0, 1, 0};
  if (args.value("--pose")) pose = numbers_of(args, "--pose", 4, 6, "X,Y,Z,YAW or X,Y,Z,YAW,PITCH,ROLL");
  pose.resize(6, 0.0);
  scene.T_world_body = make_pose({pose[0], pose[1], pose[2]}, pose[3] * kDeg, pose[4] * kDeg, pose[5] * kDeg);
  if (!s.lab.room.contains(scene.T_world_body.translation())) {
    throw UsageError("--pose: the drone at " + *args.value("--pose") + " is outside the room");
  }
  if (args.value("--velocity")) {
    const auto v = numbers_of(args, "--velocity", 3, 3, "VX,VY,VZ");
    scene.velocity_world_mps = {v[0], v[1], v[2]};
  }
  if (args.value("--rates")) {
    const auto r = numbers_of(args, "--rates", 3, 3, "ROLL,PITCH,YAW");
    scene.angular_velocity_body_radps = Eigen::Vector3d(r[0], r[1], r[2]) * kDeg;
  }
  Eigen::Vector3d teacher(s.lab.teacher.waypoints.front().x(), s.lab.teacher.waypoints.front().y(), 0.0);
  const Eigen::Vector3d drone = scene.T_world_body.translation();
  teacher.z() = std::atan2(drone.y() - teacher.y(), drone.x() - teacher.x());
  if (args.value("--teacher")) {
    const auto t = numbers_of(args, "--teacher", 3, 3, "X,Y,YAW");
    teacher = {t[0], t[1], t[2] * kDeg};
  }
  scene.teacher_present = !args.flag("--no-teacher");
  scene.teacher_floor_xy = teacher.head<2>();
  scene.T_world_head = teacher_head_pose(s.lab, teacher.x(), teacher.y(), teacher.z());
  scene.exposure_gain = args.number_or("--gain", 1.0, 0.05, 20.0);

  LabRenderOptions options;
  if (args.flag("--sharp")) options.motion_blur = options.noise = false;
  LabRenderer renderer(s.lab, s.cameras, maybe_head(args, s, load_head),
                       static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30)), options);
  const std::string prefix = args.value_or("--out", "render");
  for (const auto& [id, name] : {std::pair{CameraId::Front, "front"}, std::pair{CameraId::Bottom, "bottom"}}) {
    cv::Mat bgr;
    renderer.render(id, scene, bgr);
    const std::string file = prefix + "_" + name + ".png";
    if (!cv::imwrite(file, bgr)) throw std::runtime_error("cannot write " + file);
    std::cout << "wrote " << file << " (" << bgr.cols << "x" << bgr.rows << ", motion " << std::fixed << std::setprecision(1)
              << renderer.last_stats(id).blur_px << " px)\n";
  }
  return 0;
}

}  // namespace labo::sim
