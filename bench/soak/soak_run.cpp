#include "bench/soak/soak_run.hpp"

#include <algorithm>
#include <boost/asio/executor_work_guard.hpp>
#include <thread>

#include "bench/soak/recording_check.hpp"
#include "bench/soak/soak_audience.hpp"
#include "bench/soak/soak_script.hpp"
#include "bench/soak/soak_server.hpp"
#include "bench/soak/soak_watch.hpp"

namespace labo::bench {

using server::AppConfig;
using server::Role;
using server::ServerMetrics;
using server::load_app_config;


namespace {

constexpr double kProbeEvery_s = 5;

// The students of the configuration, logged in with the demo accounts' password convention.
std::vector<Student> log_students_in(const AppConfig& config, unsigned short port) {
  std::vector<Student> students;
  for (const auto& user : config.server.users) {
    if (user.role != Role::Student) continue;
    const std::string password = user.name + "-pass";
    const std::string cookie = login(port, user.name, password);
    if (cookie.empty())
      throw std::runtime_error("soak: " + user.name + " cannot log in with '" + password +
                               "' (the soak logs the configuration's students in with the demo accounts' passwords)");
    students.push_back({user.name, cookie});
  }
  if (students.empty()) throw std::runtime_error("soak: the configuration has no student (server.users)");
  return students;
}

// The configuration's first admin (the lab's staff: sets the drone on its platform when asked).
Student log_admin_in(const AppConfig& config, unsigned short port) {
  for (const auto& user : config.server.users) {
    if (user.role != Role::Admin) continue;
    const std::string password = user.name + "-pass";
    const std::string cookie = login(port, user.name, password);
    if (cookie.empty())
      throw std::runtime_error("soak: admin " + user.name + " cannot log in with '" + password + "'");
    return {user.name, cookie};
  }
  throw std::runtime_error("soak: the configuration has no admin (server.users): nobody could set the drone down");
}

}  // namespace

SoakSummary run_soak(const SoakOptions& o) {
  AppConfig config = load_app_config(o.config_file);
  config.sim.lab.seed = o.seed;
  config.sim.link.seed = o.seed;
  const double total_s = o.minutes * 60.0;
  SoakSummary s;
  SoakServer server(config, o.config_file, o.recording, Logger("soak", o.log_level));
  boost::asio::io_context io;  // every client's WebSocket, on one thread as a page's would be
  auto work = boost::asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  {
    SoakWatch watch(server.drone(), server.flight(), server.port(), kProbeEvery_s);
    const std::vector<Student> students = log_students_in(config, server.port());
    std::vector<std::string> cookies;
    for (const auto& st : students) cookies.push_back(st.cookie);
    AudienceOptions audience_options;
    audience_options.max_spectators = o.max_spectators;
    audience_options.slow_stall_s = o.slow_stall_s;
    audience_options.seed = o.seed;
    SoakAudience audience(io, server.port(), cookies, audience_options);
    ScriptOptions script_options;
    script_options.total_s = total_s;
    // A short soak (the test suite's) gives up on a mission sooner, so that it ends in minutes.
    script_options.mission_timeout_s = std::clamp(total_s / 2, 90.0, 180.0);
    SoakScript script(server, watch, io, config, students, log_admin_in(config, server.port()), script_options);
    script.run();
    audience.stop();
    script.report(s);
    s.duration_s = watch.elapsed_s();
    s.ended_landed = !server.drone().truth().airborne;
    s.timing = server.flight().timing();
    watch.stop();
    s.health_probes = watch.health_probes();
    s.health_failures = watch.health_failures();
    s.longest_unmanaged_flight_s = watch.longest_unmanaged_flight_s();
    s.crashes = watch.crashes();
    s.crash_reports = watch.crash_reports();
    summarise_memory(watch.rss(), total_s, s);
    const AudienceCounts a = audience.counts();
    s.spectators_joined = a.spectators_joined;
    s.slow_reader_stalls = a.slow_reader_stalls;
    s.slow_reader_cut_off = a.slow_reader_cut_off;
    s.frames_received = a.frames_received;
    s.logins = students.size();
  }
  const ServerMetrics& m = server.metrics();
  s.http_5xx = m.http_errors_5xx;
  s.ws_connections = m.ws_connections_total;
  s.frames_sent = m.ws_frames_out + m.ws_units_out;
  s.frames_skipped = m.ws_frames_skipped + m.ws_units_skipped;
  s.slow_disconnects = m.ws_slow_disconnects;
  server.shutdown(15.0);
  work.reset();
  io.stop();
  io_thread.join();

  s.recording_reported_bytes = server.recorded_bytes();
  const RecordingCheck r = check_recording(o.recording);
  s.recording_file_bytes = r.file_bytes;
  s.replay_records = r.records;
  s.replay_navdata = r.navdata;
  s.replay_frames = r.frames;
  s.replay_to_end = r.read_to_end;
  s.replay_error = r.error;
  if (!o.keep_recording) std::filesystem::remove(o.recording);
  return s;
}

}  // namespace labo::bench
