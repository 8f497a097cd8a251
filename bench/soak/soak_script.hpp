#pragma once
// The soak's rounds: students take turns at the controls over real WebSockets (request control,
// wait for it, one mission, heartbeats meanwhile, release), the next one already queued; the
// missions rotate through inspect (the lab's first instrument), find the teacher (followed a while,
// then land) and inspect (the lab's last instrument). The faults fall into the rounds when they are
// due: the link cut or the emulator restarted while the drone flies, a nearly empty battery put in
// before a round, and a fresh battery whenever the drone is down to 40 % between rounds.
#include <boost/asio/io_context.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/soak/soak_client.hpp"
#include "bench/soak/soak_report.hpp"
#include "bench/soak/soak_server.hpp"
#include "bench/soak/soak_watch.hpp"

namespace labo::bench {

using server::AppConfig;


struct Student {
  std::string name;
  std::string cookie;
};

// A fault and when it is due (seconds since the start); in-flight faults wait for the drone to have
// flown 10 s in a round.
struct PlannedFault {
  enum class Kind { LinkCut, EmulatorRestart, LowBattery };
  Kind kind = Kind::LinkCut;
  double due_s = 0;
  double duration_s = 0;  // the cut, or the time the emulator stays down
};

// The faults of a soak of `total_s`: spread over its middle, more of them in a long one.
std::vector<PlannedFault> plan_faults(double total_s);

struct ScriptOptions {
  double total_s = 1800;
  double follow_s = 20;          // find the teacher: how long to follow once found
  double mission_timeout_s = 180;
  double settle_s = 20;          // after a fault, the flight software's time to act before we look
  double battery_swap_below_percent = 40;
};

class SoakScript {
 public:
  SoakScript(SoakServer& server, SoakWatch& watch, boost::asio::io_context& io, const AppConfig& config,
             std::vector<Student> students, Student admin, ScriptOptions options);

  // Rounds until the time is up and every planned fault has been applied (at most half the time
  // more, ten minutes at most).
  void run();
  // Results, into the summary's rounds, missions, faults and battery swaps.
  void report(SoakSummary& summary) const;

 private:
  enum class Mission { InspectFirst, FindTeacher, InspectLast };
  struct PendingLook {
    std::size_t fault = 0;
    double at_s = 0;
  };

  void round(int index);
  void ready_the_drone(bool low_battery);
  std::shared_ptr<SoakClient> queue_for_control(const Student& student);
  bool issue(SoakClient& client, const nlohmann::json& command);
  void fly(SoakClient& client, Mission mission, std::uint64_t ended_before, std::uint64_t safety_before);
  void land_if_flying(SoakClient& client);
  void heartbeats(SoakClient* controlling);
  void tick(SoakClient& client);  // heartbeats, due faults, looks at the drone after faults
  void apply_in_flight_faults();
  void look_after_faults(bool now);
  // A new lab (RestartableDrone::replace_lab) whose drone stands at `where`, its battery at
  // start_percent, the flight software restarted too when asked; waits until it reads the battery.
  void swap_battery(double start_percent, const DroneTruth& where, bool restart_flight = false);
  // The drone (stopped, its lab replaced) standing at `where` with its battery at start_percent;
  // waits until the flight software reads that battery.
  void put_drone(double start_percent, const DroneTruth& where, bool restart_flight);
  // What the lab's staff does for a drone landed where its place is not confirmed: carry it to its
  // platform (the battery as it is) and say so (POST /api/drone/set-down, as the admin).
  void set_on_platform(const DroneTruth& truth, double unobserved_s);
  double now() const { return watch_.elapsed_s(); }

  SoakServer& server_;
  SoakWatch& watch_;
  boost::asio::io_context& io_;
  AppConfig config_;
  std::vector<Student> students_;
  Student admin_;
  ScriptOptions options_;
  std::vector<std::string> instruments_;
  std::vector<PlannedFault> plan_;
  std::vector<bool> applied_;
  std::vector<FaultRecord> faults_;
  std::vector<PendingLook> looks_;
  std::shared_ptr<SoakClient> queued_;  // the next student, already waiting for control
  std::optional<DroneTruth> crash_;     // where to set the drone down after a crash
  double flying_since_ = -1;            // in this round, per the truth
  // A round flown on the nearly empty battery: no other fault meanwhile, so that what ends its
  // mission is the battery rule under test, not a link cut or restart landing it first.
  bool low_battery_round_ = false;
  double last_heartbeat_ = 0;
  int next_command_id_ = 1;
  int rounds_ = 0, accepted_ = 0, succeeded_ = 0, refused_ = 0, battery_swaps_ = 0, set_downs_ = 0;
  std::vector<std::string> results_;
};

}  // namespace labo::bench
