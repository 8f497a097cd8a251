#include "drone/sim/render_commands.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
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

namespace labo {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct RenderSetup {
  LabDescription lab;
  CamerasConfig cameras;
};

RenderSetup load_setup(const ParsedArgs& args) {
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

// The teacher standing at (x, y), facing yaw, eyes at their height.
Eigen::Isometry3d head_pose(const LabDescription& lab, double x, double y, double yaw) {
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0), up = Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = up.cross(forward);  // the subject's left
  T.linear().col(1) = up;
  T.linear().col(2) = forward;
  T.translation() = Eigen::Vector3d(x, y, lab.teacher.eye_height_m);
  return T;
}

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
  const RenderSetup s = load_setup(args);
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
  scene.T_world_head = head_pose(s.lab, teacher.x(), teacher.y(), teacher.z());
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

namespace {

// A flight through the lab for the benchmark: an ellipse around the room's middle at 0.85-1.35 m, the
// nose swinging around the direction of travel so every wall, bench and instrument is seen.
SceneState bench_scene(const LabDescription& lab, int frame, double fps) {
  const double t = frame / fps;
  const Eigen::Vector3d c = lab.room.centre();
  const double rx = 0.3 * lab.room.size().x(), ry = 0.25 * lab.room.size().y(), w = 0.3;  // rad/s around the ellipse
  SceneState s;
  s.t = t;
  const Eigen::Vector3d p(c.x() + rx * std::cos(w * t), c.y() + ry * std::sin(w * t), 1.1 + 0.25 * std::sin(0.4 * t));
  const Eigen::Vector3d v(-rx * w * std::sin(w * t), ry * w * std::cos(w * t), 0.1 * std::cos(0.4 * t));
  const double yaw = std::atan2(v.y(), v.x()) + 1.2 * std::sin(0.5 * t);
  const double yaw_rate = w + 0.6 * std::cos(0.5 * t);
  const double pitch = 0.08 * std::sin(1.3 * t), roll = 0.06 * std::sin(1.1 * t);
  s.T_world_body = make_pose(p, yaw, pitch, roll);
  s.velocity_world_mps = v;
  s.angular_velocity_body_radps = Eigen::Vector3d(0.07 * std::cos(1.1 * t), 0.1 * std::cos(1.3 * t), yaw_rate);
  // The teacher walks back and forth between the first two waypoints, facing the drone.
  const Eigen::Vector2d a = lab.teacher.waypoints[0], b = lab.teacher.waypoints[1];
  const double f = 0.5 - 0.5 * std::cos(0.1 * t);
  s.teacher_floor_xy = a + f * (b - a);
  s.T_world_head = head_pose(lab, s.teacher_floor_xy.x(), s.teacher_floor_xy.y(),
                             std::atan2(p.y() - s.teacher_floor_xy.y(), p.x() - s.teacher_floor_xy.x()));
  s.exposure_gain = 1.0 + 0.15 * std::sin(0.3 * t);
  return s;
}

// CPU time of this thread (ms): on a shared machine, what the renderer itself costs; wall time
// also counts the time other processes hold the core.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

}  // namespace

const CommandSpec& bench_render_command_spec() {
  static const CommandSpec spec{"bench render",
                                "",
                                "Time the simulated lab's renderer per frame: each camera, sharp and with blur + noise.",
                                {{"--config", "FILE", "cameras and lab (default: config/default.json)"},
                                 {"--lab", "FILE", "lab description (default: the config's)"},
                                 {"--frames", "N", "frames per camera and mode (default 300: 10 s at 30 fps)"},
                                 {"--no-face", "", "draw the teacher's head untextured (no photograph needed)"},
                                 {"--save", "DIR", "also write every 30th frame as PNG into DIR"}},
                                0,
                                0};
  return spec;
}

int run_bench_render_command(const ParsedArgs& args, const TeacherHeadLoader& load_head) {
  const RenderSetup s = load_setup(args);
  const int frames = args.integer_or("--frames", 300, 1, 100000);
  const auto save_dir = args.value("--save");
  LabRenderer renderer(s.lab, s.cameras, maybe_head(args, s, load_head), 1);
  std::cout << "bench render: " << frames << " frames per camera and mode along a flight through " << s.lab.source.string()
            << " (target: <= 3 ms per 640x360 frame, one core)\n"
            << "                              cpu ms/frame         wall ms/frame\n"
            << "camera  mode        size      median   p95    max   median   p95    max  uniform_tiles  motion_px(median)\n";
  cv::Mat bgr;
  for (const auto& [id, name] : {std::pair{CameraId::Front, "front"}, std::pair{CameraId::Bottom, "bottom"}}) {
    for (const bool effects : {false, true}) {
      LabRenderOptions o;
      o.motion_blur = o.noise = effects;
      renderer.set_options(o);
      renderer.render(id, bench_scene(s.lab, 0, 30.0), bgr);  // first frame: buffers sized
      std::vector<double> cpu, wall, motion;
      double uniform = 0;
      for (int i = 0; i < frames; ++i) {
        const SceneState scene = bench_scene(s.lab, i, 30.0);
        const double c0 = thread_cpu_ms();
        const auto t0 = std::chrono::steady_clock::now();
        renderer.render(id, scene, bgr);
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cpu.push_back(thread_cpu_ms() - c0);
        const auto& st = renderer.last_stats(id);
        uniform += static_cast<double>(st.tracer.uniform_tiles) /
                   std::max(1, st.tracer.uniform_tiles + st.tracer.mixed_tiles + st.tracer.empty_tiles);
        motion.push_back(st.blur_px);
        if (save_dir && i % 30 == 0) {
          std::ostringstream f;
          f << *save_dir << "/" << name << (effects ? "_fx_" : "_sharp_") << std::setw(4) << std::setfill('0') << i << ".png";
          cv::imwrite(f.str(), bgr);
        }
      }
      std::cout << std::left << std::setw(8) << name << std::setw(12) << (effects ? "blur+noise" : "sharp") << std::setw(10)
                << (std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows)) << std::right << std::fixed << std::setprecision(2)
                << std::setw(6) << percentile(cpu, 0.5) << std::setw(7) << percentile(cpu, 0.95) << std::setw(7)
                << percentile(cpu, 1.0) << std::setw(9) << percentile(wall, 0.5) << std::setw(7) << percentile(wall, 0.95)
                << std::setw(7) << percentile(wall, 1.0) << std::setw(14) << std::setprecision(0) << 100.0 * uniform / frames << "%"
                << std::setw(15) << std::setprecision(1) << percentile(motion, 0.5) << "\n";
    }
  }
  return 0;
}

}  // namespace labo
