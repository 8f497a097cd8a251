#pragma once
// Sequences with ground truth for the planar pipeline: approach (3 m -> 0.5 m), hover at 0.8 m,
// lateral pass (the panel crosses the field of view), motion blur, H.264 round trip, lighting change,
// corrupted frames (loss and recovery), the landing platform seen by the bottom camera during a
// descent (all rendered by synthetic_scene's PlanarViewRenderer), and an approach of the lab's
// oscilloscope rendered by the simulated lab's LabRenderer (drone/sim). Each runs through PlanarObjectLocalizer with each tracker; errors are measured against
// the rendered pose.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "localization/planar/planar_config.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::bench {

struct RangeBinStats {
  std::string tracker;
  double min_m = 0, max_m = 0;
  int poses = 0;
  double median_error_percent = 0, p95_error_percent = 0, median_error_deg = 0, p95_error_deg = 0;
  double median_rotation_sigma_deg = 0, rotation_within_2sigma_percent = 0;
  double median_filtered_error_deg = 0, p95_filtered_error_deg = 0;
};

struct SequenceStats {
  std::string sequence, tracker;
  int frames = 0, frames_in_view = 0, frames_with_pose = 0, frames_in_view_without_pose = 0;
  int detections = 0, losses = 0, gross_errors = 0;  // gross: > 10 % of range or > 10 degrees
  int recoveries = 0, max_recovery_frames = 0;       // frames in view from a loss to the next pose
  double min_range_m = 0, max_range_m = 0;
  double median_error_mm = 0, p95_error_mm = 0;
  double median_error_percent = 0, p95_error_percent = 0;
  double median_error_deg = 0, p95_error_deg = 0;
  // The reported rotation uncertainty against the error: its median, and how often the error is
  // within 2 sigma (95 % for an honest Gaussian sigma).
  double median_rotation_sigma_deg = 0, rotation_within_2sigma_percent = 0;
  // The orientation fused over frames by PlanarPoseFilter (planar_pose_filter.hpp), same poses.
  double median_filtered_error_deg = 0, p95_filtered_error_deg = 0;
  int refined_poses = 0;  // poses from the SE(3) refinement
  std::map<std::string, int> loss_reasons;
  double median_frame_ms = 0, median_tracking_ms = 0, p95_tracking_ms = 0, mean_detection_ms = 0;
  double median_tracking_cpu_ms = 0;  // this thread's CPU time (wall time includes the neighbours' load)
  // SE(3) refinement Gauss-Newton iterations per tracked frame (PlanarResult::refinement_iterations).
  double mean_refinement_iterations = 0;
  std::vector<RangeBinStats> range_bins;  // this sequence's poses by range (0.4-1, 1-2, 2-3.1 m)
};

// One frame of one sequence, for `bench planar --frames-csv`: where the error is, not only how big.
// Errors are the estimate minus the truth in the camera frame (x right, y down, z forward); the
// rotation error is the axis-angle vector of R_est * R_trueᵀ, in degrees, in the camera frame.
struct FrameRecord {
  std::string sequence, tracker;
  int frame = 0;
  double range_m = 0;
  bool in_view = false, has_pose = false, refined = false;
  std::string state;
  Eigen::Vector3d position_error_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_error_deg = Eigen::Vector3d::Zero();
  // The same rotation error in the panel's frame (about its horizontal in-plane axis x, its vertical
  // in-plane axis y, its normal z): R_trueᵀ times the camera-frame vector.
  Eigen::Vector3d panel_rotation_error_deg = Eigen::Vector3d::Zero();
  double rotation_sigma_deg = 0, cpu_ms = 0;
  Eigen::Vector3d filtered_rotation_error_deg = Eigen::Vector3d::Zero();  // PlanarPoseFilter's
};

struct SequenceBenchResult {
  std::string renderer;  // which renderer produced the frames
  std::vector<SequenceStats> sequences;
  std::vector<FrameRecord> frames;  // every frame of every sequence and tracker
  std::vector<RangeBinStats> range_bins;  // all sequences pooled (the H.264 sequence's noise seed 0 only), per tracker
  int h264_seeds = 1;
  std::vector<RangeBinStats> h264_seed_bins;  // the H.264 sequence's poses pooled over its noise seeds, per tracker
};

// The H.264 sequence's bit rate: what LaboDrone's driver configures (link.video_max_bitrate_kbps,
// docs/ardrone2.md); the firmware's own default is 1000 (--h264-kbps 1000).
inline constexpr int kDefaultH264Kbps = 4000;
// At most this many noise seeds of the H.264 sequence (`h264_seeds`).
inline constexpr int kMaxH264Seeds = 64;

// The H.264 sequence's name for noise seed `seed` (0: the sequence as it always was; k > 0: "_seedk").
std::string h264_sequence_name(int seed);

// `only` (when not empty) keeps the sequences whose name contains it; `trackers` run in turn;
// `h264_kbps` is the bit rate the H.264 sequence is encoded at. The H.264 sequence's one random
// input is its sensor noise (the path and the scene are fixed): `h264_seeds` (1-kMaxH264Seeds) runs
// it with that many noise seeds, each its own sequence (h264_sequence_name), pooled in h264_seed_bins.
SequenceBenchResult run_sequence_bench(const planar::PlanarConfig& config, const VisionThresholds& vision,
                                       const std::string& only = "",
                                       const std::vector<planar::TrackerKind>& trackers = {planar::TrackerKind::InverseCompositional,
                                                                                   planar::TrackerKind::Ecc},
                                       int h264_kbps = kDefaultH264Kbps, int h264_seeds = 1);

}  // namespace labo::bench
