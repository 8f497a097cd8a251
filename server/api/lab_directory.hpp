#pragma once
// The labs of one front (docs/web.md "Several labs"): a JSON file listing each lab's id, name, page
// URL and, when its video also goes through Janus, the Janus server and mount point. Every lab's
// server reads the same file and answers GET /api/labs with it and its own id, so any lab's page can
// list the others and find its own mount point. Validated once at start-up.
#include <filesystem>
#include <memory>
#include <string>

namespace labo::server {

class LabDirectory {
 public:
  // No file: this lab alone ({"self": null, "labs": []}).
  LabDirectory() = default;
  // Throws std::runtime_error naming the file, the entry and the field, with what was expected; or
  // when `self_id` is not one of the labs.
  LabDirectory(const std::filesystem::path& file, const std::string& self_id);
  static LabDirectory parse(const std::string& text, const std::string& self_id, const std::string& source);

  // {"self": ID, "labs": [{"id", "name", "url", "janus": {"url", "mountpoint"} | absent}]}
  const std::string& json() const { return *json_; }

 private:
  std::shared_ptr<const std::string> json_ = std::make_shared<const std::string>(R"({"self":null,"labs":[]})");
};

}  // namespace labo::server
