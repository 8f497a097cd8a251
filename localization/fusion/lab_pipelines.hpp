#pragma once
// The lab's localization pipelines behind FlightStack: the StateEstimator (localization/estimation/)
// fed with navdata, the commands sent, and the vision results of the source LocalizationSwitch chose
// (SLAM far, the instrument's or platform's homography near, the face in face-follow).
//
// Vision results come in stamped with their frame time: from the vision front-ends
// (vision_front_end.hpp) on each frame, as the current focus selects - SLAM on front frames, the
// focused instrument's panel in the front camera, the platform in the bottom camera, the face in
// face-follow - or through add_*_result() from a perception model in the lockstep experiments.
// on_video() runs the front-ends inline; prepare_vision() / run_vision_job() / apply_vision() let a
// real-time runtime run them on a worker thread (vision_job.hpp). make_lab_pipelines()
// (lab_pipelines_factory.hpp) attaches the real front-ends.
// Convention: every TargetObservation's T_cam_target has z pointing into the target (away from a viewer
// in front of it), for panels and faces alike; faces are converted at this edge.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "localization/fusion/attitude_history.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/localization_pipelines.hpp"
#include "localization/fusion/slam_points_top_down.hpp"
#include "localization/fusion/vision_front_end.hpp"
#include "localization/fusion/vision_job.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo::fusion {

class FaceFrontEnd;

class LabPipelines final : public LocalizationPipelines {
 public:
  LabPipelines(LabGeometry lab, const estimation::EstimatorConfig& config, const VisionThresholds& thresholds);

  // Front-ends run by on_video(); without one, that kind of result only comes through add_*_result().
  // Throws std::invalid_argument for an instrument id the lab does not have.
  void set_instrument_front_end(const std::string& id, std::unique_ptr<TargetFrontEnd> front_end);
  void set_platform_front_end(std::unique_ptr<TargetFrontEnd> front_end) { platform_fe_ = std::move(front_end); }
  void set_face_front_end(std::unique_ptr<TargetFrontEnd> front_end);
  void set_slam_front_end(std::unique_ptr<SlamFrontEnd> front_end) { slam_fe_ = std::move(front_end); }
  // How add_instrument() makes an instrument's front-end (make_lab_pipelines sets it; unset: an added
  // instrument has none, its results only come through add_instrument_result()).
  using InstrumentFrontEndFactory = std::function<std::unique_ptr<TargetFrontEnd>(const PlanarTarget&)>;
  void set_instrument_front_end_factory(InstrumentFrontEndFactory factory) { make_instrument_fe_ = std::move(factory); }
  // Throws std::invalid_argument for an id the lab has already, or what the factory throws (a
  // template that cannot be used).
  bool add_instrument(const PlanarTarget& instrument) override;

  // Vision results (frame-stamped). The estimator is corrected only by the chosen source.
  void add_instrument_result(const TargetObservation& obs);
  void add_platform_result(const TargetObservation& obs);
  void add_face_result(const TargetObservation& obs);
  void add_slam_result(const Eigen::Isometry3d& T_map_cam, const SlamSummary& summary, int map_id, Seconds t);

  void on_navdata(const NavdataSample& sample) override;
  void on_command(const MoveCommand& command, Seconds t) override;
  void on_video(const VideoFrame& frame) override;
  bool prepare_vision(const VideoFrame& frame, VisionJob& job) override;
  void apply_vision(const VisionResults& results) override;
  void set_focus(const PerceptionFocus& focus) override { focus_ = focus; }
  bool follow_person(const face::PersonShape& person) override;
  void reset(const Eigen::Isometry3d& T_world_body, Seconds t) override;
  void start_at_first_navdata(const Eigen::Isometry3d& T_world_body) override;
  void set_down_at_next_navdata(const Eigen::Isometry3d& T_world_body) override;

  PoseEstimate predict(Seconds t) const override;
  TargetObservation instrument() const override { return instrument_; }
  TargetObservation platform() const override { return platform_; }
  TargetObservation face() const override { return face_; }
  SlamSummary slam() const override;
  std::shared_ptr<const SlamPointsXy> slam_points() const override { return slam_points_.latest(); }

  const estimation::StateEstimator& estimator() const { return estimator_; }
  const PerceptionFocus& focus() const { return focus_; }

 private:
  int instrument_index(const std::string& id) const;
  // Camera to target, as the estimator predicts it for a frame at t; empty when the estimate is too
  // uncertain to choose a detector with.
  std::optional<double> expected_distance(const Eigen::Isometry3d& T_world_target, CameraId camera, Seconds t) const;
  // The estimator's camera pose at t in SLAM's current map, once the map is placed and its scale
  // estimated (the prior tum_ardrone gives PTAM); empty otherwise.
  std::optional<Eigen::Isometry3d> slam_prior(Seconds t) const;
  // The IMU's attitude at a front frame's capture time as gravity's direction in the front camera
  // (navdata and video delays from the estimator's configuration); empty without navdata around it.
  std::optional<Eigen::Vector3d> gravity_in_front_camera(Seconds frame_t) const;
  void prepare_front_camera(VisionJob& job);
  void prepare_bottom_camera(VisionJob& job);
  void apply_instrument(const std::string& id, const TargetObservation& obs);
  // A sample of SLAM's map, placed in the world once the estimator has placed that map.
  void apply_slam_points(const VisionResults& results);

  LabGeometry lab_;
  estimation::StateEstimator estimator_;
  PerceptionFocus focus_;
  TargetObservation instrument_, platform_, face_;
  SlamSummary slam_;
  int slam_map_id_ = -1;  // the map of the last SLAM result given to the estimator
  int slam_fe_map_id_ = SlamFrame{}.map_id;  // the map of the last SLAM result applied, good or not
  std::vector<std::unique_ptr<TargetFrontEnd>> instrument_fes_;  // parallel to lab_.instruments
  std::unique_ptr<TargetFrontEnd> platform_fe_, face_fe_;
  FaceFrontEnd* face_person_fe_ = nullptr;  // face_fe_ when it is the face pose estimator's
  std::unique_ptr<SlamFrontEnd> slam_fe_;
  InstrumentFrontEndFactory make_instrument_fe_;
  AttitudeHistory attitude_;  // navdata roll/pitch at their measurement times
  SlamPointsTopDown slam_points_;
  VisionJob job_;              // on_video's, reused
  VisionResults results_;
};

// Rotation by pi about y: between "z into the face" (control) and "z out of the face" (face/).
Eigen::Isometry3d flip_about_y();

}  // namespace labo::fusion
