#include "server/api/lab_directory.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace labo::server {
namespace {

using Json = nlohmann::json;

[[noreturn]] void refuse(const std::string& source, const std::string& where, const std::string& what) {
  throw std::runtime_error("lab directory " + source + ": " + where + ": " + what);
}

void only_keys(const Json& obj, const std::set<std::string>& allowed, const std::string& source, const std::string& where) {
  for (const auto& [key, value] : obj.items())
    if (!allowed.contains(key)) {
      std::string list;
      for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
      refuse(source, where, "unknown key '" + key + "' (expected " + list + ")");
    }
}

std::string text_field(const Json& obj, const std::string& key, const std::regex& pattern, const std::string& expected,
                       const std::string& source, const std::string& where) {
  if (!obj.contains(key) || !obj[key].is_string()) refuse(source, where + "." + key, "missing or not a string (" + expected + ")");
  const std::string v = obj[key].get<std::string>();
  if (!std::regex_match(v, pattern)) refuse(source, where + "." + key, "'" + v + "': expected " + expected);
  return v;
}

Json read_janus(const Json& janus, const std::string& source, const std::string& where) {
  if (!janus.is_object()) refuse(source, where, "expected an object {url, mountpoint}");
  only_keys(janus, {"url", "mountpoint"}, source, where);
  const std::string url = text_field(janus, "url", std::regex(R"(wss?://\S+)"),
                                     "a ws:// or wss:// URL of Janus's WebSocket transport ({host}: the page's host)", source, where);
  if (!janus.contains("mountpoint") || !janus["mountpoint"].is_number_integer() || janus["mountpoint"].get<long long>() < 1 ||
      janus["mountpoint"].get<long long>() > 2147483647)
    refuse(source, where + ".mountpoint", "expected the streaming mount point's id, an integer from 1");
  return {{"url", url}, {"mountpoint", janus["mountpoint"].get<long long>()}};
}

}  // namespace

LabDirectory::LabDirectory(const std::filesystem::path& file, const std::string& self_id) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("lab directory " + file.string() + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  *this = parse(text.str(), self_id, file.string());
}

LabDirectory LabDirectory::parse(const std::string& text, const std::string& self_id, const std::string& source) {
  const Json doc = Json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) refuse(source, "top level", "not a JSON object {\"labs\": [...]}");
  only_keys(doc, {"labs"}, source, "top level");
  if (!doc.contains("labs") || !doc["labs"].is_array() || doc["labs"].empty())
    refuse(source, "labs", "expected a non-empty array of labs");
  Json labs = Json::array();
  std::set<std::string> ids;
  for (std::size_t i = 0; i < doc["labs"].size(); ++i) {
    const Json& lab = doc["labs"][i];
    const std::string where = "labs[" + std::to_string(i) + "]";
    if (!lab.is_object()) refuse(source, where, "expected an object {id, name, url, janus}");
    only_keys(lab, {"id", "name", "url", "janus"}, source, where);
    Json out;
    out["id"] = text_field(lab, "id", std::regex("[a-z0-9_-]{1,32}"), "1 to 32 of a-z, 0-9, _ and -", source, where);
    if (!ids.insert(out["id"].get<std::string>()).second) refuse(source, where + ".id", "'" + out["id"].get<std::string>() + "' twice");
    out["name"] = text_field(lab, "name", std::regex(".{1,80}"), "a name of 1 to 80 characters", source, where);
    out["url"] = text_field(lab, "url", std::regex(R"(https?://\S+)"), "an http:// or https:// URL of the lab's pages", source, where);
    if (lab.contains("janus")) out["janus"] = read_janus(lab["janus"], source, where + ".janus");
    labs.push_back(std::move(out));
  }
  if (!ids.contains(self_id))
    throw std::runtime_error("lab directory " + source + ": this lab's id '" + self_id + "' (--lab-id) is not one of its labs");
  LabDirectory d;
  d.json_ = std::make_shared<const std::string>(Json{{"self", self_id}, {"labs", labs}}.dump());
  return d;
}

}  // namespace labo::server
