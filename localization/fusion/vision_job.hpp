#pragma once
// One frame's vision work, cut in three so that a real-time runtime can run the costly middle on a
// worker thread while control keeps ticking (server/runtime/vision_worker.hpp):
//  1. LabPipelines::prepare_vision (the flight thread): picks the front-ends the focus selects and
//     gives each its inputs from the estimator at the frame's capture time; copies the grey frame.
//  2. run_vision_job (one thread at a time): runs those front-ends and nothing else.
//  3. LabPipelines::apply_vision (the flight thread): hands the results, stamped with the frame's
//     capture time, to the estimator, whose delay handling places them in its past.
// LabPipelines::on_video does all three at once (lockstep runs, tests); a lockstep run can also hold
// the results back for as long as the worker would take (bench/experiments/vision_latency.hpp).
//
// Buffers are reused: a job and a results object kept across frames allocate nothing once they have
// seen a frame of each kind.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/fusion/vision_front_end.hpp"

namespace labo::fusion {

struct VisionJob {
  Seconds t = 0;                       // the frame's capture time
  CameraId camera = CameraId::Front;
  cv::Mat gray;                        // the frame in 8-bit grey, owned by the job

  TargetFrontEnd* instrument = nullptr;  // the focused instrument's front-end, or none
  std::string instrument_id;
  std::optional<double> instrument_distance_m;  // predicted camera-to-panel distance
  TargetFrontEnd* platform = nullptr;
  std::optional<double> platform_distance_m;
  TargetFrontEnd* face = nullptr;
  SlamFrontEnd* slam = nullptr;
  bool slam_pause = false;             // bottom-camera frame: SLAM sees nothing and reports off
  std::optional<Eigen::Isometry3d> slam_prior_T_cam_map;
  std::optional<Eigen::Vector3d> gravity_down_cam;

  // Whether any front-end runs on this frame.
  bool has_work() const { return instrument || platform || face || slam; }
  // Forgets the front-ends and inputs; keeps the grey buffer.
  void clear();
};

struct VisionResults {
  Seconds t = 0;
  CameraId camera = CameraId::Front;
  bool has_instrument = false, has_platform = false, has_face = false, has_slam = false;
  std::string instrument_id;
  TargetObservation instrument, platform, face;
  SlamFrame slam;
  // Once a second while SLAM runs: a bounded sample of its map's points (map units, map slam.map_id),
  // for the lab page's map; the buffer is reused.
  bool has_slam_points = false;
  std::vector<Eigen::Vector3d> slam_points_map;
  std::string failure;  // set by a runner whose front-end threw: the frame yielded nothing
  // Whether a detector (template matching, SIFT, the face detector) ran, rather than only a tracker
  // following its last result: a detection costs several times a tracked frame.
  bool detected() const;
  // Whether a target (instrument, platform, face) was tracked in this frame, rather than searched for.
  bool tracking() const;
};

// Runs the job's front-ends on its frame into `out` (reused). Touches the job's front-ends only.
void run_vision_job(const VisionJob& job, VisionResults& out);

}  // namespace labo::fusion
