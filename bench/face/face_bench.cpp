#include "bench/face/face_bench.hpp"

#include <algorithm>
#include <fstream>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "core/candide3.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "bench/face/frame_degrader.hpp"
#include "bench/face/head_pose_sequences.hpp"
#include "localization/face/person_registration.hpp"
#include "drone/lab/lab_description.hpp"
#include "core/cpu_time.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "localization/face/teacher_head.hpp"
#include "localization/face/textured_head_renderer.hpp"

namespace labo::bench {

using face::FaceConfig;
using face::FaceLandmarkModel;
using face::FacePoseEstimator;
using face::FacePoseSolver;
using face::FacePoseSolverOptions;
using face::FaceResult;
using face::HeadAngles;
using face::IdealPinhole;
using face::PersonShape;
using face::PnpMethod;
using face::PnpProblem;
using face::RegistrationError;
using face::TexturedHeadRenderer;
using face::TurnRefinement;
using face::head_angles;
using face::head_rotation;
using face::make_face_landmark_model;
using face::refine_lm;
using face::refine_person_from_turns;
using face::register_person;
using face::texture_head_from_photo;
using face::to_head_model;

using lab::LabDescription;
using lab::load_lab_description;

using lab::LabDescription;
using lab::load_lab_description;

using sim::LabRenderOptions;
using sim::LabRenderer;
using sim::SceneState;
using sim::TexturedHeadModel;


namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
constexpr std::array<PnpMethod, 5> kMethods{PnpMethod::Epnp, PnpMethod::RansacP3p, PnpMethod::EpnpLm,
                                            PnpMethod::RansacP3pLm, PnpMethod::LmTracking};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

// A lab-like background: smooth random shading with some mid-frequency texture.
cv::Mat make_background(const PinholeCamera& camera, unsigned seed) {
  cv::RNG rng(seed);
  cv::Mat coarse(9, 16, CV_32F), detail(45, 80, CV_32F), out;
  rng.fill(coarse, cv::RNG::UNIFORM, 70, 190);
  rng.fill(detail, cv::RNG::NORMAL, 0, 18);
  cv::Mat a, b;
  cv::resize(coarse, a, cv::Size(camera.width(), camera.height()), 0, 0, cv::INTER_CUBIC);
  cv::resize(detail, b, a.size(), 0, 0, cv::INTER_LINEAR);
  cv::Mat sum = a + b;
  sum.convertTo(out, CV_8U);
  return out;
}

FrameDegradation degradation_of(const FaceBenchOptions& o) { return {o.lossy_video, o.video_bitrate_kbps}; }

// The registration's head turn: at 0.8 m, yaw 0 -> +a -> -a -> 0 degrees over the first half,
// then pitch 0 -> +b -> -b -> 0 over the second, degraded like the frontal picture.
std::vector<cv::Mat> render_turn_frames(TexturedHeadRenderer& renderer, const PinholeCamera& camera,
                                        const FaceBenchOptions& options) {
  const double kYawDeg = options.turn_yaw_deg, kPitchDeg = options.turn_pitch_deg;
  const double rad = std::numbers::pi / 180.0;
  const cv::Mat background = make_background(camera, options.seed + 1000);
  FrameDegrader degrader(degradation_of(options), camera, options.seed + 1);
  std::vector<cv::Mat> frames;
  const int n = options.turn_frames;
  for (int i = 0; i < n; ++i) {
    const double s = static_cast<double>(i) / n;  // 0..1
    const double wave = std::sin(2 * std::numbers::pi * std::fmod(2 * s, 1.0));
    HeadAngles a;
    (s < 0.5 ? a.yaw : a.pitch) = wave * (s < 0.5 ? kYawDeg : kPitchDeg) * rad;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = head_rotation(a);
    T.translation() = Eigen::Vector3d(0, -0.02, 0.8);
    cv::Mat frame = background.clone();
    renderer.render(T, frame);
    degrader.apply(0.5, 2.0, frame);
    frames.push_back(std::move(frame));
  }
  return frames;
}

// The head in the simulated lab: LabRenderer draws the room, the teacher's body, neck and hair and
// the same textured face mesh. The front camera stands still, level, 2.2 m from the lab teacher's
// first waypoint towards the room's centre, looking at it; the head is placed at the sequence's
// T_cam_face, the body under it. The renderer's own noise and blur are off: every sequence gets the
// same degradations afterwards.
class LabHeadScene {
 public:
  LabHeadScene(const LabDescription& lab, const CamerasConfig& cameras, TexturedHeadModel head, unsigned seed)
      : renderer_(lab, cameras, std::move(head), seed, LabRenderOptions{0.0, 0.0, false, false}) {
    if (lab.teacher.waypoints.empty()) throw std::runtime_error(lab.source.string() + ": the teacher has no waypoint");
    const Eigen::Vector2d teacher = lab.teacher.waypoints.front();
    const Eigen::Vector2d centre = 0.5 * (lab.room.min.head<2>() + lab.room.max.head<2>());
    const Eigen::Vector2d away = (centre - teacher).normalized();
    const Eigen::Vector3d forward(-away.x(), -away.y(), 0), down(0, 0, -1);
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.linear().col(0) = down.cross(forward);
    T_world_cam.linear().col(1) = down;
    T_world_cam.linear().col(2) = forward;
    T_world_cam.translation() << teacher + 2.2 * away, lab.teacher.eye_height_m;
    T_world_cam_ = T_world_cam;
    scene_.T_world_body = T_world_cam * LabRenderer::T_body_cam(CameraId::Front).inverse();
  }
  void render(const Eigen::Isometry3d& T_cam_face, Seconds t, cv::Mat& gray) {
    scene_.t = t;
    scene_.T_world_head = T_world_cam_ * T_cam_face;
    scene_.teacher_floor_xy = scene_.T_world_head.translation().head<2>();
    renderer_.render(CameraId::Front, scene_, bgr_);
    cv::cvtColor(bgr_, gray, cv::COLOR_BGR2GRAY);
  }

 private:
  LabRenderer renderer_;
  Eigen::Isometry3d T_world_cam_;
  SceneState scene_;
  cv::Mat bgr_;
};

struct MethodAccumulator {
  std::vector<double> tx, ty, tz, roll, yaw, pitch, time, abs_tx, abs_ty, abs_tz;
  int failures = 0;

  // dt: relative-motion translation error, dt_abs: absolute (mm); angle errors in degrees.
  void add(const Eigen::Vector3d& dt, const Eigen::Vector3d& dt_abs, double roll_err, double yaw_err, double pitch_err,
           double ms) {
    tx.push_back(std::abs(dt.x()));
    ty.push_back(std::abs(dt.y()));
    tz.push_back(std::abs(dt.z()));
    abs_tx.push_back(std::abs(dt_abs.x()));
    abs_ty.push_back(std::abs(dt_abs.y()));
    abs_tz.push_back(std::abs(dt_abs.z()));
    roll.push_back(roll_err);
    yaw.push_back(yaw_err);
    pitch.push_back(pitch_err);
    time.push_back(ms);
  }
};

MethodErrors summarise(PnpMethod m, const MethodAccumulator& a) {
  return {m, static_cast<int>(a.tx.size()), mean(a.tx), mean(a.ty), mean(a.tz), mean(a.roll), mean(a.yaw), mean(a.pitch),
          mean(a.time), a.failures, mean(a.abs_tx), mean(a.abs_ty), mean(a.abs_tz)};
}

double angle_error_deg(double a, double b) { return std::abs(std::remainder(a - b, 2 * std::numbers::pi)) * kDeg; }

// RMS (mm) of the depth difference between `points` and `truth` (3 x n, face frame), the mean removed;
// with `untilted`, also the part linear in the points' x and y (least squares).
double depth_error_rms_mm(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& truth, bool untilted) {
  const Eigen::Index n = points.cols();
  Eigen::MatrixXd G(n, untilted ? 3 : 1);
  G.col(0).setOnes();
  if (untilted) {
    G.col(1) = points.row(0).transpose();
    G.col(2) = points.row(1).transpose();
  }
  const Eigen::VectorXd d = (points.row(2) - truth.row(2)).transpose();
  const Eigen::VectorXd r = d - G * G.colPivHouseholderQr().solve(d);
  return std::sqrt(r.squaredNorm() / static_cast<double>(n)) * 1000.0;
}

// The registered person's landmarks as the estimator uses them: the shape's mapped points plus the
// person's offsets (surface landmarks, head turn) when registration made any, in the person's frontal frame.
Eigen::Matrix3Xd person_points_of(const FacePoseEstimator& estimator) {
  const PersonShape& person = estimator.person();
  return person_landmarks_m(person, estimator.model().points_m(person.shape_params, person.interpupillary_distance_m));
}

std::string pose_columns(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  std::ostringstream out;
  out.precision(9);
  out << T.translation().x() << ',' << T.translation().y() << ',' << T.translation().z() << ',' << q.w() << ',' << q.x()
      << ',' << q.y() << ',' << q.z();
  return out.str();
}

// For offline analysis of the pose from the landmarks: the ideal camera, and per rigid landmark the
// person's registered point and the rendered head's true point (face frame, metres).
void write_model_csv(const std::string& path, const FacePoseEstimator& estimator, const Eigen::Matrix3Xd& person,
                     const Eigen::Matrix3Xd& truth) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write the model CSV");
  out.precision(9);
  const IdealPinhole c = estimator.ideal_camera();
  out << "landmark,person_x_m,person_y_m,person_z_m,true_x_m,true_y_m,true_z_m,fx,fy,cx,cy\n";
  for (Eigen::Index i = 0; i < person.cols(); ++i) {
    out << estimator.model().landmark_ids()[static_cast<std::size_t>(i)] << ',' << person(0, i) << ',' << person(1, i)
        << ',' << person(2, i) << ',' << truth(0, i) << ',' << truth(1, i) << ',' << truth(2, i) << ',' << c.fx << ','
        << c.fy << ',' << c.cx << ',' << c.cy << '\n';
  }
}

}  // namespace

FaceBenchReport run_face_bench(const FaceConfig& base_config, const PinholeCamera& camera,
                               const FaceBenchOptions& options, const std::function<void(const std::string&)>& progress) {
  const auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  FaceConfig config = base_config;
  config.solver.method = PnpMethod::LmTracking;
  config.teacher.clear();
  const Candide3Model candide = Candide3Model::load(config.model);
  FacePoseEstimator estimator(config, camera,
                              make_face_landmark_model(candide, load_ibug68_mapping(config.mapping)));

  const cv::Mat photo_bgr =
      options.texture_bgr.empty() ? cv::imread(options.texture.string(), cv::IMREAD_COLOR) : options.texture_bgr;
  if (photo_bgr.empty()) {
    throw std::runtime_error(options.texture.string() + ": cannot read the head texture (run scripts/setup.sh)");
  }
  cv::Mat photo;
  cv::cvtColor(photo_bgr, photo, cv::COLOR_BGR2GRAY);
  TexturedHeadRenderer renderer(candide, texture_head_from_photo(estimator, candide, photo, options.interpupillary_distance_m),
                                camera);
  FaceBenchReport report;

  // Registration: a frontal picture of the rendered head at 0.8 m.
  {
    cv::Mat frontal = make_background(camera, options.seed + 1000);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = head_rotation({});
    T.translation() = Eigen::Vector3d(0, -0.02, 0.8);
    renderer.render(T, frontal);
    // Consecutive frames of the still head: the first is the picture a one-picture registration uses
    // (same seed), the others the same video's next frames.
    const std::vector<cv::Mat> pictures =
        degraded_registration_pictures(frontal, options.registration_frames, degradation_of(options), camera, options.seed);
    frontal = pictures.front();
    const PersonShape teacher = register_person(estimator, pictures, "teacher", options.interpupillary_distance_m);
    PersonShape used = teacher;
    if (options.true_shape) {
      used.shape_params = renderer.head().shape_params;
      used.interpupillary_distance_m = options.interpupillary_distance_m * renderer.head().scale;
      used.R_frontal_model.setIdentity();  // the rendered head's own frame
    }
    estimator.set_person(used, true);
    report.shape_fit_rms_px = teacher.fit_rms_px;
    report.registration_frames = static_cast<int>(pictures.size());
    const Eigen::Matrix3Xd registered_points = person_points_of(estimator);
    if (options.turn_frames > 0) {
      try {
        const TurnRefinement turns =
            refine_person_from_turns(estimator, used, render_turn_frames(renderer, camera, options));
        report.turn_views = turns.views;
        report.turn_rms_before_px = turns.rms_before_px;
        report.turn_rms_after_px = turns.rms_after_px;
      } catch (const RegistrationError& e) {
        report.turn_refused = e.what();  // the registered shape stays as it was
        say(report.turn_refused);
      }
    }
    const FaceLandmarkModel& model = estimator.model();
    Eigen::Matrix3Xd truth(3, model.size());
    for (int i = 0; i < model.size(); ++i) {
      truth.col(i) = renderer.head().landmarks_face_m.col(model.landmark_ids()[static_cast<std::size_t>(i)]);
    }
    if (truth.allFinite()) {
      report.depth_error_mm = depth_error_rms_mm(registered_points, truth, false);
      report.depth_error_untilted_mm = depth_error_rms_mm(registered_points, truth, true);
      report.depth_error_turned_mm = depth_error_rms_mm(person_points_of(estimator), truth, false);
      report.depth_error_untilted_turned_mm = depth_error_rms_mm(person_points_of(estimator), truth, true);
    }
    const auto fitted = estimator.model().observable_units();
    double sum = 0;
    int n = 0;
    for (std::size_t u = 0; u < fitted.size(); ++u) {
      if (!fitted[u]) continue;
      const double e = teacher.shape_params(static_cast<Eigen::Index>(u)) -
                       renderer.head().shape_params(static_cast<Eigen::Index>(u));
      sum += e * e;
      ++n;
    }
    report.shape_param_error_rms = n ? std::sqrt(sum / n) : 0;
    if (!options.sample_dir.empty()) {
      std::filesystem::create_directories(options.sample_dir);
      cv::imwrite((options.sample_dir / "registration.png").string(), frontal);
    }
  }

  std::map<PnpMethod, MethodAccumulator> acc;
  std::map<std::string, MethodAccumulator> by_renderer;  // LM tracking
  std::vector<double> frame_ms, tracking_frame_ms, detect_ms, landmarks_ms, pose_ms;
  std::map<std::string, int> reasons;
  auto sequences = make_head_pose_sequences(options.sequences, options.frames, options.seed);
  std::optional<LabHeadScene> lab_scene;
  if (options.lab_sequences > 0 && !options.lab.empty()) {
    lab_scene.emplace(load_lab_description(options.lab), options.cameras,
                      to_head_model(candide, renderer.head(), photo_bgr), options.seed);
    for (auto& q : make_head_pose_sequences(options.lab_sequences, options.frames, options.seed + 101)) {
      q.name = "lab_" + q.name;
      sequences.push_back(std::move(q));
    }
  }
  if (!options.only_sequence.empty() &&
      std::none_of(sequences.begin(), sequences.end(), [&](const HeadPoseSequence& q) { return q.name == options.only_sequence; })) {
    throw std::runtime_error("face bench: no sequence named '" + options.only_sequence + "'");
  }
  std::ofstream csv, landmark_csv, pose_csv;
  if (!options.frames_csv.empty()) {
    csv.open(options.frames_csv);
    if (!csv) throw std::runtime_error(options.frames_csv.string() + ": cannot write the per-frame CSV");
    csv << "sequence,frame,guided,distance_m,true_yaw_deg,true_pitch_deg,true_roll_deg,true_z_m,interocular_px,"
           "rms_px,err_tx_mm,err_ty_mm,err_tz_mm,err_abs_tz_mm,err_roll_deg,err_yaw_deg,err_pitch_deg,"
           "model_only_abs_tz_mm,model_only_yaw_deg,model_only_pitch_deg,model_only_roll_deg,landmarks_only_abs_tz_mm,"
           "landmarks_only_yaw_deg,landmarks_only_pitch_deg,landmarks_only_roll_deg,lost_reason\n";
    landmark_csv.open(options.frames_csv.string() + ".landmarks.csv");
    landmark_csv << "sequence,frame,true_yaw_deg,true_pitch_deg,true_roll_deg,interocular_px,landmark,dx_px,dy_px,"
                    "true_u_px,true_v_px\n";
    pose_csv.open(options.frames_csv.string() + ".poses.csv");
    pose_csv << "sequence,frame,t_s,true_x_m,true_y_m,true_z_m,true_qw,true_qx,true_qy,true_qz,est_x_m,est_y_m,est_z_m,"
                "est_qw,est_qx,est_qy,est_qz\n";
  }
  // The rendered head's true landmarks, rigid subset (face frame, metres), for the analysis columns.
  const FaceLandmarkModel& lm_model = estimator.model();
  Eigen::Matrix3Xd true_landmarks(3, lm_model.size());
  for (int i = 0; i < lm_model.size(); ++i) {
    true_landmarks.col(i) = renderer.head().landmarks_face_m.col(lm_model.landmark_ids()[static_cast<std::size_t>(i)]);
  }
  const bool truth_known = true_landmarks.allFinite();
  const Eigen::Matrix3Xd person_points = person_points_of(estimator);
  if (csv.is_open()) write_model_csv(options.frames_csv.string() + ".model.csv", estimator, person_points, true_landmarks);
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    const HeadPoseSequence& seq = sequences[s];
    if (!options.only_sequence.empty() && seq.name != options.only_sequence) continue;
    const cv::Mat background = make_background(camera, options.seed + static_cast<unsigned>(s));
    FrameDegrader degrader(degradation_of(options), camera, options.seed * 7919u + static_cast<unsigned>(s));
    estimator.reset();
    std::vector<FacePoseSolver> solvers;
    for (PnpMethod m : kMethods) {
      FacePoseSolverOptions o = config.solver;
      o.method = m;
      solvers.emplace_back(o);
    }
    const bool in_lab = s >= static_cast<std::size_t>(options.sequences);
    SequenceSummary summary{seq.name, in_lab ? "lab" : "head", seq.distance_m, 0, 0, 0};
    std::vector<double> seq_yaw, seq_tz;
    std::vector<std::optional<Eigen::Isometry3d>> first_estimate(kMethods.size());
    std::optional<Eigen::Isometry3d> first_truth;
    int tracked = 0;
    cv::Mat frame;
    for (std::size_t f = 0; f < seq.T_cam_face.size(); ++f) {
      const Eigen::Isometry3d& truth = seq.T_cam_face[f];
      if (in_lab) {
        lab_scene->render(truth, static_cast<double>(f) / 30.0, frame);
      } else {
        background.copyTo(frame);
        renderer.render(truth, frame);
      }
      degrader.apply(seq.blur_sigma_px, seq.noise_sigma, frame);
      if (!options.sample_dir.empty() && (s < 2 || in_lab) && f % 75 == 0) {
        cv::imwrite((options.sample_dir / (seq.name + "_" + std::to_string(f) + ".png")).string(), frame);
      }
      const FaceResult r = estimator.process(frame, static_cast<double>(f) / 30.0);
      ++report.frames_total;
      frame_ms.push_back(r.timings.total_ms());
      detect_ms.push_back(r.timings.detect_ms);
      landmarks_ms.push_back(r.timings.landmarks_ms);
      pose_ms.push_back(r.timings.pose_ms);
      if (r.faces_found < 0 && r.tracking()) tracking_frame_ms.push_back(r.timings.total_ms());
      if (!r.tracking()) {
        ++reasons[std::string(to_string(r.reason))];
        if (csv.is_open()) {
          const HeadAngles ta = head_angles(truth.linear());
          csv << seq.name << ',' << f << ',' << seq.guided << ',' << seq.distance_m << ',' << ta.yaw * kDeg << ','
              << ta.pitch * kDeg << ',' << ta.roll * kDeg << ',' << truth.translation().z() << std::string(18, ',')
              << '"' << to_string(r.reason) << "\"\n";
        }
        for (auto& solver : solvers) solver.reset();
        continue;
      }
      ++tracked;
      // Every method solves the same landmarks against the same person's points as the estimator.
      const PnpProblem problem{person_points, estimator.ideal_pixels(r.landmarks), estimator.ideal_camera(),
                               r.landmark_weights};
      const double iod = (r.landmarks.middleCols(42, 6).rowwise().mean() - r.landmarks.middleCols(36, 6).rowwise().mean()).norm();
      const HeadAngles ta = head_angles(truth.linear());
      if (!first_truth) first_truth = truth;
      for (std::size_t m = 0; m < kMethods.size(); ++m) {
        const double start = process_cpu_seconds();
        const auto est = solvers[m].solve(problem, std::max(iod / 60.0, 0.5));
        const double ms = (process_cpu_seconds() - start) * 1000.0;
        MethodAccumulator& a = acc[kMethods[m]];
        if (!est) {
          ++a.failures;
          continue;
        }
        const Eigen::Isometry3d& T = est->solution.T_cam_face;
        if (!first_estimate[m]) first_estimate[m] = T;
        // Relative motion in the camera frame: where the face origin moved since the first frame.
        const Eigen::Vector3d moved_est = T.translation() - first_estimate[m]->translation();
        const Eigen::Vector3d moved_truth = truth.translation() - first_truth->translation();
        const Eigen::Vector3d dt = (moved_est - moved_truth) * 1000.0;
        const Eigen::Vector3d dt_abs = (T.translation() - truth.translation()) * 1000.0;
        const HeadAngles ea = head_angles(est->solution.T_cam_face.linear());
        a.add(dt, dt_abs, angle_error_deg(ea.roll, ta.roll), angle_error_deg(ea.yaw, ta.yaw),
              angle_error_deg(ea.pitch, ta.pitch), ms);
        if (kMethods[m] == PnpMethod::LmTracking) {
          by_renderer[summary.renderer].add(dt, dt_abs, a.roll.back(), a.yaw.back(), a.pitch.back(), ms);
          report.lm_frame_errors.push_back({a.tx.back(), a.ty.back(), a.tz.back(), a.roll.back(), a.yaw.back(), a.pitch.back()});
          seq_yaw.push_back(a.yaw.back());
          seq_tz.push_back(a.tz.back());
          if (csv.is_open()) {
            // Apart: the model's error (true landmark pixels, the estimator's model) and the
            // landmarks' error (detected pixels, the true 3-D landmarks).
            PnpProblem true_pixels = problem, true_model = problem;
            for (int i = 0; i < lm_model.size(); ++i) {
              true_pixels.pixels.col(i) = problem.camera.project(truth * true_landmarks.col(i).eval());
              if (truth_known) {
                const Eigen::Vector2d d = problem.pixels.col(i) - true_pixels.pixels.col(i);
                landmark_csv << seq.name << ',' << f << ',' << ta.yaw * kDeg << ',' << ta.pitch * kDeg << ','
                             << ta.roll * kDeg << ',' << iod << ',' << lm_model.landmark_ids()[static_cast<std::size_t>(i)]
                             << ',' << d.x() << ',' << d.y() << ',' << true_pixels.pixels(0, i) << ','
                             << true_pixels.pixels(1, i) << '\n';
              }
            }
            pose_csv << seq.name << ',' << f << ',' << static_cast<double>(f) / 30.0 << ',' << pose_columns(truth) << ','
                     << pose_columns(T) << '\n';
            true_model.points_face = true_landmarks;
            const auto write_errors = [&](const PnpProblem& p) {
              const auto r = truth_known ? refine_lm(p, truth, config.solver.lm) : std::nullopt;
              if (!r) {
                csv << ",nan,nan,nan,nan";
                return;
              }
              const HeadAngles ra = head_angles(r->T_cam_face.linear());
              csv << ',' << (r->T_cam_face.translation().z() - truth.translation().z()) * 1000 << ','
                  << std::remainder(ra.yaw - ta.yaw, 2 * std::numbers::pi) * kDeg << ','
                  << std::remainder(ra.pitch - ta.pitch, 2 * std::numbers::pi) * kDeg << ','
                  << std::remainder(ra.roll - ta.roll, 2 * std::numbers::pi) * kDeg;
            };
            csv << seq.name << ',' << f << ',' << seq.guided << ',' << seq.distance_m << ',' << ta.yaw * kDeg << ','
                << ta.pitch * kDeg << ',' << ta.roll * kDeg << ',' << truth.translation().z() << ',' << iod << ','
                << est->solution.rms_px << ',' << dt.x() << ',' << dt.y() << ',' << dt.z() << ',' << dt_abs.z() << ','
                << std::remainder(ea.roll - ta.roll, 2 * std::numbers::pi) * kDeg << ','
                << std::remainder(ea.yaw - ta.yaw, 2 * std::numbers::pi) * kDeg << ','
                << std::remainder(ea.pitch - ta.pitch, 2 * std::numbers::pi) * kDeg;
            write_errors(true_pixels);
            write_errors(true_model);
            csv << ",\n";
          }
        }
      }
    }
    report.frames_tracked += tracked;
    summary.detection_rate = static_cast<double>(tracked) / static_cast<double>(std::max<std::size_t>(1, seq.T_cam_face.size()));
    summary.yaw_err_deg = mean(seq_yaw);
    summary.tz_err_mm = mean(seq_tz);
    report.sequences.push_back(summary);
    say(seq.name + ": tracked " + std::to_string(tracked) + "/" + std::to_string(seq.T_cam_face.size()));
  }
  for (PnpMethod m : kMethods) report.methods.push_back(summarise(m, acc[m]));
  for (const auto& [name, a] : by_renderer) report.lm_by_renderer.emplace_back(name, summarise(PnpMethod::LmTracking, a));
  report.frame_ms = frame_ms;
  report.frame_ms_median = median(frame_ms);
  report.frame_ms_mean = mean(frame_ms);
  report.frame_ms_p95 = percentile(frame_ms, 0.95);
  report.tracking_frame_ms_median = median(tracking_frame_ms);
  report.detect_ms_median = median(detect_ms);
  report.landmarks_ms_median = median(landmarks_ms);
  report.pose_ms_median = median(pose_ms);
  report.lost_reasons.assign(reasons.begin(), reasons.end());
  return report;
}

}  // namespace labo::bench
