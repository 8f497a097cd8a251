#include "core/config_reader.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace labo {

namespace {
std::string short_dump(const nlohmann::json& j) {
  std::string s = j.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}
std::string type_name(const nlohmann::json& j) {
  return j.is_number_integer() ? "integer" : j.is_number() ? "number" : std::string(j.type_name());
}
}  // namespace

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (min_exclusive ? v <= min : v < min) return false;
  return v <= max;
}

std::string Range::describe() const {
  std::ostringstream out;
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    out << "a number in " << (min_exclusive ? "(" : "[") << min << ", " << max << "]";
  } else if (has_min) {
    out << "a number " << (min_exclusive ? "> " : ">= ") << min;
  } else if (has_max) {
    out << "a number <= " << max;
  } else {
    out << "a finite number";
  }
  return out.str();
}

ConfigDocument::ConfigDocument(std::unique_ptr<nlohmann::json> json, std::string source)
    : json_(std::move(json)), source_(std::move(source)) {}
ConfigDocument::ConfigDocument(ConfigDocument&&) noexcept = default;
ConfigDocument& ConfigDocument::operator=(ConfigDocument&&) noexcept = default;
ConfigDocument::~ConfigDocument() = default;

ConfigDocument ConfigDocument::load(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file.string() + ": cannot read the file (missing or not readable)");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse(buffer.str(), file.string());
}

ConfigDocument ConfigDocument::parse(std::string_view text, std::string source_name) {
  auto json = std::make_unique<nlohmann::json>();
  try {
    *json = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(source_name + ": invalid JSON at byte " + std::to_string(e.byte) + ": " + e.what());
  }
  if (!json->is_object()) {
    throw ConfigError(source_name + ": expected a JSON object at the top level, found " + type_name(*json));
  }
  return ConfigDocument(std::move(json), std::move(source_name));
}

ConfigReader ConfigDocument::root() const { return ConfigReader(*json_, source_, ""); }
std::string ConfigDocument::dump(int indent) const { return json_->dump(indent); }

ConfigReader::ConfigReader(const nlohmann::json& node, std::string source, std::string path)
    : node_(&node),
      source_(std::move(source)),
      path_(std::move(path)),
      read_keys_(std::make_shared<std::set<std::string, std::less<>>>()) {}

std::string ConfigReader::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

const nlohmann::json* ConfigReader::find(std::string_view key) const {
  if (!node_->is_object()) return nullptr;
  auto it = node_->find(key);
  return it == node_->end() ? nullptr : &*it;
}

void ConfigReader::mark(std::string_view key) const { read_keys_->emplace(key); }

bool ConfigReader::has(std::string_view key) const { return find(key) != nullptr; }

std::vector<std::string> ConfigReader::keys() const {
  std::vector<std::string> out;
  if (node_->is_object()) {
    for (auto it = node_->begin(); it != node_->end(); ++it) out.push_back(it.key());
  }
  return out;
}

const nlohmann::json& ConfigReader::require(std::string_view key) const {
  mark(key);
  const nlohmann::json* v = find(key);
  if (!v) throw ConfigError(source_ + ": " + key_path(key) + ": missing (required key)");
  return *v;
}

void ConfigReader::fail_value(std::string_view key, const nlohmann::json& found, std::string_view expected) const {
  throw ConfigError(source_ + ": " + key_path(key) + ": found " + short_dump(found) + " (" + type_name(found) +
                    "), expected " + std::string(expected));
}

void ConfigReader::fail(std::string_view key, std::string_view message) const {
  throw ConfigError(source_ + ": " + key_path(key) + ": " + std::string(message));
}

double ConfigReader::number(std::string_view key, Range range) const {
  const auto& v = require(key);
  if (!v.is_number() || !range.contains(v.get<double>())) fail_value(key, v, range.describe());
  return v.get<double>();
}

double ConfigReader::number_or(std::string_view key, double fallback, Range range) const {
  mark(key);
  return has(key) ? number(key, range) : fallback;
}

int ConfigReader::integer(std::string_view key, int min, int max) const {
  const auto& v = require(key);
  const std::string expected = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!v.is_number_integer()) fail_value(key, v, expected);
  const auto value = v.get<long long>();
  if (value < min || value > max) fail_value(key, v, expected);
  return static_cast<int>(value);
}

int ConfigReader::integer_or(std::string_view key, int fallback, int min, int max) const {
  mark(key);
  return has(key) ? integer(key, min, max) : fallback;
}

bool ConfigReader::boolean(std::string_view key) const {
  const auto& v = require(key);
  if (!v.is_boolean()) fail_value(key, v, "true or false");
  return v.get<bool>();
}

bool ConfigReader::boolean_or(std::string_view key, bool fallback) const {
  mark(key);
  return has(key) ? boolean(key) : fallback;
}

std::string ConfigReader::string(std::string_view key) const {
  const auto& v = require(key);
  if (!v.is_string()) fail_value(key, v, "a string");
  return v.get<std::string>();
}

std::string ConfigReader::string_or(std::string_view key, std::string fallback) const {
  mark(key);
  return has(key) ? string(key) : fallback;
}

std::string ConfigReader::choice(std::string_view key, std::initializer_list<std::string_view> choices) const {
  const auto& v = require(key);
  std::string expected = "one of";
  for (auto c : choices) expected += " \"" + std::string(c) + "\"";
  if (!v.is_string()) fail_value(key, v, expected);
  const auto s = v.get<std::string>();
  for (auto c : choices) {
    if (s == c) return s;
  }
  fail_value(key, v, expected);
}

std::string ConfigReader::choice_or(std::string_view key, std::string fallback,
                                    std::initializer_list<std::string_view> choices) const {
  mark(key);
  return has(key) ? choice(key, choices) : fallback;
}

std::vector<double> ConfigReader::numbers(std::string_view key, int size, Range range) const {
  const auto& v = require(key);
  std::string expected = size >= 0 ? "an array of " + std::to_string(size) + " numbers" : "an array of numbers";
  if (!v.is_array() || (size >= 0 && static_cast<int>(v.size()) != size)) fail_value(key, v, expected);
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number() || !range.contains(v[i].get<double>())) {
      fail_value(std::string(key) + "[" + std::to_string(i) + "]", v[i], range.describe());
    }
    out.push_back(v[i].get<double>());
  }
  return out;
}

ConfigReader ConfigReader::object(std::string_view key) const {
  const auto& v = require(key);
  if (!v.is_object()) fail_value(key, v, "an object");
  return ConfigReader(v, source_, key_path(key));
}

bool ConfigReader::is_object(std::string_view key) const {
  const auto* v = find(key);
  return v && v->is_object();
}

std::vector<ConfigReader> ConfigReader::objects(std::string_view key) const {
  const auto& v = require(key);
  if (!v.is_array()) fail_value(key, v, "an array of objects");
  std::vector<ConfigReader> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string item = std::string(key) + "[" + std::to_string(i) + "]";
    if (!v[i].is_object()) fail_value(item, v[i], "an object");
    out.emplace_back(v[i], source_, key_path(item));
  }
  return out;
}

void ConfigReader::finish() const {
  if (!node_->is_object()) return;
  std::string unknown;
  for (auto it = node_->begin(); it != node_->end(); ++it) {
    if (!read_keys_->contains(it.key())) unknown += (unknown.empty() ? "" : ", ") + key_path(it.key());
  }
  if (unknown.empty()) return;
  std::string known;
  for (const auto& k : *read_keys_) known += (known.empty() ? "" : ", ") + k;
  throw ConfigError(source_ + ": unknown key " + unknown + " (expected one of: " + known + ")");
}

}  // namespace labo
