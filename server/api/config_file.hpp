#pragma once
// The configuration file as the admin routes change it: a new document is validated exactly as at
// start-up, then written beside the file and renamed over it (readers and a crash see the old file
// or the new one, never half of one). What changed is named: the users apply at once, everything
// else at the next start.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "server/app_config.hpp"

namespace labo::server {

struct ConfigFileError {
  int status = 500;  // 422 when the document is refused, 500 when the file cannot be read or written
  std::string message;
};

// The file's JSON.
std::variant<nlohmann::json, ConfigFileError> read_config_json(const std::filesystem::path& file);
// Validates `doc` as the file's content (relative paths against the file's folder) and replaces the
// file with it; the configuration it describes.
std::variant<AppConfig, ConfigFileError> replace_config(const std::filesystem::path& file, const nlohmann::json& doc);
// The keys whose values differ between two documents: top-level keys, and "server.<key>" inside the
// server section.
std::vector<std::string> changed_keys(const nlohmann::json& before, const nlohmann::json& after);

}  // namespace labo::server
