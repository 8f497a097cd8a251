#include "bench/face/head_pose_sequences.hpp"

#include <cmath>
#include <numbers>

#include "localization/face/face_geometry.hpp"

namespace labo::bench {

using face::HeadAngles;
using face::head_rotation;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A smooth random signal in [-1, 1]: two sinusoids with random periods (4-10 s at 30 fps) and phases.
struct SmoothSignal {
  double f1, f2, p1, p2;
  SmoothSignal(std::mt19937& rng) {
    std::uniform_real_distribution<double> period(120, 300), phase(0, 2 * kPi);
    f1 = 2 * kPi / period(rng);
    f2 = 2 * kPi / period(rng) * 1.7;
    p1 = phase(rng);
    p2 = phase(rng);
  }
  double operator()(int frame) const { return 0.65 * std::sin(f1 * frame + p1) + 0.35 * std::sin(f2 * frame + p2); }
};

// Guided: one third of the frames per angle, each a full sweep 0 -> +max -> -max -> 0.
HeadAngles guided_angles(int frame, int frames) {
  const int third = std::max(1, frames / 3);
  const int axis = std::min(2, frame / third);
  const double s = std::sin(2 * kPi * static_cast<double>(frame - axis * third) / third);
  HeadAngles a;
  if (axis == 0) a.yaw = 45 * kDeg * s;
  if (axis == 1) a.pitch = 30 * kDeg * s;
  if (axis == 2) a.roll = 30 * kDeg * s;
  return a;
}
}  // namespace

std::vector<HeadPoseSequence> make_head_pose_sequences(int count, int frames, unsigned seed, double min_distance_m,
                                                       double max_distance_m) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(2.0, 5.0), blur(0.3, 1.1);
  std::vector<HeadPoseSequence> out;
  for (int s = 0; s < count; ++s) {
    HeadPoseSequence q;
    q.guided = s % 2 == 0;
    const double u = count > 1 ? static_cast<double>(s) / (count - 1) : 0.5;
    q.distance_m = min_distance_m + u * (max_distance_m - min_distance_m);
    q.name = std::string(q.guided ? "guided" : "free") + "_" + std::to_string(s) + "_" +
             std::to_string(static_cast<int>(std::lround(q.distance_m * 100))) + "cm";
    q.noise_sigma = noise(rng);
    q.blur_sigma_px = blur(rng);
    const SmoothSignal yaw(rng), pitch(rng), roll(rng), dx(rng), dy(rng), dz(rng);
    for (int f = 0; f < frames; ++f) {
      HeadAngles a = q.guided ? guided_angles(f, frames)
                              : HeadAngles{45 * kDeg * yaw(f), 30 * kDeg * pitch(f), 30 * kDeg * roll(f)};
      // The head drifts: ±8 % of the distance sideways, ±5 % vertically, ±10 % in depth (free
      // movement), a quarter of that while guided.
      const double k = q.guided ? 0.25 : 1.0;
      const double z = q.distance_m * (1 + 0.10 * k * dz(f));
      const Eigen::Vector3d t(0.08 * k * q.distance_m * dx(f), 0.05 * k * q.distance_m * dy(f) - 0.02, z);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = head_rotation(a);
      T.translation() = t;
      q.T_cam_face.push_back(T);
    }
    out.push_back(std::move(q));
  }
  return out;
}

}  // namespace labo::bench
