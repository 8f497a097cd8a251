#include "bench/realtime/sim_realtime_command.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "bench/realtime/realtime_campaign.hpp"
#include "core/source_tree.hpp"

namespace labo::bench {

using server::Percentiles;


namespace {

nlohmann::json to_json(const Percentiles& p) {
  return {{"count", p.count}, {"median", p.median}, {"p95", p.p95}, {"p99", p.p99}, {"max", p.max}};
}

nlohmann::json to_json(const RealtimeRun& r) {
  return {{"seed", r.seed},
          {"round", r.round},
          {"instrument", r.instrument},
          {"success", r.success},
          {"result", r.result},
          {"duration_s", r.duration_s},
          {"landed", r.landed},
          {"landing_error_m", r.landing_error_m},
          {"following", r.following},
          {"tick_interval_ms", to_json(r.timing.tick_interval_ms)},
          {"vision_latency_ms", to_json(r.timing.vision_latency_ms)},
          {"vision_latency_tracking_ms", to_json(r.timing.vision_latency_tracking_ms)},
          {"vision_run_ms", to_json(r.timing.vision_run_ms)},
          {"frames_in", r.timing.frames_in},
          {"frames_to_vision", r.timing.frames_to_vision},
          {"frames_skipped", r.timing.frames_skipped},
          {"vision_failures", r.timing.vision_failures}};
}

// The worst of the runs' percentiles (a campaign is as good as its worst run).
double worst(const std::vector<RealtimeRun>& runs, double (*of)(const RealtimeRun&)) {
  double w = 0;
  for (const auto& r : runs) w = std::max(w, of(r));
  return w;
}

std::string line(const char* format, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

}  // namespace

const CommandSpec& sim_realtime_command_spec() {
  static const CommandSpec spec{
      "sim realtime",
      "",
      "Missions flown in real time through labodrone serve's threads on the simulated lab: success and control-loop timing.",
      {{"--mission", "inspect|find-teacher", "the mission each run flies (default inspect)"},
       {"--runs", "N", "runs, one after another (default 1)"},
       {"--seed", "N", "first seed of the simulated lab (default 1); run i uses seed + i"},
       {"--instrument", "ID", "inspect: the instrument (default: the lab's first)"},
       {"--hold", "S", "inspect: the hold in front of the panel (default 5 s)"},
       {"--follow", "S", "find-teacher: how long to follow once found (default 20 s)"},
       {"--in-a-row", "K", "missions flown one after another on each run's server, the map, battery and place kept (default 1)"},
       {"--trace", "FILE", "write a CSV of every mission: telemetry 5 times a second and the log lines"},
       {"--timeout", "S", "a run that has not ended by then fails (default 180 s)"},
       {"--config", "FILE", "configuration (default: config/default.json)"},
       {"--json", "", "print the result as JSON"}},
      0,
      0};
  return spec;
}

int run_sim_realtime_command(const ParsedArgs& args) {
  RealtimeCampaignOptions o;
  const std::string mission = args.value_or("--mission", "inspect");
  if (mission != "inspect" && mission != "find-teacher")
    throw UsageError("--mission must be inspect or find-teacher (got '" + mission + "')");
  o.mission = mission == "inspect" ? RealtimeMission::Inspect : RealtimeMission::FindTeacher;
  o.runs = args.integer_or("--runs", 1, 1, 1000);
  o.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  o.instrument = args.value_or("--instrument", "");
  o.hold_s = args.number_or("--hold", 5.0, 0.0, 600.0);
  o.follow_s = args.number_or("--follow", 20.0, 1.0, 3600.0);
  o.timeout_s = args.number_or("--timeout", 180.0, 10.0, 3600.0);
  o.in_a_row = args.integer_or("--in-a-row", 1, 1, 100);
  o.trace_file = args.value_or("--trace", "");
  o.config_file = args.value_or("--config", (source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(o.config_file)) throw UsageError("--config " + o.config_file + ": no such file");

  const std::vector<RealtimeRun> runs = run_realtime_campaign(o);
  const auto ok = std::count_if(runs.begin(), runs.end(), [](const RealtimeRun& r) { return r.success; });
  const double tick_p99 = worst(runs, [](const RealtimeRun& r) { return r.timing.tick_interval_ms.p99; });
  const double latency_p95 = worst(runs, [](const RealtimeRun& r) { return r.timing.vision_latency_ms.p95; });
  const double tracking_p95 = worst(runs, [](const RealtimeRun& r) { return r.timing.vision_latency_tracking_ms.p95; });
  const auto missions = static_cast<long>(runs.size());
  if (args.flag("--json")) {
    nlohmann::json per_run = nlohmann::json::array();
    for (const auto& r : runs) per_run.push_back(to_json(r));
    std::cout << nlohmann::json{{"experiment", "sim realtime"},
                                {"mission", mission},
                                {"seed", o.seed},
                                {"runs", o.runs},
                                {"in_a_row", o.in_a_row},
                                {"missions", missions},
                                {"succeeded", ok},
                                {"worst_tick_interval_p99_ms", tick_p99},
                                {"worst_vision_latency_p95_ms", latency_p95},
                                {"worst_vision_latency_tracking_p95_ms", tracking_p95},
                                {"per_run", per_run}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << mission << " in real time: " << ok << "/" << missions << " missions succeeded\n"
              << line("control tick interval p99 %.1f ms at worst (nominal period 20 ms; target <= 30)\n", tick_p99)
              << line("vision latency, capture to estimate, p95 %.1f ms at worst; ", latency_p95)
              << line("of the frames with a target tracked %.1f ms (target <= 60)\n", tracking_p95);
    for (const auto& r : runs)
      std::cout << "  seed " << r.seed << (o.in_a_row > 1 ? " mission " + std::to_string(r.round + 1) : "")
                << (r.instrument.empty() ? "" : " " + r.instrument) << (r.success ? " ok: " : " FAILED: ") << r.result
                << line(" (%.0f s; ticks median %.1f ms p99 %.1f ms; ", r.duration_s, r.timing.tick_interval_ms.median,
                        r.timing.tick_interval_ms.p99)
                << line("vision latency median %.1f ms p95 %.1f ms, ", r.timing.vision_latency_ms.median, r.timing.vision_latency_ms.p95)
                << line("tracking p95 %.1f ms; ", r.timing.vision_latency_tracking_ms.p95)
                << r.timing.frames_skipped << " of " << r.timing.frames_in << " frames skipped)\n";
  }
  return ok == missions ? 0 : 3;
}

}  // namespace labo::bench
