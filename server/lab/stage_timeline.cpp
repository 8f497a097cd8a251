#include "server/lab/stage_timeline.hpp"

#include <cctype>

namespace labo::server {

StageWords split_stage_line(const std::string& line) {
  std::size_t start = 0;
  while (start < line.size() && std::isdigit(static_cast<unsigned char>(line[start]))) ++start;
  start = start > 0 && start < line.size() && line[start] == ' ' ? start + 1 : 0;
  const std::size_t colon = line.find(": ", start);
  if (colon == std::string::npos) return {line.substr(start), ""};
  return {line.substr(start, colon - start), line.substr(colon + 2)};
}

bool StageTimeline::observe(Seconds t, const MissionProgress& progress) {
  const bool one_ended = missions_ended_ && progress.missions_ended != *missions_ended_;
  missions_ended_ = progress.missions_ended;
  const bool running = progress.stage_count > 0;
  bool open = !timeline_.mission.empty() && !timeline_.ended;
  bool changed = false;
  if (open && (one_ended || !running || progress.mission != timeline_.mission)) {
    // A core that does not count its missions still ends them: the mission it reports says how.
    end_mission(t, one_ended ? progress.last_result : progress.mission == "idle" ? "ended" : progress.mission);
    open = false;
    changed = true;
  }
  if (!running) return changed;
  if (!open) {
    timeline_ = MissionTimeline{};
    timeline_.mission = progress.mission;
    timeline_.started = t;
    changed = true;
  }
  timeline_.stage_count = progress.stage_count;
  const StageWords words = split_stage_line(progress.stage);
  changed = enter_stage(t, progress.stage_index, words) || changed;
  timeline_.stages.back().waiting_for = words.waiting_for;
  return changed;
}

bool StageTimeline::enter_stage(Seconds t, int index, const StageWords& words) {
  auto& stages = timeline_.stages;
  if (!stages.empty() && stages.back().index == index && stages.back().name == words.name) return false;
  if (!stages.empty()) stages.back().ended = t;
  stages.push_back({index, words.name, t, std::nullopt, words.waiting_for});
  if (stages.size() > kMaxStages) {
    stages.erase(stages.begin());
    ++timeline_.dropped;
  }
  return true;
}

void StageTimeline::end_mission(Seconds t, const std::string& result) {
  if (!timeline_.stages.empty() && !timeline_.stages.back().ended) timeline_.stages.back().ended = t;
  timeline_.ended = t;
  timeline_.result = result;
  timeline_.succeeded = result.rfind("succeeded", 0) == 0;
}

}  // namespace labo::server
