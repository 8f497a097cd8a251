#pragma once
// The "face" section of config/default.json: model files, pose method, detector schedule and the
// limits beyond which a pose is refused rather than handed to the filter.
#include <filesystem>
#include <string>
#include <vector>

#include "core/config_reader.hpp"
#include "localization/face/depth_refinement.hpp"
#include "localization/face/face_detector.hpp"
#include "localization/face/face_pose_solver.hpp"
#include "localization/face/face_shape_fitter.hpp"

namespace labo::face {

struct FaceLimits {
  double max_rms_per_interocular = 0.12;  // RMS landmark fit error / interocular distance (px/px)
  double max_yaw_rad = 1.22;              // 70°: beyond it the detector and landmarks are unreliable
  double max_pitch_rad = 0.87;            // 50°
  // A new track starts only on a face turned less than this. Off (90°) by default: at 30° a turned
  // face's first pose no longer biases the track, but find-teacher then seldom picks up a teacher
  // walking past the drone, whose face it sees turned (docs/face.md "A track starts only on a face
  // turned less than 30°"; test "face: a track starts only on a face turned less than max_start_yaw,
  // then follows it further").
  double max_start_yaw_rad = 1.5708;
  double min_distance_m = 0.2;
  double max_distance_m = 6.0;
  double border_margin_px = 1.0;          // landmarks closer to the border than this: face cut
  double min_interocular_px = 8.0;        // smaller faces give no usable pose
  // Between consecutive tracked frames (30 fps): larger changes mean the landmarks slid off the face.
  double max_jump_m = 0.15;
  double max_turn_rad = 0.44;             // 25°
  double max_scale_change = 0.25;         // of the landmarks' spread
  int max_detector_misses = 1;            // consecutive re-detections that miss before the face is lost
};

struct FaceConfig {
  std::filesystem::path shape_predictor;  // dlib 68-point model
  std::filesystem::path model;            // CANDIDE-3 .wfm
  std::filesystem::path mapping;          // iBUG-68 -> CANDIDE-3 csv
  std::filesystem::path people_dir;       // per-person fitted shapes (<name>.json)
  std::string teacher;                    // registered person followed when several faces show; "" none
  double interpupillary_distance_m = 0.063;  // default for an unregistered face
  FacePoseSolverOptions solver;
  FaceDetectorOptions detector;
  // Box for the landmarks while tracking: "landmarks" (from the previous frame's landmarks, detector
  // every `redetect_every_n_frames`) or "detector" (the detector around the last face every frame).
  bool box_from_landmarks = true;
  int redetect_every_n_frames = 10;
  // Turn the landmarks' crop upright by the last eye line's angle (the predictor was trained on
  // upright faces; rolled heads bias its landmarks).
  bool upright_crop = true;
  // Widen the crop by (1 / cos(last yaw))^yaw_widen_exponent, at most 1.6 (0: never).
  double yaw_widen_exponent = 0.0;
  // Landmarks on the side turned away get the weight 1 / (1 + (lateral / 5 cm) (yaw / this)^2) in
  // the pose refinement, from the last pose's yaw (0: equal weights).
  double far_side_yaw_rad = 0.0;
  // Weigh each landmark by its group's reliability in the pose refinement (landmark_weights.hpp).
  bool landmark_noise_weights = false;
  // While tracking, run the predictor on a frontal view of the face made through the person's
  // CANDIDE-3 mesh at the last pose (frontal_view.hpp) instead of the upright crop.
  bool frontal_view = false;
  // A track's first frame (no earlier pose): views made, landmarks found and the pose refitted up to
  // this many times, each view at the last pass's pose, until the pose moves less than 2 mm and 0.2°
  // (1: one view at the crop's pose).
  int start_view_passes = 1;
  // In those views, the far side of a face turned beyond this (fully 15° further) is replaced by the
  // near side's mirror image, and its landmarks carry no weight in the pose (0: off). At a large yaw
  // the far side is seen obliquely, stretched from few pixels and partly hidden by the nose, and the
  // predictor's landmarks on it bias the first pose (docs/face.md, "The start of a turned face").
  double start_mirror_yaw_rad = 0.0;
  // Registration keeps where the picture's landmarks lie on the fitted mesh (surface_landmarks.hpp).
  bool surface_landmarks = false;
  // Between posed faces the head is followed (head_tracker.hpp) and reported as the face's place only.
  // Its distance, read from the head patch's scale, drifts; face-follow takes it from the face's
  // height instead where it can (control/head_range.hpp, docs/control.md).
  bool head_tracking = true;
  // A tracked frame whose landmarks do not fit is made again as a track's first frame (iterated,
  // mirrored views). Off: in flight it keeps a face turned 35-50° on more frames, but neither the
  // face-follow campaign nor the face benchmark gained (docs/face.md, Design choices).
  bool restart_unfit_tracked_frames = false;
  std::vector<double> lost_search_scales{0.5, 1.0, 2.0};  // cycled over frames while lost
  ShapeFitOptions shape_fit;
  double frontal_max_angle_rad = 0.26;    // a registration picture must be within 15° of frontal
  // A portrait (registration picture, head texture) whose eye centres are closer than this is refused:
  // its shape would come from a few pixels per landmark.
  double portrait_min_interocular_px = 20;
  // The landmarks' depth refined from frames of the head turning (`face register --turns`).
  DepthRefinementOptions depth_refinement;
  FaceLimits limits;
};

// Every key optional; relative paths resolve against `base_dir` (the config file's folder).
FaceConfig read_face_config(const ConfigReader& node, const std::filesystem::path& base_dir);
FaceConfig default_face_config();

}  // namespace labo::face
