#include "server/app_config.hpp"

#include "localization/slam/slam_config.hpp"
#include "core/source_tree.hpp"

namespace labo::server {

using ardrone2::ArdroneEmulatorSettings;
using ardrone2::ArdroneLinkSettings;
using ardrone2::read_ardrone_emulator_settings;
using ardrone2::read_ardrone_link_settings;
using lab::load_lab_description;
using tello::read_tello_config_of;

using sim::SimConfig;
using sim::read_sim_config;


namespace {
std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  std::filesystem::path path(p);
  return path.is_absolute() ? path : (base / path).lexically_normal();
}
}  // namespace

std::filesystem::path default_config_path() { return labo::source_root() / "config" / "default.json"; }

AppConfig read_app_config(const ConfigReader& root, const std::filesystem::path& base_dir) {
  AppConfig c;
  const std::string level = root.choice_or("log_level", "info", {"debug", "info", "warn", "error", "off"});
  c.log_level = parse_log_level(level);
  c.cameras = read_cameras_config_or_stock(root);
  c.control = root.has("control") ? control::read_control_config(root.object("control")) : control::ControlConfig{};
  c.vision = root.has("vision") ? read_vision_thresholds(root.object("vision")) : VisionThresholds{};
  c.estimation = root.has("estimation") ? estimation::read_estimation_config(root.object("estimation")) : estimation::EstimatorConfig{};
  c.face = root.has("face") ? face::read_face_config(root.object("face"), base_dir) : face::default_face_config();
  c.server = root.has("server") ? read_server_settings(root.object("server"), base_dir) : default_server_settings(base_dir);
  c.link = root.has("link") ? read_ardrone_link_settings(root.object("link")) : ArdroneLinkSettings{};
  c.emulator = root.has("emulator") ? read_ardrone_emulator_settings(root.object("emulator")) : ArdroneEmulatorSettings{};
  c.tello = read_tello_config_of(root);
  c.tello_estimation = root.has("tello") && root.object("tello").has("estimation")
                           ? estimation::read_estimation_config(root.object("tello").object("estimation"), c.estimation)
                           : c.estimation;
  c.planar = root.has("planar") ? planar::read_planar_config(root.object("planar")) : planar::PlanarConfig{};
  c.slam = root.has("slam") ? slam::read_slam_settings(root.object("slam")) : slam::SlamSettings{};
  c.lab_file = resolve(base_dir, root.string_or("lab", "lab.json"));
  c.sim = root.has("sim") ? read_sim_config(root.object("sim")) : SimConfig{};
  c.sim.link.video_bitrate_kbps = c.link.video_max_bitrate_kbps;  // the simulated drone streams at what the driver sets
  c.server.people = {c.face, c.cameras.front};
  root.finish();
  // The lab is read last, so a misspelt key of this file is reported before a problem in the lab's.
  if (!std::filesystem::is_regular_file(c.lab_file))
    root.fail("lab", "no lab description at " + c.lab_file.string() + " (expected a file like config/lab.json)");
  c.lab = load_lab_description(c.lab_file);
  return c;
}

AppConfig load_app_config(const std::filesystem::path& file) {
  const ConfigDocument doc = ConfigDocument::load(file);
  AppConfig c = read_app_config(doc.root(), file.parent_path());
  c.source = file;
  return c;
}

}  // namespace labo::server
