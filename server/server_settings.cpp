#include "server/server_settings.hpp"

#include <set>
#include <stdexcept>

#include "server/auth/password_hash.hpp"

namespace labo::server {

std::string to_string(Role role) {
  switch (role) {
    case Role::Student: return "student";
    case Role::Teacher: return "teacher";
    case Role::Admin: return "admin";
  }
  return "student";
}

Role parse_role(const std::string& text) {
  if (text == "student") return Role::Student;
  if (text == "teacher") return Role::Teacher;
  if (text == "admin") return Role::Admin;
  throw std::invalid_argument("'" + text + "' is not a role (student, teacher, admin)");
}

namespace {

std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? path : (base / path).lexically_normal();
}

std::vector<UserAccount> read_users(const ConfigReader& server) {
  std::vector<UserAccount> users;
  std::set<std::string> names;
  for (const ConfigReader& u : server.objects("users")) {
    UserAccount account;
    account.name = u.string("name");
    if (account.name.empty() || account.name.size() > 64) u.fail("name", "must be 1 to 64 characters");
    if (!names.insert(account.name).second) u.fail("name", "'" + account.name + "' appears twice");
    account.role = parse_role(u.choice("role", {"student", "teacher", "admin"}));
    account.password_hash = u.string("password_hash");
    if (!PasswordHash::parse(account.password_hash))
      u.fail("password_hash", "expected pbkdf2-sha256$<iterations >= 10000>$<salt base64>$<hash base64> "
                              "(make one with `labodrone hash-password`)");
    u.finish();
    users.push_back(std::move(account));
  }
  return users;
}

ControlRules read_control_rules(const ConfigReader& c) {
  ControlRules r;
  r.time_limit_s = c.number_or("time_limit_s", r.time_limit_s, Range::closed(10, 24 * 3600));
  if (c.has("warnings_s")) r.warnings_s = c.numbers("warnings_s", -1, Range::positive());
  for (double w : r.warnings_s)
    if (w >= r.time_limit_s) c.fail("warnings_s", "every warning must come before the end of the turn (< time_limit_s)");
  r.heartbeat_timeout_s = c.number_or("heartbeat_timeout_s", r.heartbeat_timeout_s, Range::closed(1, 600));
  c.finish();
  return r;
}

ClientLimits read_client_limits(const ConfigReader& c) {
  ClientLimits l;
  l.event_queue_messages = c.integer_or("event_queue_messages", l.event_queue_messages, 4, 4096);
  l.video_queue_frames = c.integer_or("video_queue_frames", l.video_queue_frames, 2, 120);
  l.backlog_timeout_s = c.number_or("backlog_timeout_s", l.backlog_timeout_s, Range::closed(0.5, 600));
  l.write_timeout_s = c.number_or("write_timeout_s", l.write_timeout_s, Range::closed(0.5, 600));
  l.commands_per_s = c.number_or("commands_per_s", l.commands_per_s, Range::closed(0.1, 1000));
  l.command_burst = c.integer_or("command_burst", l.command_burst, 1, 10000);
  l.max_message_bytes = c.integer_or("max_message_bytes", l.max_message_bytes, 256, 1 << 20);
  l.max_body_bytes = static_cast<std::size_t>(
      c.integer_or("max_body_bytes", static_cast<int>(l.max_body_bytes), 1024, 256 * 1024 * 1024));
  l.login_attempts_per_min = c.number_or("login_attempts_per_min", l.login_attempts_per_min, Range::closed(1, 10000));
  l.session_idle_timeout_s = c.number_or("session_idle_timeout_s", l.session_idle_timeout_s, Range::closed(60, 30 * 86400));
  l.rendition_max_lag_s = c.number_or("rendition_max_lag_s", l.rendition_max_lag_s, Range::closed(0.1, 10));
  l.send_buffer_bytes = c.integer_or("send_buffer_bytes", l.send_buffer_bytes, 0, 64 << 20);
  l.rendition_probe_after_s = c.number_or("rendition_probe_after_s", l.rendition_probe_after_s, Range::closed(1, 600));
  c.finish();
  return l;
}

VideoSettings read_video_settings(const ConfigReader& c) {
  VideoSettings v;
  v.jpeg_quality = c.integer_or("jpeg_quality", v.jpeg_quality, 1, 100);
  v.telemetry_hz = c.number_or("telemetry_hz", v.telemetry_hz, Range::closed(1, 50));
  v.low_rendition_kbps = c.integer_or("low_rendition_kbps", v.low_rendition_kbps, 100, 4000);
  c.finish();
  return v;
}

TlsSettings read_tls_settings(const ConfigReader& c, const std::filesystem::path& base_dir) {
  TlsSettings t;
  t.cert_file = resolve(base_dir, c.string("cert_file"));
  t.key_file = resolve(base_dir, c.string("key_file"));
  for (const auto& [key, file] : {std::pair{"cert_file", t.cert_file}, std::pair{"key_file", t.key_file}})
    if (!std::filesystem::is_regular_file(file)) c.fail(key, "no such file: " + file.string() + " (expected a PEM file)");
  c.finish();
  return t;
}

std::string read_origin(const ConfigReader& server) {
  std::string origin = server.string_or("origin", "");
  while (!origin.empty() && origin.back() == '/') origin.pop_back();
  const bool scheme = origin.rfind("http://", 0) == 0 || origin.rfind("https://", 0) == 0;
  if (!origin.empty() && (!scheme || origin.find('/', origin.find("//") + 2) != std::string::npos))
    server.fail("origin", "expected scheme://host[:port], e.g. https://lab.example.org:8443 (or leave it out)");
  return origin;
}

}  // namespace

ServerSettings default_server_settings(const std::filesystem::path& base_dir) {
  ServerSettings s;
  s.web_root = resolve(base_dir, "../web");
  s.recordings_dir = resolve(base_dir, "../var/recordings");
  s.instruments_dir = resolve(base_dir, "../var/instruments");
  s.audit_log = resolve(base_dir, "../var/audit.jsonl");
  s.sessions_file = resolve(base_dir, "../var/sessions.json");
  return s;
}

ServerSettings read_server_settings(const ConfigReader& server, const std::filesystem::path& base_dir) {
  ServerSettings s = default_server_settings(base_dir);
  s.bind_address = server.string_or("bind", s.bind_address);
  s.port = server.integer_or("port", s.port, 1, 65535);
  s.threads = server.integer_or("threads", s.threads, 1, 64);
  s.web_root = resolve(base_dir, server.string_or("web_root", "../web"));
  s.recordings_dir = resolve(base_dir, server.string_or("recordings_dir", "../var/recordings"));
  s.instruments_dir = resolve(base_dir, server.string_or("instruments_dir", "../var/instruments"));
  s.audit_log = resolve(base_dir, server.string_or("audit_log", "../var/audit.jsonl"));
  s.sessions_file = resolve(base_dir, server.string_or("sessions_file", "../var/sessions.json"));
  s.origin = read_origin(server);
  if (server.has("tls")) s.tls = read_tls_settings(server.object("tls"), base_dir);
  if (server.has("users")) s.users = read_users(server);
  if (server.has("control")) s.control = read_control_rules(server.object("control"));
  if (server.has("clients")) s.clients = read_client_limits(server.object("clients"));
  if (server.has("video")) s.video = read_video_settings(server.object("video"));
  server.finish();
  return s;
}

}  // namespace labo::server
