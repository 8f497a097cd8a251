#include "drone/sim/ground_truth_log.hpp"

#include <iomanip>
#include <stdexcept>

#include "core/frames.hpp"

namespace labo::sim {

using lab::LabDescription;


namespace {

void write_pose(std::ostream& out, const Eigen::Isometry3d& T) {
  const Eigen::Vector3d ypr = ypr_from_rotation(T.linear());
  const Eigen::Vector3d& p = T.translation();
  out << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << ypr[0] << ',' << ypr[1] << ',' << ypr[2];
}

std::ofstream open(const std::filesystem::path& file) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write the ground truth file " + file.string());
  out << std::setprecision(9);
  return out;
}

}  // namespace

GroundTruthLog::GroundTruthLog(const std::filesystem::path& file, const LabDescription& lab)
    : out_(open(file)),
      objects_file_(file.parent_path() / (file.stem().string() + "_objects.csv")) {
  out_ << "t_s,x_m,y_m,z_m,yaw_rad,pitch_rad,roll_rad,vx_mps,vy_mps,vz_mps,phase,battery_percent,"
          "teacher_present,teacher_x_m,teacher_y_m,head_x_m,head_y_m,head_z_m,head_yaw_rad,head_pitch_rad,head_roll_rad,"
          "crash\n";
  std::ofstream objects = open(objects_file_);
  objects << "kind,id,x_m,y_m,z_m,yaw_rad,pitch_rad,roll_rad,width_m,height_m,depth_m\n";
  for (const auto& i : lab.instruments) {
    objects << "instrument," << i.id;
    write_pose(objects, i.T_world_object);
    objects << ',' << i.width_m << ',' << i.height_m << ',' << i.depth_m << '\n';
  }
  objects << "platform," << lab.platform.id;
  write_pose(objects, lab.platform.T_world_object);
  objects << ',' << lab.platform.width_m << ',' << lab.platform.height_m << ',' << lab.platform.thickness_m << '\n';
  for (const auto& b : lab.benches) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = b.box.centre();
    objects << "bench," << b.id;
    write_pose(objects, T);
    objects << ',' << b.box.size().x() << ',' << b.box.size().y() << ',' << b.box.size().z() << '\n';
  }
  if (!objects) throw std::runtime_error("cannot write the ground truth file " + objects_file_.string());
}

void GroundTruthLog::record(const QuadrotorState& d, const SceneState& scene) {
  out_ << d.t;
  write_pose(out_, d.T_world_body());
  out_ << ',' << d.velocity_mps.x() << ',' << d.velocity_mps.y() << ',' << d.velocity_mps.z() << ',' << to_string(d.phase)
       << ',' << d.battery_percent << ',' << (scene.teacher_present ? 1 : 0) << ',' << scene.teacher_floor_xy.x() << ','
       << scene.teacher_floor_xy.y();
  write_pose(out_, scene.T_world_head);
  out_ << ',' << d.crash_reason << '\n';
  ++rows_;
}

}  // namespace labo::sim
