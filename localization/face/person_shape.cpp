#include "localization/face/person_shape.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "localization/face/face_geometry.hpp"

namespace labo::face {

namespace {
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// The registration refuses pictures turned beyond 15°; a stored pose beyond this is no registration's.
constexpr double kMaxFrontalPoseDeg = 30.0;
}  // namespace

Eigen::Matrix3Xd person_landmarks_m(const PersonShape& person, const Eigen::Matrix3Xd& points_m) {
  Eigen::Matrix3Xd points = points_m;
  if (person.landmark_offsets_m.cols() == points.cols()) points += person.landmark_offsets_m;
  return person.R_frontal_model * points;
}

void validate_person_name(const std::string& name) {
  const bool ok_chars = std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
  });
  if (name.empty() || name.size() > 64 || !ok_chars) {
    throw std::invalid_argument("person name '" + name + "': expected 1-64 characters of A-Z a-z 0-9 _ -");
  }
}

std::filesystem::path person_shape_path(const std::filesystem::path& people_dir, const std::string& name) {
  validate_person_name(name);
  return people_dir / (name + ".json");
}

void save_person_shape(const PersonShape& person, const std::filesystem::path& file) {
  validate_person_name(person.name);
  nlohmann::json j;
  j["name"] = person.name;
  j["interpupillary_distance_mm"] = person.interpupillary_distance_m * 1000.0;
  j["shape_params"] = std::vector<double>(person.shape_params.data(), person.shape_params.data() + person.shape_params.size());
  j["fit_rms_px"] = person.fit_rms_px;
  if (person.landmark_offsets_m.cols() > 0) {
    nlohmann::json offsets = nlohmann::json::array();
    for (Eigen::Index i = 0; i < person.landmark_offsets_m.cols(); ++i) {
      const Eigen::Vector3d mm = person.landmark_offsets_m.col(i) * 1000.0;
      offsets.push_back({mm.x(), mm.y(), mm.z()});
    }
    j["landmark_offsets_mm"] = offsets;
  }
  // Stored as the pose the registration's fit found for the frontal head (R_cam_model = F ·
  // R_frontal_model, F the frontal rotation): readable, and what the person's frame takes for frontal.
  const HeadAngles pose = head_angles(head_rotation({}) * person.R_frontal_model);
  j["frontal_pose_deg"] = {{"yaw", pose.yaw * kDegPerRad}, {"pitch", pose.pitch * kDegPerRad}, {"roll", pose.roll * kDegPerRad}};
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot write the person's face shape");
  out << j.dump(2) << "\n";
}

PersonShape load_person_shape(const std::filesystem::path& file, int shape_unit_count) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the person's face shape");
  const auto fail = [&](const std::string& what) -> void { throw std::runtime_error(file.string() + ": " + what); };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    fail(std::string("invalid JSON: ") + e.what());
  }
  PersonShape p;
  try {
    p.name = j.at("name").get<std::string>();
    validate_person_name(p.name);
    const double ipd_mm = j.at("interpupillary_distance_mm").get<double>();
    if (!(ipd_mm >= 40 && ipd_mm <= 90)) fail("interpupillary_distance_mm " + std::to_string(ipd_mm) + ": expected 40-90");
    p.interpupillary_distance_m = ipd_mm / 1000.0;
    const auto params = j.at("shape_params").get<std::vector<double>>();
    if (static_cast<int>(params.size()) != shape_unit_count) {
      fail("shape_params has " + std::to_string(params.size()) + " values, expected " + std::to_string(shape_unit_count));
    }
    p.shape_params = Eigen::Map<const Eigen::VectorXd>(params.data(), static_cast<Eigen::Index>(params.size()));
    if (!p.shape_params.allFinite() || p.shape_params.cwiseAbs().maxCoeff() > 1.0 + 1e-9) {
      fail("shape_params: expected finite values in [-1, 1]");
    }
    p.fit_rms_px = j.value("fit_rms_px", 0.0);
    if (j.contains("landmark_offsets_mm")) {
      const auto offsets = j.at("landmark_offsets_mm").get<std::vector<std::vector<double>>>();
      p.landmark_offsets_m.resize(3, static_cast<Eigen::Index>(offsets.size()));
      for (std::size_t i = 0; i < offsets.size(); ++i) {
        const auto& o = offsets[i];
        if (o.size() != 3 || !std::all_of(o.begin(), o.end(), [](double v) { return std::isfinite(v) && std::abs(v) <= 30.0; })) {
          fail("landmark_offsets_mm[" + std::to_string(i) + "]: expected [x, y, z], each finite and within 30 mm");
        }
        p.landmark_offsets_m.col(static_cast<Eigen::Index>(i)) = Eigen::Vector3d(o[0], o[1], o[2]) / 1000.0;
      }
    }
    if (j.contains("frontal_pose_deg")) {
      const auto& pose = j.at("frontal_pose_deg");
      HeadAngles a;
      for (auto [key, angle] : {std::pair<const char*, double*>{"yaw", &a.yaw}, {"pitch", &a.pitch}, {"roll", &a.roll}}) {
        if (!pose.is_object() || !pose.contains(key) || !pose.at(key).is_number())
          fail(std::string("frontal_pose_deg.") + key + ": expected a number of degrees");
        const double deg = pose.at(key).get<double>();
        if (!std::isfinite(deg) || std::abs(deg) > kMaxFrontalPoseDeg)
          fail(std::string("frontal_pose_deg.") + key + ": expected a finite angle within 30°");
        *angle = deg / kDegPerRad;
      }
      p.R_frontal_model = head_rotation({}).transpose() * head_rotation(a);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(std::string("expected keys name, interpupillary_distance_mm, shape_params: ") + e.what());
  }
  return p;
}

}  // namespace labo::face
