#include "server/api/instrument_store.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <variant>

#include "server/auth/password_hash.hpp"

namespace labo {

using nlohmann::json;

namespace {

UploadedInstrument from_json(const json& j) {
  UploadedInstrument u;
  u.id = j.at("id");
  u.name = j.at("name");
  u.width_m = j.at("width_m");
  u.height_m = j.at("height_m");
  const auto& p = j.at("position_m");
  u.x_m = p.at(0);
  u.y_m = p.at(1);
  u.z_m = p.at(2);
  u.yaw_deg = j.at("yaw_deg");
  u.width_px = j.value("width_px", 0);
  u.height_px = j.value("height_px", 0);
  u.texture_corners = j.value("texture_corners", 0);
  return u;
}

json to_json(const UploadedInstrument& u) {
  return {{"id", u.id}, {"name", u.name}, {"width_m", u.width_m}, {"height_m", u.height_m},
          {"position_m", {u.x_m, u.y_m, u.z_m}}, {"yaw_deg", u.yaw_deg}, {"width_px", u.width_px},
          {"height_px", u.height_px}, {"texture_corners", u.texture_corners}};
}

std::optional<double> number_in(const json& j, const char* key, double lo, double hi) {
  if (!j.contains(key) || !j[key].is_number()) return std::nullopt;
  const double v = j[key];
  if (!(v >= lo && v <= hi)) return std::nullopt;
  return v;
}

}  // namespace

InstrumentStore::InstrumentStore(std::filesystem::path dir) : dir_(std::move(dir)) {}

bool InstrumentStore::valid_id(const std::string& id) {
  if (id.empty() || id.size() > 32) return false;
  for (char c : id)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) return false;
  return true;
}

std::vector<UploadedInstrument> InstrumentStore::list() const {
  std::lock_guard lock(mutex_);
  std::vector<UploadedInstrument> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    const json j = json::parse(in, nullptr, false);
    try {
      if (!j.is_discarded()) out.push_back(from_json(j));
    } catch (const json::exception&) {
      // a manifest edited by hand into nonsense is skipped, not served
    }
  }
  return out;
}

std::variant<UploadedInstrument, InstrumentError> InstrumentStore::add(const std::string& body,
                                                                       const std::vector<std::string>& reserved_ids) {
  const json j = json::parse(body, nullptr, false);
  if (j.is_discarded()) return InstrumentError{400, "malformed JSON"};
  if (!j.is_object()) return InstrumentError{400, "expected a JSON object"};
  static const std::set<std::string> kFields{"id", "name", "width_m", "height_m", "position_m", "yaw_deg", "image_base64"};
  for (const auto& [key, v] : j.items())
    if (!kFields.contains(key)) return InstrumentError{400, "unknown field '" + key + "'"};
  UploadedInstrument u;
  if (!j.contains("id") || !j["id"].is_string() || !valid_id(j["id"]))
    return InstrumentError{400, "'id' must be 1-32 characters of a-z, 0-9, _ or -"};
  u.id = j["id"];
  if (!j.contains("name") || !j["name"].is_string() || j["name"].get<std::string>().empty() || j["name"].get<std::string>().size() > 80)
    return InstrumentError{400, "'name' must be a string of 1-80 characters"};
  u.name = j["name"];
  const auto w = number_in(j, "width_m", 0.02, 3.0);
  const auto h = number_in(j, "height_m", 0.02, 3.0);
  if (!w || !h) return InstrumentError{400, "'width_m' and 'height_m' must be numbers in [0.02, 3] m"};
  u.width_m = *w;
  u.height_m = *h;
  if (!j.contains("position_m") || !j["position_m"].is_array() || j["position_m"].size() != 3)
    return InstrumentError{400, "'position_m' must be [x, y, z] in metres"};
  for (const auto& v : j["position_m"])
    if (!v.is_number() || std::abs(v.get<double>()) > 100) return InstrumentError{400, "'position_m' values must be numbers within 100 m"};
  u.x_m = j["position_m"][0];
  u.y_m = j["position_m"][1];
  u.z_m = j["position_m"][2];
  const auto yaw = number_in(j, "yaw_deg", -180, 180);
  if (!yaw) return InstrumentError{400, "'yaw_deg' must be a number in [-180, 180]"};
  u.yaw_deg = *yaw;
  if (!j.contains("image_base64") || !j["image_base64"].is_string())
    return InstrumentError{400, "'image_base64' (a PNG or JPEG, base64) is required"};
  const auto bytes = base64_decode(j["image_base64"]);
  if (!bytes || bytes->empty()) return InstrumentError{400, "'image_base64' is not valid base64"};
  const cv::Mat image = cv::imdecode(*bytes, cv::IMREAD_GRAYSCALE);
  if (image.empty()) return InstrumentError{400, "'image_base64' is not a PNG or JPEG image"};
  if (image.cols < 64 || image.rows < 64 || image.cols > 4096 || image.rows > 4096)
    return InstrumentError{400, "the template must be 64 to 4096 pixels on each side, got " +
                                    std::to_string(image.cols) + "x" + std::to_string(image.rows)};
  // Texture: a panel with too few corners cannot be detected or tracked by the planar module.
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, 500, 0.01, std::max(3.0, image.cols / 100.0));
  u.texture_corners = static_cast<int>(corners.size());
  if (u.texture_corners < kMinTextureCorners)
    return InstrumentError{400, "the template has too little texture to be tracked: " + std::to_string(u.texture_corners) +
                                    " strong corners, at least " + std::to_string(kMinTextureCorners) + " needed"};
  u.width_px = image.cols;
  u.height_px = image.rows;

  std::lock_guard lock(mutex_);
  for (const auto& r : reserved_ids)
    if (r == u.id) return InstrumentError{409, "instrument '" + u.id + "' is part of the lab description"};
  if (std::filesystem::exists(dir_ / (u.id + ".json"))) return InstrumentError{409, "instrument '" + u.id + "' already exists"};
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (!cv::imwrite((dir_ / (u.id + ".png")).string(), cv::imdecode(*bytes, cv::IMREAD_COLOR)))
    return InstrumentError{500, "cannot write the template under " + dir_.string()};
  std::ofstream(dir_ / (u.id + ".json")) << to_json(u).dump(2) << "\n";
  return u;
}

bool InstrumentStore::remove(const std::string& id) {
  if (!valid_id(id)) return false;
  std::lock_guard lock(mutex_);
  std::error_code ec;
  const bool removed = std::filesystem::remove(dir_ / (id + ".json"), ec);
  std::filesystem::remove(dir_ / (id + ".png"), ec);
  return removed;
}

}  // namespace labo
