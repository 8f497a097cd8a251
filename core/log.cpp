#include "core/log.hpp"

#include <iomanip>
#include <iostream>
#include <memory>
#include <stdexcept>

namespace labo {

std::string_view to_string(LogLevel level) {
  switch (level) {
    case LogLevel::Debug: return "debug";
    case LogLevel::Info: return "info";
    case LogLevel::Warn: return "warn";
    case LogLevel::Error: return "error";
    case LogLevel::Off: return "off";
  }
  return "?";
}

LogLevel parse_log_level(std::string_view text) {
  for (LogLevel l : {LogLevel::Debug, LogLevel::Info, LogLevel::Warn, LogLevel::Error, LogLevel::Off}) {
    if (text == to_string(l)) return l;
  }
  throw std::invalid_argument("log level '" + std::string(text) +
                              "' is not one of debug, info, warn, error, off");
}

namespace {
// One mutex per sink so that lines from several threads never interleave.
Logger::Sink stderr_sink() {
  auto mutex = std::make_shared<std::mutex>();
  return [mutex](const std::string& line) {
    std::lock_guard lock(*mutex);
    std::cerr << line << '\n';
  };
}
}  // namespace

Logger::Logger(std::string component, LogLevel level) : Logger(std::move(component), level, stderr_sink()) {}

Logger::Logger(std::string component, LogLevel level, Sink sink)
    : component_(std::move(component)), level_(level), sink_(std::make_shared<Sink>(std::move(sink))) {}

Logger Logger::child(std::string_view component) const {
  Logger copy = *this;
  copy.component_ = component_ + "." + std::string(component);
  return copy;
}

LogLine Logger::log(LogLevel level, Seconds t, std::string_view msg) const {
  if (!enabled(level)) return LogLine(nullptr, {});
  std::ostringstream prefix;
  prefix << "t=" << std::fixed << std::setprecision(3) << t << " level=" << to_string(level)
         << " component=" << component_ << " msg=" << std::quoted(std::string(msg));
  return LogLine(this, prefix.str());
}
LogLine Logger::info(Seconds t, std::string_view msg) const { return log(LogLevel::Info, t, msg); }
LogLine Logger::warn(Seconds t, std::string_view msg) const { return log(LogLevel::Warn, t, msg); }
LogLine Logger::error(Seconds t, std::string_view msg) const { return log(LogLevel::Error, t, msg); }
LogLine Logger::debug(Seconds t, std::string_view msg) const { return log(LogLevel::Debug, t, msg); }

void Logger::write(const std::string& line) const { (*sink_)(line); }

LogLine::LogLine(const Logger* logger, std::string prefix) : logger_(logger) { out_ << prefix; }

LogLine::~LogLine() {
  if (logger_) logger_->write(out_.str());
}

LogLine& LogLine::kv(std::string_view key, std::string_view value) {
  if (!logger_) return *this;
  bool plain = !value.empty() && value.find_first_of(" \"=\t\n") == std::string_view::npos;
  out_ << ' ' << key << '=';
  if (plain) {
    out_ << value;
  } else {
    out_ << std::quoted(std::string(value));
  }
  return *this;
}

bool RateLimiter::allow(std::string_view kind, Seconds t, std::size_t* suppressed) {
  std::lock_guard lock(mutex_);
  auto it = entries_.find(kind);
  if (it == entries_.end()) it = entries_.emplace(std::string(kind), Entry{}).first;
  Entry& e = it->second;
  if (t - e.last >= interval_) {
    if (suppressed) *suppressed = e.suppressed;
    e.last = t;
    e.suppressed = 0;
    return true;
  }
  ++e.suppressed;
  return false;
}

}  // namespace labo
