#pragma once
// Structured logging: one line per event, `t=<s> level=<l> component=<c> msg="..." key=value ...`.
// A Logger is a value passed to whoever logs (no global logger). RateLimiter keeps hot paths from
// logging per item: at most one line per kind per interval, with the count of suppressed ones.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

#include "core/time.hpp"

namespace labo {

enum class LogLevel { Debug = 0, Info = 1, Warn = 2, Error = 3, Off = 4 };

std::string_view to_string(LogLevel level);
// Parses "debug", "info", "warn", "error", "off"; throws std::invalid_argument naming the choices.
LogLevel parse_log_level(std::string_view text);

class LogLine;

class Logger {
 public:
  using Sink = std::function<void(const std::string& line)>;

  // Writes to stderr.
  Logger(std::string component = "labodrone", LogLevel level = LogLevel::Info);
  Logger(std::string component, LogLevel level, Sink sink);

  // A logger for a sub-component sharing this one's sink and level.
  Logger child(std::string_view component) const;

  bool enabled(LogLevel level) const { return level >= level_ && level_ != LogLevel::Off; }
  LogLine log(LogLevel level, Seconds t, std::string_view msg) const;
  LogLine info(Seconds t, std::string_view msg) const;
  LogLine warn(Seconds t, std::string_view msg) const;
  LogLine error(Seconds t, std::string_view msg) const;
  LogLine debug(Seconds t, std::string_view msg) const;

  void write(const std::string& line) const;

 private:
  std::string component_;
  LogLevel level_;
  std::shared_ptr<Sink> sink_;
};

// Collects key=value pairs and writes the line when it goes out of scope.
class LogLine {
 public:
  LogLine(const Logger* logger, std::string prefix);
  LogLine(LogLine&&) = default;
  LogLine(const LogLine&) = delete;
  LogLine& operator=(const LogLine&) = delete;
  LogLine& operator=(LogLine&&) = delete;
  ~LogLine();

  template <typename T>
  LogLine& kv(std::string_view key, const T& value) {
    if (logger_) out_ << ' ' << key << '=' << value;
    return *this;
  }
  LogLine& kv(std::string_view key, std::string_view value);
  LogLine& kv(std::string_view key, const std::string& value) { return kv(key, std::string_view(value)); }
  LogLine& kv(std::string_view key, const char* value) { return kv(key, std::string_view(value)); }

 private:
  const Logger* logger_;
  std::ostringstream out_;
};

// At most one report per kind per interval; counts what it suppressed in between.
class RateLimiter {
 public:
  explicit RateLimiter(Seconds interval = 1.0) : interval_(interval) {}
  // True when a line for `kind` may be written at time t; `suppressed` gets the count skipped since.
  bool allow(std::string_view kind, Seconds t, std::size_t* suppressed = nullptr);

 private:
  struct Entry {
    Seconds last = -1e300;
    std::size_t suppressed = 0;
  };
  Seconds interval_;
  std::mutex mutex_;
  std::map<std::string, Entry, std::less<>> entries_;
};

}  // namespace labo
