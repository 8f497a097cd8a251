#pragma once
// The "server" section of the configuration: where to listen, the static pages, the users and their
// roles, the control queue's rules and the per-client limits that keep a slow viewer from costing
// memory. Read by read_server_settings(); validated like every other section.
#include <filesystem>
#include <string>
#include <vector>

#include "core/camera_config.hpp"
#include "core/config_reader.hpp"
#include "localization/face/face_config.hpp"

namespace labo::server {

enum class Role { Student, Teacher, Admin };
std::string to_string(Role role);
Role parse_role(const std::string& text);  // throws std::invalid_argument

struct UserAccount {
  std::string name;
  Role role = Role::Student;
  std::string password_hash;  // "pbkdf2-sha256$<iterations>$<salt b64>$<hash b64>"
};

struct ControlRules {
  double time_limit_s = 300;             // a student's turn
  std::vector<double> warnings_s{60, 10};  // warnings this long before the end of a turn
  double heartbeat_timeout_s = 10;       // a controller silent this long loses control
};

struct ClientLimits {
  int event_queue_messages = 64;   // queued JSON events per WebSocket client
  double backlog_timeout_s = 5;    // a queue full for this long disconnects the client
  int video_queue_frames = 10;     // H.264 access units queued per client before it drops to the next IDR
  double write_timeout_s = 10;     // one write pending this long disconnects the client
  double commands_per_s = 5;       // token bucket for WebSocket messages
  int command_burst = 10;
  int max_message_bytes = 4096;    // incoming WebSocket message
  std::size_t max_body_bytes = 8 * 1024 * 1024;  // HTTP request body (instrument photos)
  double login_attempts_per_min = 10;            // per remote address
  double session_idle_timeout_s = 8 * 3600;
  // An H.264 viewer this many seconds of stream behind moves to the low rendition; one that carried
  // it without lag for rendition_probe_after_s tries the drone's stream again (video/rendition_policy.hpp).
  double rendition_max_lag_s = 0.5;
  // The kernel's send buffer of each WebSocket (0: the kernel's own autotuning, which grows it to
  // megabytes: seconds of video a slow viewer would lag behind before its queue noticed).
  int send_buffer_bytes = 64 * 1024;
  double rendition_probe_after_s = 15;
};

struct VideoSettings {
  int jpeg_quality = 75;     // 1..100
  double telemetry_hz = 10;  // state messages to each client
  int low_rendition_kbps = 1000;  // the shared low rendition for viewers on slow links
};

// Several labs behind one front (docs/web.md "Several labs"): given on serve's command line by the
// scripts that start the labs (scripts/janus/run_labs.sh), not read from the configuration file.
struct MultiLabSettings {
  std::filesystem::path labs_file;         // the lab directory served at /api/labs; empty: this lab alone
  std::string lab_id;                      // this server's entry in it
  std::filesystem::path session_key_file;  // shared by the labs: a session of one is valid at all
};

// HTTPS and WSS on the same port when both files are set (PEM); the session cookie is then Secure.
struct TlsSettings {
  std::filesystem::path cert_file;  // the certificate chain
  std::filesystem::path key_file;   // its private key
  bool enabled() const { return !cert_file.empty(); }
};

// Faces registered from the teacher's page (docs/web.md "Registered people"): the "face" section
// (people_dir, the models, the registration's limits) and the front camera the photos are taken
// with. Filled from those sections by read_app_config(), not from "server".
struct PeopleSettings {
  face::FaceConfig face;
  CameraIntrinsics front_camera;
  bool enabled() const { return !face.people_dir.empty(); }
};

struct ServerSettings {
  std::string bind_address = "127.0.0.1";
  int port = 8080;
  int threads = 2;                        // io_context threads
  std::filesystem::path web_root;         // resolved against the config file's folder
  std::filesystem::path recordings_dir;   // flights recorded by the link, served for download
  std::filesystem::path instruments_dir;  // uploaded instrument templates
  std::filesystem::path audit_log;        // JSON lines: every command and administrative action
  std::filesystem::path sessions_file;    // the logged-in sessions, kept across restarts
  // The origin the pages are served from ("https://lab.example.org:8443"): a WebSocket upgrade from
  // a page of any other origin is refused. Empty: the origin must name the host the request names.
  std::string origin;
  TlsSettings tls;
  std::vector<UserAccount> users;
  ControlRules control;
  ClientLimits clients;
  VideoSettings video;
  MultiLabSettings multi_lab;
  PeopleSettings people;  // empty people_dir: the people routes answer 503
};

// Throws ConfigError naming the file, key path, value and expectation.
ServerSettings read_server_settings(const ConfigReader& server, const std::filesystem::path& base_dir);
ServerSettings default_server_settings(const std::filesystem::path& base_dir);

}  // namespace labo::server
