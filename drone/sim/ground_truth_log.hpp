#pragma once
// GroundTruthLog: what really happened in a simulated run, as CSV for plots and error metrics.
//  - <file>: one row per record(): time, the drone's true pose, velocity, firmware phase, battery,
//    the teacher's floor position and head pose (face frame of core/candide3.hpp), crash;
//  - <file stem>_objects.csv: the lab's fixed objects once (instruments, the platform, benches),
//    each with its pose in the world.
// Poses as position (m) and yaw, pitch, roll (rad, Z-Y-X as in core/frames.hpp).
#include <filesystem>
#include <fstream>

#include "drone/lab/lab_description.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo::sim {

class GroundTruthLog {
 public:
  // Creates both files (and their folder); throws std::runtime_error naming a file it cannot write.
  GroundTruthLog(const std::filesystem::path& file, const lab::LabDescription& lab);
  void record(const QuadrotorState& drone, const SceneState& scene);
  std::filesystem::path objects_file() const { return objects_file_; }
  std::size_t rows() const { return rows_; }

 private:
  std::ofstream out_;
  std::filesystem::path objects_file_;
  std::size_t rows_ = 0;
};

}  // namespace labo::sim
