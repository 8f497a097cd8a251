#pragma once
// Who commanded what: an append-only file of JSON lines, one per command sent over the WebSocket and
// per administrative action over REST, each with the user, their role, the wall-clock time, what
// was asked and its result. Lines are only ever appended (the file is opened for appending and each
// line is flushed whole), so an admin reading it sees every line written before. Thread-safe.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

namespace labo::server {

struct AuditRecord {
  std::string user;
  std::string role;
  std::string action;  // "command", "take_over", "login", "user_add", "config_put", ...
  std::string target;  // what it acted on: the command's name, a user, an instrument id; may be empty
  bool accepted = false;
  std::string detail;  // the reason of a refusal, or what was done
};

struct AuditPage {
  std::size_t total = 0;           // lines in the log
  std::vector<std::string> lines;  // newest first, each one JSON object
};

class AuditLog {
 public:
  // Creates the file's folder. An empty path keeps no log (tests of other parts).
  explicit AuditLog(std::filesystem::path file);

  void record(const AuditRecord& record);
  // Lines [offset, offset + limit) counted from the newest.
  AuditPage read(std::size_t offset, std::size_t limit) const;
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  mutable std::mutex mutex_;
  std::ofstream out_;
};

}  // namespace labo::server
