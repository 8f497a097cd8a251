#include "control/experiments/lockstep_flight.hpp"

#include "core/frames.hpp"

namespace labo {

namespace {
constexpr int kPhysicsSubsteps = 5;
}

Eigen::Vector4d xyz_yaw(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d p = T.translation();
  return {p.x(), p.y(), p.z(), ypr_from_rotation(T.linear())[0]};
}

LockstepFlight::LockstepFlight(const FlightStackSetup& setup, const PerceptionModelConfig& perception, unsigned seed)
    : lab_(setup.lab), perception_(perception, setup.lab, seed) {
  drone_.p = setup.lab.base;
  drone_.yaw = setup.lab.base_yaw_rad;
  auto pipelines = std::make_unique<LabPipelines>(setup.lab, setup.estimation, setup.vision);
  pipelines_ = pipelines.get();
  stack_ = std::make_unique<FlightStack>(setup, std::move(pipelines));
  samples_.reserve(20000);
}

Eigen::Isometry3d LockstepFlight::true_T_cam(const Eigen::Isometry3d& T_world_target) const {
  return (drone_.pose() * T_body_cam_front()).inverse() * T_world_target;
}

void LockstepFlight::tick() {
  stack_->on_navdata(perception_.navdata(drone_, t_));
  perception_.observe(drone_, T_world_face_, t_, *pipelines_);
  stack_->set_ground_truth(drone_.pose(), t_);
  const FlightOutput out = stack_->tick(t_);
  switch (out.action) {
    case FlightOutput::Action::Move: drone_.move(out.move); break;
    case FlightOutput::Action::Hover: drone_.hover(); break;
    case FlightOutput::Action::Takeoff: drone_.takeoff(); break;
    case FlightOutput::Action::Land: drone_.land(); break;
    case FlightOutput::Action::Emergency: drone_.emergency(); break;
    case FlightOutput::Action::None: break;
  }
  const FlightStatus s = stack_->status();
  FlightSample sample;
  sample.t = t_;
  sample.estimated = xyz_yaw(s.pose.T_world_body);
  sample.truth = xyz_yaw(drone_.pose());
  sample.desired = s.desired;
  sample.source = s.source;
  sample.stage_index = s.stage_index;
  sample.stage = s.stage;
  samples_.push_back(std::move(sample));
  for (int i = 0; i < kPhysicsSubsteps; ++i) drone_.step(kControlDt / kPhysicsSubsteps);
  t_ += kControlDt;
}

void LockstepFlight::run(double seconds) {
  const Seconds end = t_ + seconds - 1e-9;
  while (t_ < end) tick();
}

bool LockstepFlight::run_until(const std::function<bool()>& done, double timeout_s) {
  const Seconds end = t_ + timeout_s;
  while (t_ < end) {
    tick();
    if (done()) return true;
  }
  return false;
}

}  // namespace labo
