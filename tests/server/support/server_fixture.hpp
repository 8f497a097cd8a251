#pragma once
// A WebServer on a free loopback port over a ScriptedFlight, with four users and its own temporary
// config file and folders. Tests only.
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "server/app_config.hpp"
#include "server/auth/password_hash.hpp"
#include "server/http/web_server.hpp"
#include "tests/server/support/scripted_flight.hpp"
#include "core/source_tree.hpp"

namespace labo::server::test {

inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("labo_web_" + name + "_" + random_hex(4));
  std::filesystem::create_directories(dir);
  return dir;
}

struct ServerFixture {
  explicit ServerFixture(const std::function<void(ServerSettings&)>& tweak = {}) : dir(fresh_temp_dir("srv")) {
    // A config file the PUT /api/config tests may overwrite: a copy of the default one.
    std::filesystem::create_directories(dir / "config");
    config_file = dir / "config" / "default.json";
    std::filesystem::copy_file(default_config_path(), config_file);
    // The lab description it names (validated with the config) and its panels' templates.
    const auto source_config = default_config_path().parent_path();
    std::filesystem::copy_file(source_config / "lab.json", dir / "config" / "lab.json");
    std::filesystem::copy(source_config / "instruments", dir / "config" / "instruments");
    settings = default_server_settings(dir / "config");
    settings.port = 0;
    settings.web_root = labo::source_root() / "web";
    std::filesystem::create_directories(settings.recordings_dir);
    std::ofstream(settings.recordings_dir / "flight1.ldrec") << "recorded bytes";
    const auto user = [](const std::string& name, Role role) {
      return UserAccount{name, role, PasswordHash::create(name + "-pw", PasswordHash::kMinIterations).encode()};
    };
    settings.users = {user("alice", Role::Student), user("bob", Role::Student), user("tess", Role::Teacher), user("root", Role::Admin)};
    if (tweak) tweak(settings);
    write_users_to_config();
    server = std::make_unique<WebServer>(settings, config_file, flight, Logger("test", LogLevel::Warn));
    port = server->start();
  }
  ~ServerFixture() {
    server.reset();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }

  // The config file names the same users as `settings`, as it does when the server reads its users
  // from it: the admin's user routes edit that file.
  void write_users_to_config() {
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(config_file));
    doc["server"]["users"] = nlohmann::json::array();
    for (const UserAccount& u : settings.users)
      doc["server"]["users"].push_back({{"name", u.name}, {"role", to_string(u.role)}, {"password_hash", u.password_hash}});
    std::ofstream(config_file) << doc.dump(2) << "\n";
  }

  std::filesystem::path dir, config_file;
  ServerSettings settings;
  ScriptedFlight flight;
  std::unique_ptr<WebServer> server;
  unsigned short port = 0;
};

// The audit log's entries as "action target ok|refused", oldest first.
inline std::vector<std::string> audit_actions(const ServerFixture& f) {
  std::vector<std::string> out;
  std::ifstream in(f.settings.audit_log);
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    out.push_back(j.value("action", "") + " " + j.value("target", "") + " " + (j.value("result", "") == "accepted" ? "ok" : "refused"));
  }
  return out;
}

}  // namespace labo::server::test
