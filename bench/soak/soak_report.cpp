#include "bench/soak/soak_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace labo::bench {

using server::Percentiles;


namespace {

int count_kind(const SoakSummary& s, const std::string& kind) {
  return static_cast<int>(std::count_if(s.faults.begin(), s.faults.end(), [&](const FaultRecord& f) { return f.kind == kind; }));
}

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// RSS less the SLAM map at its level in two spans: the warm-up's second half, by when every pool
// and cache has been sized once, and the run's last quarter. A leak raises the second level.
void summarise_memory_levels(const std::vector<RssSample>& rss, SoakSummary& s) {
  if (rss.empty()) return;
  const double end_from_s = 0.75 * rss.back().t_s;
  std::vector<double> warmup, end;
  for (const auto& r : rss) {
    if (r.t_s > 0.5 * s.warmup_s && r.t_s <= s.warmup_s) warmup.push_back(r.mib - r.slam_map_mib);
    if (r.t_s > s.warmup_s && r.t_s >= end_from_s) end.push_back(r.mib - r.slam_map_mib);
  }
  s.net_warmup_level_mib = median(warmup);
  s.net_end_level_mib = median(end);
  if (s.net_warmup_level_mib > 0 && s.net_end_level_mib > 0)
    s.net_growth_percent = std::max(0.0, 100.0 * (s.net_end_level_mib / s.net_warmup_level_mib - 1.0));
}

}  // namespace

// Memory after warm-up against the warm-up's: the first quarter of the soak (at most five minutes)
// sizes every pool and cache once. Peaks are reported beside the levels the check judges.
void summarise_memory(const std::vector<RssSample>& rss, double total_s, SoakSummary& s) {
  s.rss_samples = static_cast<int>(rss.size());
  s.warmup_s = std::min(300.0, 0.25 * total_s);
  for (const auto& r : rss) {
    const auto minute = static_cast<std::size_t>(r.t_s / 60.0);
    if (s.rss_per_minute_mib.size() <= minute) {
      s.rss_per_minute_mib.resize(minute + 1, 0.0);
      s.heap_in_use_per_minute_mib.resize(minute + 1, 0.0);
      s.heap_held_per_minute_mib.resize(minute + 1, 0.0);
      s.slam_map_per_minute_mib.resize(minute + 1, 0.0);
    }
    s.slam_map_per_minute_mib[minute] = r.slam_map_mib;
    double& net_peak = r.t_s <= s.warmup_s ? s.net_warmup_peak_mib : s.net_after_peak_mib;
    net_peak = std::max(net_peak, r.mib - r.slam_map_mib);
    double& in_use_peak = r.t_s <= s.warmup_s ? s.in_use_net_warmup_peak_mib : s.in_use_net_after_peak_mib;
    in_use_peak = std::max(in_use_peak, r.heap_in_use_mib - r.slam_map_mib);
    s.rss_per_minute_mib[minute] = r.mib;
    s.heap_in_use_per_minute_mib[minute] = r.heap_in_use_mib;
    s.heap_held_per_minute_mib[minute] = r.heap_held_mib;
    double& peak = r.t_s <= s.warmup_s ? s.rss_warmup_peak_mib : s.rss_after_peak_mib;
    peak = std::max(peak, r.mib);
  }
  if (!rss.empty()) s.rss_final_mib = rss.back().mib;
  if (s.rss_warmup_peak_mib > 0 && s.rss_after_peak_mib > 0)
    s.rss_growth_percent = std::max(0.0, 100.0 * (s.rss_after_peak_mib / s.rss_warmup_peak_mib - 1.0));
  if (s.net_warmup_peak_mib > 0 && s.net_after_peak_mib > 0)
    s.net_peak_growth_percent = std::max(0.0, 100.0 * (s.net_after_peak_mib / s.net_warmup_peak_mib - 1.0));
  summarise_memory_levels(rss, s);
}

std::vector<std::string> service_failures(const SoakSummary& s, const SoakLimits& limits) {
  std::vector<std::string> f;
  if (s.health_probes == 0 || s.health_failures > 0)
    f.push_back(std::to_string(s.health_failures) + " of " + std::to_string(s.health_probes) +
                " health probes unanswered: the server did not stay up");
  if (s.http_5xx > 0) f.push_back(std::to_string(s.http_5xx) + " HTTP 5xx answers");
  if (count_kind(s, "link_cut") < limits.link_cuts)
    f.push_back("link cuts applied: " + std::to_string(count_kind(s, "link_cut")) + ", expected " + std::to_string(limits.link_cuts));
  if (count_kind(s, "emulator_restart") < limits.emulator_restarts)
    f.push_back("emulator restarts applied: " + std::to_string(count_kind(s, "emulator_restart")) + ", expected " +
                std::to_string(limits.emulator_restarts));
  if (count_kind(s, "low_battery") < limits.low_battery)
    f.push_back("low-battery flights: " + std::to_string(count_kind(s, "low_battery")) + ", expected " +
                std::to_string(limits.low_battery));
  if (s.missions_accepted == 0) f.push_back("no mission was accepted");
  if (s.frames_received == 0) f.push_back("no client received a frame");
  if (s.recording_reported_bytes == 0 || s.recording_file_bytes != s.recording_reported_bytes)
    f.push_back("recording: " + std::to_string(s.recording_file_bytes) + " bytes on disk, the writer reported " +
                std::to_string(s.recording_reported_bytes));
  if (!s.replay_to_end) f.push_back("recording: the replay did not read it to its end (" + s.replay_error + ")");
  if (s.rss_samples < 2 || s.net_warmup_level_mib <= 0 || s.net_end_level_mib <= 0)
    f.push_back("memory: too few samples to judge its level (" + std::to_string(s.rss_samples) +
                " samples; needed some in the warm-up's second half and in the last quarter)");
  else if (s.net_growth_percent > limits.rss_growth_percent)
    f.push_back(format("memory grew %.1f %% after warm-up beyond the SLAM map's (%.1f -> %.1f MiB, the median of RSS less "
                       "the map over the warm-up's second half and over the last quarter; limit %.1f %%)",
                       s.net_growth_percent, s.net_warmup_level_mib, s.net_end_level_mib, limits.rss_growth_percent));
  return f;
}

std::vector<std::string> flight_failures(const SoakSummary& s, const SoakLimits& limits) {
  std::vector<std::string> f;
  for (const auto& fault : s.faults) {
    if (fault.after != "landed" && fault.after.rfind("mission ", 0) != 0)
      f.push_back(fault.kind + format(" at %.0f s: the drone was ", fault.at_s) + fault.after + " once it was over");
    if (fault.kind == "low_battery" && fault.after != "landed")
      f.push_back(format("low battery at %.0f s: the drone did not land", fault.at_s));
    if (fault.kind == "low_battery" && fault.detail.find("battery") == std::string::npos)
      f.push_back(format("low battery at %.0f s: the mission did not end for the battery", fault.at_s) + " (" +
                  fault.detail + ")");
  }
  if (s.longest_unmanaged_flight_s > limits.unmanaged_flight_s)
    f.push_back(format("the drone flew %.1f s without a mission (limit %.1f s)", s.longest_unmanaged_flight_s,
                       limits.unmanaged_flight_s));
  if (!s.ended_landed) f.push_back("the drone was not landed at the end");
  if (s.crashes > 0) f.push_back(std::to_string(s.crashes) + " crashes in the simulated lab");
  return f;
}

std::vector<std::string> soak_failures(const SoakSummary& s, const SoakLimits& limits) {
  std::vector<std::string> f = service_failures(s, limits);
  for (auto& g : flight_failures(s, limits)) f.push_back(std::move(g));
  return f;
}

namespace {

nlohmann::json to_json(const TrailPose& p) { return {p.x_m, p.y_m, p.z_m, p.yaw_deg}; }

nlohmann::json to_json(const TrailPoint& p) {
  nlohmann::json j = {{"t_s", p.t_s},
                      {"true", to_json(p.truth)},
                      {"estimate", to_json(p.estimate)},
                      {"source", p.source},
                      {"slam", p.slam},
                      {"stage", p.stage},
                      {"link", p.link}};
  if (p.desired) j["desired"] = to_json(*p.desired);
  return j;
}

nlohmann::json to_json(const CrashReport& c) {
  nlohmann::json trail = nlohmann::json::array();
  for (const auto& p : c.trail) trail.push_back(to_json(p));
  return {{"at_s", c.at_s}, {"hit", c.hit}, {"mission", c.mission}, {"trail", trail}};
}

double horizontal_error_m(const TrailPoint& p) {
  return std::hypot(p.estimate.x_m - p.truth.x_m, p.estimate.y_m - p.truth.y_m);
}

}  // namespace

nlohmann::json to_json(const SoakSummary& s, const std::vector<std::string>& failures) {
  nlohmann::json crash_reports = nlohmann::json::array();
  for (const auto& c : s.crash_reports) crash_reports.push_back(to_json(c));
  nlohmann::json faults = nlohmann::json::array();
  for (const auto& f : s.faults)
    faults.push_back({{"kind", f.kind}, {"at_s", f.at_s}, {"duration_s", f.duration_s}, {"airborne", f.airborne},
                      {"after", f.after}, {"detail", f.detail}});
  const auto pct = [](const Percentiles& p) {
    return nlohmann::json{{"count", p.count}, {"median", p.median}, {"p95", p.p95}, {"p99", p.p99}, {"max", p.max}};
  };
  return {{"experiment", "sim soak"},
          {"passed", failures.empty()},
          {"failures", failures},
          {"duration_s", s.duration_s},
          {"server", {{"health_probes", s.health_probes}, {"health_failures", s.health_failures}, {"http_5xx", s.http_5xx}}},
          {"drone",
           {{"faults", faults},
            {"longest_unmanaged_flight_s", s.longest_unmanaged_flight_s},
            {"ended_landed", s.ended_landed},
            {"crashes", s.crashes},
            {"crash_reports", crash_reports},
            {"battery_swaps", s.battery_swaps},
            {"set_downs", s.set_downs}}},
          {"missions",
           {{"rounds", s.rounds},
            {"accepted", s.missions_accepted},
            {"succeeded", s.missions_succeeded},
            {"refused", s.missions_refused},
            {"results", s.mission_results}}},
          {"clients",
           {{"logins", s.logins},
            {"ws_connections", s.ws_connections},
            {"spectators_joined", s.spectators_joined},
            {"slow_reader_stalls", s.slow_reader_stalls},
            {"slow_reader_cut_off", s.slow_reader_cut_off},
            {"slow_disconnects", s.slow_disconnects},
            {"frames_sent", s.frames_sent},
            {"frames_received", s.frames_received},
            {"frames_skipped", s.frames_skipped}}},
          {"recording",
           {{"reported_bytes", s.recording_reported_bytes},
            {"file_bytes", s.recording_file_bytes},
            {"replay_to_end", s.replay_to_end},
            {"replay_records", s.replay_records},
            {"replay_navdata", s.replay_navdata},
            {"replay_frames", s.replay_frames},
            {"replay_error", s.replay_error}}},
          {"memory",
           {{"samples", s.rss_samples},
            {"warmup_s", s.warmup_s},
            {"warmup_peak_mib", s.rss_warmup_peak_mib},
            {"after_warmup_peak_mib", s.rss_after_peak_mib},
            {"final_mib", s.rss_final_mib},
            {"growth_percent", s.rss_growth_percent},
            {"net_of_slam_map", {{"warmup_level_mib", s.net_warmup_level_mib},
                                 {"end_level_mib", s.net_end_level_mib},
                                 {"growth_percent", s.net_growth_percent},
                                 {"warmup_peak_mib", s.net_warmup_peak_mib},
                                 {"after_warmup_peak_mib", s.net_after_peak_mib},
                                 {"peak_growth_percent", s.net_peak_growth_percent},
                                 {"heap_in_use_warmup_peak_mib", s.in_use_net_warmup_peak_mib},
                                 {"heap_in_use_after_warmup_peak_mib", s.in_use_net_after_peak_mib}}},
            {"slam_map_per_minute_mib", s.slam_map_per_minute_mib},
            {"per_minute_mib", s.rss_per_minute_mib},
            {"heap_in_use_per_minute_mib", s.heap_in_use_per_minute_mib},
            {"heap_held_per_minute_mib", s.heap_held_per_minute_mib}}},
          {"timing",
           {{"tick_interval_ms", pct(s.timing.tick_interval_ms)},
            {"vision_latency_ms", pct(s.timing.vision_latency_ms)},
            {"frames_in", s.timing.frames_in},
            {"frames_skipped", s.timing.frames_skipped},
            {"vision_failures", s.timing.vision_failures}}}};
}

std::string to_text(const SoakSummary& s, const std::vector<std::string>& failures) {
  std::ostringstream out;
  out << (failures.empty() ? "soak passed" : "soak FAILED") << format(" after %.0f s\n", s.duration_s);
  for (const auto& f : failures) out << "  failed: " << f << "\n";
  out << "server: " << s.health_probes - s.health_failures << "/" << s.health_probes << " health probes answered, "
      << s.http_5xx << " 5xx\n";
  out << "missions: " << s.missions_succeeded << " succeeded of " << s.missions_accepted << " accepted in " << s.rounds
      << " rounds (" << s.missions_refused << " refused)\n";
  for (const auto& f : s.faults)
    out << "  " << f.kind << format(" at %.0f s for %.1f s", f.at_s, f.duration_s) << (f.airborne ? " in flight" : " landed")
        << ": then " << f.after << (f.detail.empty() ? "" : " (" + f.detail + ")") << "\n";
  out << format("drone: longest flight without a mission %.1f s; ", s.longest_unmanaged_flight_s)
      << (s.ended_landed ? "landed at the end" : "NOT landed at the end") << "; " << s.crashes << " crashes; "
      << s.battery_swaps << " battery swaps\n";
  for (const auto& c : s.crash_reports) {
    out << format("  crash at %.0f s into ", c.at_s) << c.hit << " during " << c.mission;
    if (!c.trail.empty()) {
      const TrailPoint& last = c.trail.back();
      const auto worst = std::max_element(c.trail.begin(), c.trail.end(), [](const TrailPoint& a, const TrailPoint& b) {
        return horizontal_error_m(a) < horizontal_error_m(b);
      });
      out << " (" << last.stage << "; " << last.source << ", SLAM " << last.slam
          << format("): the estimate %.2f m off the truth at the crash", horizontal_error_m(last))
          << format(", at most %.2f m", horizontal_error_m(*worst)) << format(" over the %.0f s before", c.at_s - c.trail.front().t_s);
    }
    out << "\n";
  }
  out << "clients: " << s.ws_connections << " WebSocket connections (" << s.spectators_joined << " spectators), "
      << s.logins << " logins; frames sent " << s.frames_sent << ", received " << s.frames_received << ", skipped "
      << s.frames_skipped << "; slow reader stalled " << s.slow_reader_stalls << " times, cut off " << s.slow_reader_cut_off
      << " times (" << s.slow_disconnects << " slow clients disconnected)\n";
  out << "recording: " << s.recording_file_bytes << " bytes on disk, " << s.recording_reported_bytes
      << " reported; replay " << (s.replay_to_end ? "read to the end" : "FAILED: " + s.replay_error) << " ("
      << s.replay_records << " records, " << s.replay_navdata << " navdata, " << s.replay_frames << " frames)\n";
  out << format("memory: RSS peak %.1f MiB during warm-up", s.rss_warmup_peak_mib)
      << format(" (%.0f s), %.1f MiB after", s.warmup_s, s.rss_after_peak_mib)
      << format(", %.1f MiB at the end: growth %.2f %%", s.rss_final_mib, s.rss_growth_percent)
      << format("; without the SLAM map: level %.1f -> %.1f MiB, growth %.2f %%", s.net_warmup_level_mib,
                s.net_end_level_mib, s.net_growth_percent)
      << format(" (peak %.1f -> %.1f MiB, %.2f %%)", s.net_warmup_peak_mib, s.net_after_peak_mib, s.net_peak_growth_percent)
      << format(" (heap in use less the map: peak %.1f -> %.1f MiB)\n", s.in_use_net_warmup_peak_mib,
                s.in_use_net_after_peak_mib);
  out << format("control ticks (last window): median %.1f ms, p99 %.1f ms\n", s.timing.tick_interval_ms.median,
                s.timing.tick_interval_ms.p99);
  return out.str();
}

}  // namespace labo::bench
