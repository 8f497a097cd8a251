#pragma once
// Head-pose sequences for the face benchmark, after the UPNA protocol: "guided" sweeps one angle at a
// time (yaw ±45°, pitch ±30°, roll ±30°) and "free" moves all of them at once, with the head drifting
// in translation, 0.6-2 m from the camera. Deterministic for a seed.
#include <Eigen/Geometry>
#include <random>
#include <string>
#include <vector>

namespace labo::bench {

struct HeadPoseSequence {
  std::string name;
  bool guided = true;
  double distance_m = 1.0;
  double noise_sigma = 3.0;   // grey levels
  double blur_sigma_px = 0.5;
  std::vector<Eigen::Isometry3d> T_cam_face;  // one per frame
};

// `count` sequences of `frames` frames: guided and free alternate, distances spread over
// [min_distance_m, max_distance_m].
std::vector<HeadPoseSequence> make_head_pose_sequences(int count, int frames, unsigned seed,
                                                       double min_distance_m = 0.6, double max_distance_m = 2.0);

}  // namespace labo::bench
