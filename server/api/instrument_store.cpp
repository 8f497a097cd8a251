#include "server/api/instrument_store.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "server/auth/password_hash.hpp"

namespace labo::server {

using lab::InstrumentSpec;
using lab::panel_pose;

using nlohmann::json;

namespace {

json strength_json(const planar::TemplateStrength& s) {
  return {{"sift_keypoints", s.sift_keypoints}, {"strong_corners", s.strong_corners}, {"textured_fraction", s.textured_fraction}};
}

UploadedInstrument from_json(const json& j) {
  UploadedInstrument u;
  u.id = j.at("id");
  u.name = j.at("name");
  u.width_m = j.at("width_m");
  u.height_m = j.at("height_m");
  u.depth_m = j.value("depth_m", 0.2);
  if (j.contains("position_m") && j["position_m"].is_array()) {
    const auto& p = j["position_m"];
    u.placement = InstrumentPlacement{p.at(0), p.at(1), p.at(2), j.at("yaw_deg")};
  }
  u.width_px = j.value("width_px", 0);
  u.height_px = j.value("height_px", 0);
  if (j.contains("strength")) {
    const auto& s = j["strength"];
    u.strength = {s.value("sift_keypoints", 0), s.value("strong_corners", 0), s.value("textured_fraction", 0.0)};
  }
  return u;
}

json to_json(const UploadedInstrument& u) {
  json j{{"id", u.id}, {"name", u.name}, {"width_m", u.width_m}, {"height_m", u.height_m}, {"depth_m", u.depth_m},
         {"width_px", u.width_px}, {"height_px", u.height_px}, {"strength", strength_json(u.strength)}};
  if (u.placement) {
    j["position_m"] = {u.placement->x_m, u.placement->y_m, u.placement->z_m};
    j["yaw_deg"] = u.placement->yaw_deg;
  }
  return j;
}

std::optional<double> number_in(const json& j, const char* key, double lo, double hi) {
  if (!j.contains(key) || !j[key].is_number()) return std::nullopt;
  const double v = j[key];
  if (!(v >= lo && v <= hi)) return std::nullopt;
  return v;
}

// Id, name and sizes; the placement and the image are read apart.
std::optional<InstrumentError> read_fields(const json& j, UploadedInstrument& u) {
  if (!j.contains("id") || !j["id"].is_string() || !InstrumentStore::valid_id(j["id"]))
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
  if (j.contains("depth_m")) {
    const auto d = number_in(j, "depth_m", 0.01, 2.0);
    if (!d) return InstrumentError{400, "'depth_m' (the housing behind the panel) must be a number in [0.01, 2] m"};
    u.depth_m = *d;
  }
  return std::nullopt;
}

// The template: decodable, of a usable size, strong enough to be found and tracked.
std::variant<cv::Mat, InstrumentError> read_template(const json& j, UploadedInstrument& u) {
  if (!j.contains("image_base64") || !j["image_base64"].is_string())
    return InstrumentError{400, "'image_base64' (a PNG or JPEG, base64) is required"};
  const auto bytes = base64_decode(j["image_base64"]);
  if (!bytes || bytes->empty()) return InstrumentError{400, "'image_base64' is not valid base64"};
  const cv::Mat colour = cv::imdecode(*bytes, cv::IMREAD_COLOR);
  if (colour.empty()) return InstrumentError{415, "'image_base64' is not a PNG or JPEG image"};
  if (colour.cols < InstrumentStore::kMinSidePx || colour.rows < InstrumentStore::kMinSidePx ||
      colour.cols > InstrumentStore::kMaxSidePx || colour.rows > InstrumentStore::kMaxSidePx)
    return InstrumentError{422, "the template must be " + std::to_string(InstrumentStore::kMinSidePx) + " to " +
                                    std::to_string(InstrumentStore::kMaxSidePx) + " pixels on each side, got " +
                                    std::to_string(colour.cols) + "x" + std::to_string(colour.rows)};
  // The panel's aspect: a template stretched onto the panel would give the tracker a wrong homography.
  const double aspect_px = static_cast<double>(colour.cols) / colour.rows, aspect_m = u.width_m / u.height_m;
  if (std::abs(std::log(aspect_px / aspect_m)) > std::log(1.1))
    return InstrumentError{422, "the template's aspect (" + std::to_string(colour.cols) + "x" + std::to_string(colour.rows) +
                                    " px) differs from the panel's (" + json(u.width_m).dump() + " x " + json(u.height_m).dump() +
                                    " m) by more than 10 %: crop the photo to the panel"};
  cv::Mat gray;
  cv::cvtColor(colour, gray, cv::COLOR_BGR2GRAY);
  u.strength = planar::measure_template_strength(gray);
  if (const std::string weak = planar::template_weakness(u.strength); !weak.empty())
    return InstrumentError{422, "the template is too weak to be found and tracked: " + weak +
                                    " (photograph the panel head-on, evenly lit, cropped to its displays, labels and knobs)"};
  u.width_px = colour.cols;
  u.height_px = colour.rows;
  return colour;
}

}  // namespace

InstrumentStore::InstrumentStore(std::filesystem::path dir) : dir_(std::move(dir)) {}

bool InstrumentStore::valid_id(const std::string& id) {
  if (id.empty() || id.size() > 32) return false;
  for (char c : id)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) return false;
  return true;
}

std::variant<std::optional<InstrumentPlacement>, InstrumentError> InstrumentStore::read_placement(const json& j) {
  const bool has_position = j.contains("position_m"), has_yaw = j.contains("yaw_deg");
  if (!has_position && !has_yaw) return std::optional<InstrumentPlacement>{};
  if (!has_position || !j["position_m"].is_array() || j["position_m"].size() != 3)
    return InstrumentError{400, "'position_m' must be [x, y, z] in metres (the panel's centre in the world), with 'yaw_deg'"};
  for (const auto& v : j["position_m"])
    if (!v.is_number() || !std::isfinite(v.get<double>()) || std::abs(v.get<double>()) > 100)
      return InstrumentError{400, "'position_m' values must be numbers within 100 m"};
  const auto yaw = number_in(j, "yaw_deg", -180, 180);
  if (!yaw) return InstrumentError{400, "'yaw_deg' (the direction the panel faces) must be a number in [-180, 180], with 'position_m'"};
  return std::optional<InstrumentPlacement>{InstrumentPlacement{j["position_m"][0], j["position_m"][1], j["position_m"][2], *yaw}};
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
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

std::optional<UploadedInstrument> InstrumentStore::find(const std::string& id) const {
  if (!valid_id(id)) return std::nullopt;
  for (UploadedInstrument& u : list())
    if (u.id == id) return std::move(u);
  return std::nullopt;
}

std::variant<UploadedInstrument, InstrumentError> InstrumentStore::add(const std::string& body,
                                                                       const std::vector<std::string>& reserved_ids) {
  const json j = json::parse(body, nullptr, false);
  if (j.is_discarded()) return InstrumentError{400, "malformed JSON"};
  if (!j.is_object()) return InstrumentError{400, "expected a JSON object"};
  static const std::set<std::string> kFields{"id", "name", "width_m", "height_m", "depth_m", "position_m", "yaw_deg", "image_base64"};
  for (const auto& [key, v] : j.items())
    if (!kFields.contains(key)) return InstrumentError{400, "unknown field '" + key + "'"};
  UploadedInstrument u;
  if (auto error = read_fields(j, u)) return *error;
  auto placement = read_placement(j);
  if (auto* error = std::get_if<InstrumentError>(&placement)) return *error;
  u.placement = std::get<std::optional<InstrumentPlacement>>(placement);
  auto image = read_template(j, u);
  if (auto* error = std::get_if<InstrumentError>(&image)) return *error;

  std::lock_guard lock(mutex_);
  for (const auto& r : reserved_ids)
    if (r == u.id) return InstrumentError{409, "instrument '" + u.id + "' is in the lab already"};
  if (std::filesystem::exists(dir_ / (u.id + ".json"))) return InstrumentError{409, "instrument '" + u.id + "' already exists"};
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (!cv::imwrite(template_path(u.id).string(), std::get<cv::Mat>(image)))
    return InstrumentError{500, "cannot write the template under " + dir_.string()};
  write_manifest(u);
  return u;
}

void InstrumentStore::write_manifest(const UploadedInstrument& u) const {
  // Written beside and renamed over: a crash never leaves half a manifest.
  const auto file = dir_ / (u.id + ".json"), temporary = dir_ / (u.id + ".json.tmp");
  std::ofstream(temporary) << to_json(u).dump(2) << "\n";
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
}

bool InstrumentStore::set_placement(const std::string& id, const std::optional<InstrumentPlacement>& placement) {
  std::optional<UploadedInstrument> u = find(id);
  if (!u) return false;
  u->placement = placement;
  std::lock_guard lock(mutex_);
  write_manifest(*u);
  return true;
}

bool InstrumentStore::remove(const std::string& id) {
  if (!valid_id(id)) return false;
  std::lock_guard lock(mutex_);
  std::error_code ec;
  const bool removed = std::filesystem::remove(dir_ / (id + ".json"), ec);
  std::filesystem::remove(template_path(id), ec);
  return removed;
}

InstrumentSpec instrument_spec_of(const UploadedInstrument& u, const std::filesystem::path& template_path) {
  InstrumentSpec s;
  s.id = u.id;
  s.name = u.name;
  s.template_path = template_path;
  s.width_m = u.width_m;
  s.height_m = u.height_m;
  s.depth_m = u.depth_m;
  const InstrumentPlacement p = u.placement.value_or(InstrumentPlacement{});
  s.T_world_object = panel_pose({p.x_m, p.y_m, p.z_m}, p.yaw_deg * std::numbers::pi / 180.0);
  return s;
}

}  // namespace labo::server
