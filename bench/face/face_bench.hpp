#pragma once
// The face benchmark behind `labodrone-bench bench face`: head-pose sequences rendered with the textured
// CANDIDE-3 head, degraded (noise, blur, lossy video), run through the whole pipeline once per frame;
// each PnP method of Table 1 then solves the same landmarks, against the known pose.
#include <filesystem>
#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/camera_config.hpp"
#include "core/camera_model.hpp"
#include "localization/face/face_config.hpp"
#include "localization/face/face_pose_solver.hpp"

namespace labo::bench {

struct FaceBenchOptions {
  int sequences = 10;
  int frames = 300;
  unsigned seed = 1;
  std::filesystem::path texture;  // photograph with one face (assets/astronaut.png)
  cv::Mat texture_bgr;            // the photograph itself, when set (then `texture` only names it)
  double interpupillary_distance_m = 0.063;
  bool lossy_video = true;        // H.264 round trip through the link's codec
  int video_bitrate_kbps = 1000;  // the AR.Drone 2.0's default video:max_bitrate
  // The teacher is registered from this many consecutive frames of the still, frontal head at 0.8 m
  // (each with its own noise and the video's loss; landmarks averaged, person_registration.hpp).
  int registration_frames = 8;
  bool true_shape = false;          // use the rendered head's shape instead of the registered one
  // After the frontal picture, this many frames of the head turning left, right (± turn_yaw_deg),
  // up and down (± turn_pitch_deg) at 0.8 m refine the landmarks' depth (person_registration.hpp:
  // refine_person_from_turns). 0: off.
  int turn_frames = 0;
  double turn_yaw_deg = 25, turn_pitch_deg = 15;
  std::filesystem::path sample_dir;  // when set, a few rendered frames are written there
  // Sequences drawn by the simulated lab's LabRenderer (drone/sim/lab_renderer.hpp: the room, the
  // teacher's body, neck and hair around the same textured CANDIDE-3 face), after the `sequences`
  // drawn by TexturedHeadRenderer over a random background. 0, or no lab file: none.
  int lab_sequences = 4;
  std::filesystem::path lab;  // lab description (config/lab.json)
  CamerasConfig cameras;      // the lab renderer's cameras (front: the benchmark's camera)
  std::filesystem::path frames_csv;  // when set, per-frame truth and LM-tracking errors (analysis)
  // When set, only the sequence of that name runs (the others are drawn but neither rendered nor
  // tracked; each sequence starts a new track, so its figures are those it has in the whole run).
  std::string only_sequence;
};

struct MethodErrors {
  face::PnpMethod method = face::PnpMethod::LmTracking;
  int frames = 0;                                 // frames with a pose
  // Relative motion (the UPNA protocol): each pose taken relative to the sequence's first tracked
  // frame, for the estimate and the truth alike, so constant offsets of the face origin cancel.
  double tx_mm = 0, ty_mm = 0, tz_mm = 0;         // mean absolute errors
  double roll_deg = 0, yaw_deg = 0, pitch_deg = 0;
  double time_ms = 0;                             // mean pose time
  int failures = 0;                               // frames with landmarks but no pose
  double abs_tx_mm = 0, abs_ty_mm = 0, abs_tz_mm = 0;  // absolute translation errors
};

struct SequenceSummary {
  std::string name;
  std::string renderer;  // "head" (TexturedHeadRenderer) or "lab" (LabRenderer)
  double distance_m = 0;
  double detection_rate = 0;  // frames tracked / frames
  double yaw_err_deg = 0, tz_err_mm = 0;  // LM tracking, mean absolute
};

struct FaceBenchReport {
  int frames_total = 0;
  int frames_tracked = 0;
  std::vector<MethodErrors> methods;  // Table 1's order
  std::vector<std::pair<std::string, MethodErrors>> lm_by_renderer;  // LM tracking per renderer
  std::vector<SequenceSummary> sequences;
  // Whole pipeline (detection + landmarks + LM-tracking pose), per frame: median, mean, 95th pct.
  double frame_ms_median = 0, frame_ms_mean = 0, frame_ms_p95 = 0;
  double tracking_frame_ms_median = 0;  // frames where the detector did not run
  double detect_ms_median = 0, landmarks_ms_median = 0, pose_ms_median = 0;
  int registration_frames = 0;            // frontal frames the teacher was registered from
  double shape_fit_rms_px = 0;            // registration picture
  double shape_param_error_rms = 0;       // fitted vs the rendered head's τs, observable units
  int turn_views = 0;                     // turn frames used (0: no turn refinement)
  double turn_rms_before_px = 0, turn_rms_after_px = 0;
  std::string turn_refused;               // the refinement's refusal ("" when accepted or not asked)
  // Evaluation only (the refinement never sees it): RMS over the rigid landmarks of the registered
  // points' depth against the rendered head's true landmarks, each set's mean removed, before and
  // after the head-turn refinement; and the same without the part linear in x and y (a tilt of the
  // face frame, which no refinement of the shape alone can tell).
  double depth_error_mm = 0, depth_error_turned_mm = 0;
  double depth_error_untilted_mm = 0, depth_error_untilted_turned_mm = 0;
  std::vector<std::pair<std::string, int>> lost_reasons;
  // LM tracking's errors per posed frame, as MethodErrors accumulates them: |tx|, |ty|, |tz| mm
  // (relative motion), |roll|, |yaw|, |pitch| degrees (medians, figures pooled over several faces).
  std::vector<std::array<double, 6>> lm_frame_errors;
  // Whole pipeline CPU time per frame, ms.
  std::vector<double> frame_ms;
};

// Throws std::runtime_error when the texture has no single face or the registration fails.
FaceBenchReport run_face_bench(const face::FaceConfig& config, const PinholeCamera& camera, const FaceBenchOptions& options,
                               const std::function<void(const std::string&)>& progress = {});

}  // namespace labo::bench
