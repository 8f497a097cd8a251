#include "localization/face/face_commands.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <vector>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/camera_config.hpp"
#include "core/config_reader.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/person_registration.hpp"
#include "core/source_tree.hpp"

namespace labo {

FaceSetup load_face_setup(const ParsedArgs& args) {
  const std::filesystem::path file =
      args.value_or("--config", (labo::source_root() / "config" / "default.json").string());
  const ConfigDocument doc = ConfigDocument::load(file);
  const ConfigReader root = doc.root();
  const CamerasConfig cameras = read_cameras_config_or_stock(root);
  face::FaceConfig face = root.has("face") ? face::read_face_config(root.object("face"), file.parent_path())
                                           : face::default_face_config();
  return {face, PinholeCamera(cameras.front), cameras};
}

const CommandSpec& face_register_command_spec() {
  static const CommandSpec spec{
      "face register",
      "IMAGE...",
      "Fit a person's CANDIDE-3 shape from frontal pictures taken with the front camera (one, or several consecutive "
      "frames of the still head: their landmarks are averaged) and store it.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--name", "NAME", "person's name (A-Z a-z 0-9 _ -), required"},
       {"--ipd-mm", "MM", "interpupillary distance in mm (default: face.interpupillary_distance_mm)"},
       {"--turns", "DIR", "pictures (PNG/JPEG, in name order) of the person slowly turning their head left, right, "
                          "up and down: refine the landmarks' depth from them"},
       {"--out", "FILE", "where to write (default: <face.people_dir>/<NAME>.json)"}},
      1,
      100};
  return spec;
}

namespace {

// The --turns folder's pictures in name order (a recording's frames keep their order that way), each
// checked to be the front camera's size. None when the option is absent.
std::vector<cv::Mat> read_turn_pictures(const std::optional<std::string>& dir, const PinholeCamera& camera) {
  std::vector<cv::Mat> frames;
  if (!dir) return frames;
  if (!std::filesystem::is_directory(*dir)) throw UsageError("--turns " + *dir + ": not a folder");
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(*dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw UsageError("--turns " + *dir + ": no PNG or JPEG pictures in it");
  for (const auto& f : files) {
    cv::Mat gray = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) throw UsageError(f.string() + ": cannot read the picture");
    if (gray.cols != camera.width() || gray.rows != camera.height()) {
      throw UsageError(f.string() + ": picture is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) +
                       ", expected the front camera's " + std::to_string(camera.width()) + "x" +
                       std::to_string(camera.height()));
    }
    frames.push_back(std::move(gray));
  }
  return frames;
}

}  // namespace

int run_face_register_command(const ParsedArgs& args) {
  const FaceSetup setup = load_face_setup(args);
  const auto name = args.value("--name");
  if (!name) throw UsageError("--name NAME is required");
  const double ipd_m = args.number_or("--ipd-mm", setup.face.interpupillary_distance_m * 1000.0, 40, 90) / 1000.0;
  std::vector<cv::Mat> images;
  for (const std::string& path : args.positionals) {
    cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw UsageError(path + ": cannot read the picture");
    if (image.cols != setup.camera.width() || image.rows != setup.camera.height()) {
      throw UsageError(path + ": picture is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                       ", expected the front camera's " + std::to_string(setup.camera.width()) + "x" +
                       std::to_string(setup.camera.height()));
    }
    images.push_back(std::move(image));
  }
  const std::vector<cv::Mat> turns = read_turn_pictures(args.value("--turns"), setup.camera);
  face::FacePoseEstimator estimator(setup.face, setup.camera);
  try {
    face::PersonShape person = face::register_person(estimator, images, *name, ipd_m);
    if (!turns.empty()) {
      const face::TurnRefinement refined = face::refine_person_from_turns(estimator, person, turns);
      person = refined.person;
      std::cout << "head turn: " << refined.views << " of " << turns.size() << " pictures tracked (yaw span "
                << refined.yaw_span_deg << "°, pitch span " << refined.pitch_span_deg << "°), landmark fit "
                << refined.rms_before_px << " -> " << refined.rms_after_px << " px\n";
    }
    const auto out = args.value_or("--out", face::person_shape_path(setup.face.people_dir, *name).string());
    face::save_person_shape(person, out);
    std::cout << "registered " << *name << ": fit RMS " << person.fit_rms_px << " px -> " << out << "\n";
  } catch (const face::RegistrationError& e) {
    std::cerr << "labodrone face register: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace labo
