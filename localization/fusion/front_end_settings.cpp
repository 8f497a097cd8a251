#include "localization/fusion/front_end_settings.hpp"

#include "localization/slam/slam_config.hpp"

namespace labo::fusion {

FrontEndSettings read_front_end_settings(const ConfigReader& root, const std::filesystem::path& base_dir) {
  FrontEndSettings s;
  if (root.has("planar")) s.planar = planar::read_planar_config(root.object("planar"));
  if (root.has("slam")) s.slam = slam::read_slam_settings(root.object("slam"));
  if (root.has("face")) s.face = face::read_face_config(root.object("face"), base_dir);
  return s;
}

}  // namespace labo::fusion
