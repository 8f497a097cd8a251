// The soak of `labodrone serve` under faults (bench/soak/): its checks, each shown failing on a
// summary that breaks it, and a short soak on the simulated lab that must pass them all.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "bench/soak/sim_soak_command.hpp"
#include "bench/soak/soak_run.hpp"
#include "core/source_tree.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

// A summary that passes every check.
SoakSummary passing() {
  SoakSummary s;
  s.health_probes = 10;
  s.faults = {{"link_cut", 30, 3, true, "mission inspect", ""},
              {"emulator_restart", 60, 3, true, "landed", ""},
              {"link_cut", 90, 8, true, "landed", ""},
              {"low_battery", 120, 40, false, "landed", "mission 'inspect' ended: safety: battery 19 % below 20 %"}};
  s.ended_landed = true;
  s.missions_accepted = 3;
  s.frames_received = 100;
  s.recording_reported_bytes = s.recording_file_bytes = 1000;
  s.replay_to_end = true;
  s.rss_samples = 10;
  s.rss_growth_percent = 1;
  s.net_warmup_level_mib = 400;
  s.net_end_level_mib = 404;
  s.net_growth_percent = 1;
  return s;
}

bool fails_with(const SoakSummary& s, const std::string& words) {
  for (const auto& f : soak_failures(s, SoakLimits{}))
    if (f.find(words) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("sim soak: bad options are refused naming what was expected", "[soak]") {
  const auto run = [](std::vector<std::string> args) {
    return run_sim_soak_command(parse_args(sim_soak_command_spec(), args));
  };
  CHECK_THROWS_WITH(run({"--minutes", "0"}), Catch::Contains("--minutes"));
  CHECK_THROWS_WITH(run({"--log", "loud"}), Catch::Contains("--log"));
  CHECK_THROWS_WITH(run({"--config", "/nonexistent/config.json"}), Catch::Contains("no such file"));
}

TEST_CASE("soak checks: each check fails on a summary that breaks it", "[soak]") {
  CHECK(soak_failures(passing(), SoakLimits{}).empty());
  CHECK(service_failures(passing(), SoakLimits{}).empty());
  CHECK(flight_failures(passing(), SoakLimits{}).empty());
  SoakSummary s = passing();
  s.health_failures = 1;
  CHECK(fails_with(s, "did not stay up"));
  s = passing();
  s.http_5xx = 2;
  CHECK(fails_with(s, "5xx"));
  s = passing();
  s.faults.erase(s.faults.begin());
  CHECK(fails_with(s, "link cuts applied: 1, expected 2"));
  s = passing();
  s.faults[1].after = "flying without a mission";
  CHECK(fails_with(s, "emulator_restart at 60 s: the drone was flying without a mission once it was over"));
  s = passing();
  s.faults[3].after = "mission return_home";
  CHECK(fails_with(s, "did not land"));
  s = passing();
  s.faults[3].detail = "mission 'inspect' ended: succeeded";
  CHECK(fails_with(s, "did not end for the battery"));
  s = passing();
  s.longest_unmanaged_flight_s = 30;
  CHECK(fails_with(s, "without a mission (limit 15.0 s)"));
  s = passing();
  s.ended_landed = false;
  CHECK(fails_with(s, "not landed at the end"));
  s = passing();
  s.crashes = 1;
  CHECK(fails_with(s, "crashes"));
  s = passing();
  s.recording_file_bytes = 999;
  CHECK(fails_with(s, "999 bytes on disk, the writer reported 1000"));
  s = passing();
  s.replay_to_end = false;
  s.replay_error = "the last record is cut short";
  CHECK(fails_with(s, "cut short"));
  s = passing();
  s.net_growth_percent = 5.5;
  CHECK(fails_with(s, "memory grew 5.5 % after warm-up beyond the SLAM map's"));
  s = passing();
  s.net_end_level_mib = 0;  // no sample after warm-up: nothing to judge, not a pass
  CHECK(fails_with(s, "memory: too few samples to judge its level"));
  s = passing();
  s.rss_growth_percent = 40;  // all of it the SLAM map filling up: bounded, not a leak
  CHECK(soak_failures(s, SoakLimits{}).empty());
  s = passing();
  s.frames_received = 0;
  CHECK(fails_with(s, "no client received a frame"));
}

// The check judges levels, not peaks: a solve or a burst of frames at one sample is not growth, the
// SLAM map filling up is bounded, and a leak raises the last quarter's level.
TEST_CASE("soak checks: memory is judged by its levels: transient peaks and the SLAM map pass, a steady leak fails", "[soak]") {
  auto run = [](double leak_mib_per_min) {
    std::vector<RssSample> rss;
    for (int i = 0; i <= 360; ++i) {  // 30 minutes, a sample every 5 s
      const double t = 5.0 * i;
      const double map = std::min(180.0, 0.1 * t);  // fills up over the first 30 minutes' half
      const double transient = i % 37 == 0 ? 150.0 : 0.0;
      rss.push_back({t, 360.0 + map + transient + leak_mib_per_min * t / 60.0, 250.0 + map, 300.0 + map, map});
    }
    SoakSummary s;
    summarise_memory(rss, 1800.0, s);
    return s;
  };
  const SoakSummary flat = run(0);
  CHECK(flat.warmup_s == 300);
  CHECK(flat.net_growth_percent < 0.1);
  CHECK(flat.net_peak_growth_percent < 0.1);  // the same transient in both spans
  CHECK(flat.rss_growth_percent > 20);        // the map
  SoakSummary s = passing();
  s.net_growth_percent = flat.net_growth_percent;
  CHECK(soak_failures(s, SoakLimits{}).empty());
  const SoakSummary leaking = run(1.0);  // 1 MiB a minute: ~6 % over the last 22 minutes
  CHECK(leaking.net_growth_percent > 5);
  s.net_growth_percent = leaking.net_growth_percent;
  CHECK(fails_with(s, "memory grew"));
}

TEST_CASE("soak report: a crash is reported with the flight before it, the estimate beside the truth", "[soak]") {
  SoakSummary s = passing();
  s.crashes = 1;
  CrashReport crash{42, "wall_xmin", "inspect", {}};
  for (int i = 0; i < 3; ++i) {
    TrailPoint p;
    p.t_s = 39 + i;
    p.truth.x_m = -0.5 - 0.4 * i;  // the drone flying into the wall while it believes itself still
    p.estimate.x_m = -0.5;
    p.stage = "1 init: taking off";
    p.source = "slam";
    p.slam = "tracking";
    crash.trail.push_back(p);
  }
  s.crash_reports.push_back(crash);
  const std::string text = to_text(s, soak_failures(s, SoakLimits{}));
  CHECK_THAT(text, Catch::Contains("crash at 42 s into wall_xmin during inspect (1 init: taking off; slam, SLAM tracking)"));
  CHECK_THAT(text, Catch::Contains("the estimate 0.80 m off the truth at the crash, at most 0.80 m over the 3 s before"));
  const nlohmann::json j = to_json(s, soak_failures(s, SoakLimits{}));
  const nlohmann::json& report = j.at("drone").at("crash_reports").at(0);
  CHECK(report.at("hit") == "wall_xmin");
  CHECK(report.at("trail").size() == 3);
  CHECK(report.at("trail").at(2).at("true").at(0).get<double>() == Approx(-1.3));
  CHECK(report.at("trail").at(2).at("estimate").at(0).get<double>() == Approx(-0.5));
  CHECK_FALSE(report.at("trail").at(0).contains("desired"));
}

TEST_CASE("sim soak: three minutes of serve under link cuts, an emulator restart and a low battery pass the service's checks",
          "[soak][sim]") {
  SoakOptions o;
  o.config_file = source_root() / "config" / "default.json";
  o.minutes = 3;
  o.max_spectators = 2;
  o.slow_stall_s = 30;
  o.recording = std::filesystem::temp_directory_path() / ("labo_soak_test_" + std::to_string(::getpid()) + ".laborec");
  o.log_level = LogLevel::Error;
  const SoakSummary s = run_soak(o);
  INFO(to_text(s, soak_failures(s, SoakLimits{})));
  // Three minutes are too few for memory to settle (the first flights size the SLAM map, the face
  // models load on the first find-teacher, a crash restarts the flight software): here the check
  // only catches a gross leak; the 5 % target is the 30-minute command's.
  SoakLimits limits;
  limits.rss_growth_percent = 60;
  CHECK(service_failures(s, limits).empty());
  // The flight's checks are reported, not required here: the flight software does not yet come
  // through every fault (docs/realtime.md, "Known limits"); `labodrone-bench sim soak` fails on them.
  for (const auto& f : flight_failures(s, SoakLimits{})) WARN("flight check failed: " << f);
  CHECK(s.faults.size() >= 4);
  CHECK(s.ws_connections >= 4);  // the students' turns, spectators and the slow reader
  CHECK(s.slow_reader_stalls >= 1);
  CHECK(s.replay_frames > 1000);
}
