#pragma once
// Validated reading of JSON configuration. Every value is read through a ConfigReader, which knows
// the file and the key path it stands at, so every refusal names the file, the key path, the value
// found and what was expected. Keys nobody read are errors (finish()): a misspelt key is refused, not
// silently ignored. JSON stays at this edge: modules see only ConfigReader.
#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace labo {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;  // (min, max] when true: "must be > min"

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false}; }
  bool contains(double v) const;
  std::string describe() const;
};

class ConfigReader;

// Owns a parsed JSON document and its source name.
class ConfigDocument {
 public:
  // Throws ConfigError "<file>: cannot read ..." or "<file>: invalid JSON at byte N: ...".
  static ConfigDocument load(const std::filesystem::path& file);
  static ConfigDocument parse(std::string_view text, std::string source_name);
  ConfigDocument(ConfigDocument&&) noexcept;
  ConfigDocument& operator=(ConfigDocument&&) noexcept;
  ~ConfigDocument();

  ConfigReader root() const;
  const std::string& source() const { return source_; }
  std::string dump(int indent = 2) const;
  const nlohmann::json& json() const { return *json_; }

 private:
  ConfigDocument(std::unique_ptr<nlohmann::json> json, std::string source);
  std::unique_ptr<nlohmann::json> json_;
  std::string source_;
};

class ConfigReader {
 public:
  ConfigReader(const nlohmann::json& node, std::string source, std::string path);

  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }
  std::string key_path(std::string_view key) const;

  bool has(std::string_view key) const;
  std::vector<std::string> keys() const;  // of an object node, marks none as read

  double number(std::string_view key, Range range = {}) const;
  double number_or(std::string_view key, double fallback, Range range = {}) const;
  int integer(std::string_view key, int min = std::numeric_limits<int>::min(),
              int max = std::numeric_limits<int>::max()) const;
  int integer_or(std::string_view key, int fallback, int min = std::numeric_limits<int>::min(),
                 int max = std::numeric_limits<int>::max()) const;
  bool boolean(std::string_view key) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  std::string string(std::string_view key) const;
  std::string string_or(std::string_view key, std::string fallback) const;
  // A string that must be one of `choices`.
  std::string choice(std::string_view key, std::initializer_list<std::string_view> choices) const;
  std::string choice_or(std::string_view key, std::string fallback,
                        std::initializer_list<std::string_view> choices) const;
  // An array of numbers; `size` < 0 accepts any length.
  std::vector<double> numbers(std::string_view key, int size = -1, Range range = {}) const;

  ConfigReader object(std::string_view key) const;
  bool is_object(std::string_view key) const;
  std::vector<ConfigReader> objects(std::string_view key) const;  // array of objects

  // Throws ConfigError naming every key of this object that no accessor read.
  void finish() const;
  // Throws ConfigError "<source>: <path.key>: <message>" for checks across several values.
  [[noreturn]] void fail(std::string_view key, std::string_view message) const;

 private:
  const nlohmann::json& require(std::string_view key) const;
  const nlohmann::json* find(std::string_view key) const;
  void mark(std::string_view key) const;
  [[noreturn]] void fail_value(std::string_view key, const nlohmann::json& found, std::string_view expected) const;

  const nlohmann::json* node_;
  std::string source_;
  std::string path_;
  std::shared_ptr<std::set<std::string, std::less<>>> read_keys_;
};

}  // namespace labo
