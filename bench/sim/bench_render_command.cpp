#include "bench/sim/bench_render_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>

#include "bench/frame_timing.hpp"
#include "core/frames.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "drone/sim/render_commands.hpp"
#include "localization/face/teacher_head.hpp"

namespace labo::bench {

using lab::LabDescription;

using sim::LabRenderOptions;
using sim::LabRenderer;
using sim::RenderSetup;
using sim::SceneState;
using sim::TexturedHeadModel;
using sim::load_render_setup;
using sim::teacher_head_pose;


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
  s.T_world_head = teacher_head_pose(lab, s.teacher_floor_xy.x(), s.teacher_floor_xy.y(),
                             std::atan2(p.y() - s.teacher_floor_xy.y(), p.x() - s.teacher_floor_xy.x()));
  s.exposure_gain = 1.0 + 0.15 * std::sin(0.3 * t);
  return s;
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

int run_bench_render_command(const ParsedArgs& args) {
  const RenderSetup s = load_render_setup(args);
  const int frames = args.integer_or("--frames", 300, 1, 100000);
  const auto save_dir = args.value("--save");
  std::optional<TexturedHeadModel> head;
  if (!args.flag("--no-face")) head = face::load_lab_teacher_head(s.lab);
  LabRenderer renderer(s.lab, s.cameras, std::move(head), 1);
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
                << std::setw(6) << quantile_of(cpu, 0.5) << std::setw(7) << quantile_of(cpu, 0.95) << std::setw(7)
                << quantile_of(cpu, 1.0) << std::setw(9) << quantile_of(wall, 0.5) << std::setw(7) << quantile_of(wall, 0.95)
                << std::setw(7) << quantile_of(wall, 1.0) << std::setw(14) << std::setprecision(0) << 100.0 * uniform / frames << "%"
                << std::setw(15) << std::setprecision(1) << quantile_of(motion, 0.5) << "\n";
    }
  }
  return 0;
}

}  // namespace labo::bench
