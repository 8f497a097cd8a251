#include "server/api/people_store.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace labo::server {

using nlohmann::json;

namespace {

// A file name <name>.json whose name is a valid person name.
std::optional<std::string> person_of(const std::filesystem::path& file) {
  if (file.extension() != ".json") return std::nullopt;
  const std::string name = file.stem().string();
  try {
    face::validate_person_name(name);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  return name;
}

RegisteredPerson summary_of(const std::string& name, const std::filesystem::path& file) {
  RegisteredPerson p;
  p.name = name;
  std::ifstream in(file);
  const json j = json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    p.error = "not a JSON object";
    return p;
  }
  try {
    p.fit_rms_px = j.at("fit_rms_px").get<double>();
    p.interpupillary_distance_mm = j.at("interpupillary_distance_mm").get<double>();
    if (j.contains("registration")) {
      const json& r = j["registration"];
      p.registration = RegistrationRecord{r.at("frontal_photos").get<int>(), r.at("head_turn_views").get<int>(),
                                          r.at("unix_s").get<double>(), r.at("by").get<std::string>()};
    }
  } catch (const json::exception& e) {
    p.error = e.what();
  }
  return p;
}

}  // namespace

PeopleStore::PeopleStore(std::filesystem::path dir, int shape_unit_count)
    : dir_(std::move(dir)), shape_unit_count_(shape_unit_count) {}

std::vector<RegisteredPerson> PeopleStore::list() const {
  std::lock_guard lock(mutex_);
  std::vector<RegisteredPerson> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    if (!entry.is_regular_file()) continue;
    if (const auto name = person_of(entry.path())) out.push_back(summary_of(*name, entry.path()));
  }
  std::sort(out.begin(), out.end(), [](const RegisteredPerson& a, const RegisteredPerson& b) { return a.name < b.name; });
  return out;
}

bool PeopleStore::exists(const std::string& name) const {
  std::lock_guard lock(mutex_);
  return std::filesystem::is_regular_file(face::person_shape_path(dir_, name));
}

std::shared_ptr<const face::PersonShape> PeopleStore::load(const std::string& name) const {
  std::lock_guard lock(mutex_);
  return std::make_shared<const face::PersonShape>(face::load_person_shape(face::person_shape_path(dir_, name), shape_unit_count_));
}

bool PeopleStore::write(const face::PersonShape& person, const RegistrationRecord& record, bool replace) {
  std::lock_guard lock(mutex_);
  const std::filesystem::path file = face::person_shape_path(dir_, person.name);
  if (!replace && std::filesystem::exists(file)) return false;
  const std::filesystem::path temporary = file.string() + ".tmp";
  face::save_person_shape(person, temporary);
  json j = json::parse(std::ifstream(temporary));
  j["registration"] = {{"frontal_photos", record.frontal_photos}, {"head_turn_views", record.head_turn_views},
                       {"unix_s", record.unix_s}, {"by", record.by}};
  {
    std::ofstream out(temporary);
    out << j.dump(2) << "\n";
    if (!out.flush()) throw std::runtime_error(temporary.string() + ": cannot write the person's face shape");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot replace: " + ec.message());
  return true;
}

bool PeopleStore::remove(const std::string& name) {
  std::lock_guard lock(mutex_);
  std::error_code ec;
  return std::filesystem::remove(face::person_shape_path(dir_, name), ec);
}

}  // namespace labo::server
