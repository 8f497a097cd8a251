#include "server/api/config_file.hpp"

#include <fstream>
#include <set>

namespace labo::server {

using nlohmann::json;

std::variant<json, ConfigFileError> read_config_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return ConfigFileError{500, "cannot read " + file.string()};
  json doc = json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return ConfigFileError{500, file.string() + " is not a JSON object"};
  return doc;
}

std::variant<AppConfig, ConfigFileError> replace_config(const std::filesystem::path& file, const json& doc) {
  const std::string text = doc.dump(2) + "\n";
  AppConfig config;
  try {
    // The same validation as at start-up: types, ranges, unknown keys, users' hashes.
    const ConfigDocument parsed = ConfigDocument::parse(text, file.filename().string());
    config = read_app_config(parsed.root(), file.parent_path());
  } catch (const ConfigError& e) {
    return ConfigFileError{422, e.what()};
  }
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    if (!out) return ConfigFileError{500, "cannot write " + tmp.string()};
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) return ConfigFileError{500, "cannot replace " + file.string() + ": " + ec.message()};
  return config;
}

std::vector<std::string> changed_keys(const json& before, const json& after) {
  std::set<std::string> keys;
  const auto differs = [](const json& a, const json& b, const std::string& key) {
    const bool in_a = a.is_object() && a.contains(key), in_b = b.is_object() && b.contains(key);
    return in_a != in_b || (in_a && a[key] != b[key]);
  };
  const auto collect = [&](const json& a, const json& b, const std::string& prefix) {
    for (const json* doc : {&a, &b})
      if (doc->is_object())
        for (const auto& [key, value] : doc->items())
          if (differs(a, b, key) && !(prefix.empty() && key == "server")) keys.insert(prefix + key);
  };
  collect(before, after, "");
  collect(before.value("server", json::object()), after.value("server", json::object()), "server.");
  return {keys.begin(), keys.end()};
}

}  // namespace labo::server
