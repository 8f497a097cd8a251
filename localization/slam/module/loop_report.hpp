#pragma once
// What one loop detection found and did (mapping statistics, benchmark trace).

namespace labo::slam {

struct LoopReport {
  bool detected = false;
  bool corrected = false;
  int current = -1, loop = -1;
  int inliers = 0, confirmed = 0;
  double correction_translation = 0;  // map units, of the current keyframe's centre
  double correction_rotation_deg = 0;
  double correction_scale = 1;
  int points_fused = 0;
};

}  // namespace labo::slam
