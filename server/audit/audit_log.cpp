#include "server/audit/audit_log.hpp"

#include <chrono>
#include <ctime>
#include <nlohmann/json.hpp>

namespace labo::server {

namespace {

// ISO 8601 in UTC with milliseconds, e.g. "2026-01-31T14:05:09.123Z".
std::string utc_now_iso() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[40];
  const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof text - n, ".%03dZ", static_cast<int>(ms));
  return text;
}

}  // namespace

AuditLog::AuditLog(std::filesystem::path file) : file_(std::move(file)) {
  if (file_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(file_.parent_path(), ec);
  out_.open(file_, std::ios::app);
}

void AuditLog::record(const AuditRecord& r) {
  if (file_.empty()) return;
  const nlohmann::json line{{"time", utc_now_iso()}, {"user", r.user},     {"role", r.role},
                            {"action", r.action},    {"target", r.target}, {"result", r.accepted ? "accepted" : "refused"},
                            {"detail", r.detail}};
  // Invalid UTF-8 from a client (a user name, a reason) is replaced, never a reason to lose the line.
  const std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::lock_guard lock(mutex_);
  out_ << text;
  out_.flush();
}

AuditPage AuditLog::read(std::size_t offset, std::size_t limit) const {
  AuditPage page;
  if (file_.empty()) return page;
  std::vector<std::string> all;
  {
    std::lock_guard lock(mutex_);  // a line being written is never read half
    std::ifstream in(file_);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) all.push_back(std::move(line));
  }
  page.total = all.size();
  for (std::size_t i = offset; i < all.size() && page.lines.size() < limit; ++i) page.lines.push_back(std::move(all[all.size() - 1 - i]));
  return page;
}

}  // namespace labo::server
