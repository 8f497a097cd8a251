#pragma once
// The registered people of face.people_dir, one <name>.json each (localization/face/person_shape.hpp):
// listed, loaded, written atomically (a temporary file renamed over the old one, so a reader never
// sees half a shape) and removed. Thread-safe: the REST routes and the registration worker share it.
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "localization/face/person_shape.hpp"

namespace labo::server {

// How a shape was registered from the page, kept beside the shape in its file ("registration"); a
// file written by `labodrone face register` has none.
struct RegistrationRecord {
  int frontal_photos = 0;
  int head_turn_views = 0;  // frames the depth refinement used; 0: no head turn
  double unix_s = 0;
  std::string by;           // the teacher or admin who registered it
};

struct RegisteredPerson {
  std::string name;
  double fit_rms_px = 0;
  double interpupillary_distance_mm = 0;
  std::optional<RegistrationRecord> registration;
  std::string error;  // a file that cannot be read: why (the other fields are empty)
};

class PeopleStore {
 public:
  // `shape_unit_count`: the CANDIDE-3 model's, every stored shape must match it.
  PeopleStore(std::filesystem::path dir, int shape_unit_count);

  std::vector<RegisteredPerson> list() const;
  bool exists(const std::string& name) const;
  // Throws std::runtime_error naming the file and what is wrong with it.
  std::shared_ptr<const face::PersonShape> load(const std::string& name) const;
  // False when `name` exists and `replace` is not set; throws std::runtime_error when it cannot write.
  bool write(const face::PersonShape& person, const RegistrationRecord& record, bool replace);
  bool remove(const std::string& name);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  int shape_unit_count_;
  mutable std::mutex mutex_;
};

}  // namespace labo::server
