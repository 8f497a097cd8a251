#pragma once
// Instruments uploaded by an admin: a template photo of the front panel with its physical size and
// pose in the lab, stored as <dir>/<id>.png + <id>.json. Every upload is validated (id, sizes, pose,
// a decodable image that is large and textured enough to be tracked) before anything is written.
#include <filesystem>
#include <mutex>
#include <optional>
#include <variant>
#include <string>
#include <vector>

namespace labo {

struct UploadedInstrument {
  std::string id, name;
  double width_m = 0, height_m = 0;
  double x_m = 0, y_m = 0, z_m = 0, yaw_deg = 0;  // panel centre in the world, panel facing
  int width_px = 0, height_px = 0;
  int texture_corners = 0;  // strong corners found on the template
};

// A refusal: which field and why, for a 400 (or 409 for a duplicate id).
struct InstrumentError {
  int status = 400;
  std::string message;
};

class InstrumentStore {
 public:
  explicit InstrumentStore(std::filesystem::path dir);

  std::vector<UploadedInstrument> list() const;
  // `body` is the JSON of POST /api/instruments; `reserved_ids` are the lab's own instruments.
  std::variant<UploadedInstrument, InstrumentError> add(const std::string& body,
                                                        const std::vector<std::string>& reserved_ids);
  // false when no uploaded instrument has that id.
  bool remove(const std::string& id);

  static bool valid_id(const std::string& id);
  static constexpr int kMinTextureCorners = 40;

 private:
  std::filesystem::path dir_;
  mutable std::mutex mutex_;
};

}  // namespace labo
