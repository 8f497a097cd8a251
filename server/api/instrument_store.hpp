#pragma once
// Instruments uploaded by an admin: a template photo of the front panel with its physical size and,
// once known, where it stands in the lab, stored as <dir>/<id>.png + <id>.json. Every upload is
// validated (id, sizes, placement, a decodable image of a usable size whose template is strong enough
// to be found and tracked: localization/planar/template_strength.hpp) before anything is written.
// Placing it in the flight software is the REST layer's (instrument_routes.cpp).
#include <filesystem>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "drone/lab/lab_description.hpp"
#include "localization/planar/template_strength.hpp"

namespace labo::server {

// Where an instrument's panel is: its centre in the world and the direction it faces (the lab
// file's facing_deg: the way a viewer in front of it looks from), degrees about z.
struct InstrumentPlacement {
  double x_m = 0, y_m = 0, z_m = 0;
  double yaw_deg = 0;
};

struct UploadedInstrument {
  std::string id, name;
  double width_m = 0, height_m = 0;
  double depth_m = 0.2;  // the housing behind the panel
  std::optional<InstrumentPlacement> placement;  // unset: stored, not yet placed in the lab
  int width_px = 0, height_px = 0;
  planar::TemplateStrength strength;
};

// A refusal: the HTTP status (400 malformed, 409 a duplicate id, 415 not an image, 422 an image or
// placement that cannot be used) and what was wrong.
struct InstrumentError {
  int status = 400;
  std::string message;
};

class InstrumentStore {
 public:
  explicit InstrumentStore(std::filesystem::path dir);

  std::vector<UploadedInstrument> list() const;
  std::optional<UploadedInstrument> find(const std::string& id) const;
  // `body` is the JSON of POST /api/instruments; `reserved_ids` are the ids the lab has already.
  std::variant<UploadedInstrument, InstrumentError> add(const std::string& body,
                                                        const std::vector<std::string>& reserved_ids);
  // Records (or clears) where an uploaded instrument stands; false when there is none with that id.
  bool set_placement(const std::string& id, const std::optional<InstrumentPlacement>& placement);
  // false when no uploaded instrument has that id.
  bool remove(const std::string& id);
  std::filesystem::path template_path(const std::string& id) const { return dir_ / (id + ".png"); }

  static bool valid_id(const std::string& id);
  // `position_m` [x, y, z] and `yaw_deg` of an upload or a placement: both or neither (empty).
  static std::variant<std::optional<InstrumentPlacement>, InstrumentError> read_placement(const nlohmann::json& j);
  static constexpr int kMinSidePx = 64, kMaxSidePx = 4096;

 private:
  void write_manifest(const UploadedInstrument& u) const;

  std::filesystem::path dir_;
  mutable std::mutex mutex_;
};

// The lab description's instrument for a placed upload (its template at `template_path`).
lab::InstrumentSpec instrument_spec_of(const UploadedInstrument& u, const std::filesystem::path& template_path);

}  // namespace labo::server
