#pragma once
// The lab the lockstep experiments and control tests fly in until the sim's LabDescription
// (config/lab.json) is wired in: a 6 m x 6 m x 2.6 m room, the base and platform at the origin, an
// oscilloscope panel 3.5 m ahead facing the base at 1.0 m height.
#include "localization/fusion/lab_geometry.hpp"

namespace labo::bench {

// A pose whose z axis points along +x (away from a viewer at the base), x = -world y, y down.
Eigen::Isometry3d facing_base(const Eigen::Vector3d& at);
fusion::LabGeometry model_lab();

}  // namespace labo::bench
