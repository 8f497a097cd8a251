#include "bench/experiments/lockstep_flight.hpp"

#include <algorithm>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
constexpr int kPhysicsSubsteps = 5;
}

LockstepFlight::LockstepFlight(const control::FlightStackSetup& setup, const PerceptionModelConfig& perception, unsigned seed)
    : lab_(setup.lab), true_lab_{setup.lab, setup.cameras.front, T_body_cam_front()}, perception_(perception, setup.lab, seed) {
  drone_.p = setup.lab.base;
  drone_.yaw = setup.lab.base_yaw_rad;
  auto pipelines = std::make_unique<fusion::LabPipelines>(setup.lab, setup.estimation, setup.vision);
  pipelines_ = pipelines.get();
  stack_ = std::make_unique<control::FlightStack>(setup, std::move(pipelines));
  samples_.reserve(20000);
  // The teacher stands 2.5 m out, looking at the base (z into the face, control's convention).
  T_world_face_.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T_world_face_.translation() = Eigen::Vector3d(2.5, -0.5, 1.6);
}

void LockstepFlight::walk_teacher() {
  constexpr double kSpeed = 0.5, kAccel = 0.5, kTurnY = 1.0;
  double& y = T_world_face_.translation().y();
  const double stopping = walk_speed_ * walk_speed_ / (2 * kAccel);
  if (walk_direction_ * y + stopping >= kTurnY) walk_speed_ -= kAccel * kControlDt;
  else walk_speed_ = std::min(kSpeed, walk_speed_ + kAccel * kControlDt);
  if (walk_speed_ <= 0) {
    walk_speed_ = 0;
    walk_direction_ = -walk_direction_;
  }
  y += walk_direction_ * walk_speed_ * kControlDt;
}

std::optional<Eigen::Isometry3d> LockstepFlight::true_face() const { return T_world_face_ * fusion::flip_about_y(); }

void LockstepFlight::tick() {
  if (walking_) walk_teacher();
  TickRecord record;
  record.navdata = perception_.navdata(drone_, t_);
  record.focus = pipelines_->focus();
  record.frame = perception_.observe(drone_, T_world_face_, t_, record.focus);
  record.truth = drone_.pose();
  stack_->on_navdata(record.navdata);
  record.frame.deliver_to(*pipelines_);
  stack_->set_ground_truth(drone_.pose(), t_);
  const control::FlightOutput out = stack_->tick(t_);
  if (recording_) {
    if (out.action == control::FlightOutput::Action::Move) record.command = out.move;
    else if (out.action == control::FlightOutput::Action::Hover) record.command = MoveCommand{};
    records_.push_back(std::move(record));
  }
  switch (out.action) {
    case control::FlightOutput::Action::Move: drone_.move(out.move); break;
    case control::FlightOutput::Action::Hover: drone_.hover(); break;
    case control::FlightOutput::Action::Takeoff: drone_.takeoff(); break;
    case control::FlightOutput::Action::Land: drone_.land(); break;
    case control::FlightOutput::Action::Emergency: drone_.emergency(); break;
    case control::FlightOutput::Action::None: break;
  }
  samples_.push_back(sample_of(stack_->status(), out, pipelines_->estimator(), drone_.pose(), t_, true_face()));
  for (int i = 0; i < kPhysicsSubsteps; ++i) drone_.step(kControlDt / kPhysicsSubsteps);
  t_ += kControlDt;
}

}  // namespace labo::bench
