#pragma once
// Who flies: one controller at a time, the others wait in a FIFO queue that everyone sees. A
// student's turn has a time limit with warnings before its end; a controller whose heartbeat stops
// loses control; teachers and admins have no time limit and may take over (the student they replace
// goes back to the head of the queue). Pure logic: time is passed in, nothing here touches sockets.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "server/server_settings.hpp"

namespace labo::server {

using ClientId = std::uint64_t;

struct Participant {
  ClientId client = 0;
  std::string user;
  Role role = Role::Student;
};

// A notice for one client, produced when control changes hands or a turn nears its end.
struct ControlNotice {
  enum class Kind { Granted, Warning, Ended };
  Kind kind = Kind::Granted;
  ClientId client = 0;
  double remaining_s = 0;  // Warning: time left
  std::string reason;      // Ended: "time limit", "heartbeat lost", "taken over by <user>", "released", or a teacher's words
  std::string by{};        // Ended by a teacher or an admin (end_turn): who
};

struct ControlSnapshot {
  std::optional<Participant> controller;
  double remaining_s = -1;  // -1: no time limit
  double held_s = 0;        // how long the controller has held control
  std::vector<Participant> queue;
  std::vector<double> waited_s;  // parallel to queue: how long each has waited
};

class ControlQueue {
 public:
  explicit ControlQueue(ControlRules rules) : rules_(std::move(rules)) {}

  // Granted at once when nobody controls, else queued (once). Returns the notices to deliver.
  std::vector<ControlNotice> request(const Participant& p, double now_s);
  std::vector<ControlNotice> release(ClientId client, double now_s);
  // Teacher or admin only (the caller checks the role; this refuses students too).
  std::vector<ControlNotice> take_over(const Participant& p, double now_s);
  // A teacher or an admin (`by`; the caller checks the role) ends the controller's turn with their
  // reason; the next in line is granted control. Nothing when nobody controls.
  std::vector<ControlNotice> end_turn(const std::string& by, const std::string& reason, double now_s);
  // The client left (socket closed): out of the queue, control passed on.
  std::vector<ControlNotice> leave(ClientId client, double now_s);
  void heartbeat(ClientId client, double now_s);
  // Warnings, time limit and heartbeat expiry.
  std::vector<ControlNotice> tick(double now_s);

  bool is_controller(ClientId client) const { return controller_ && controller_->who.client == client; }
  std::optional<std::size_t> queue_position(ClientId client) const;  // 1-based
  ControlSnapshot snapshot(double now_s) const;

 private:
  struct Turn {
    Participant who;
    double started_s = 0;
    double deadline_s = -1;  // -1: none
    double last_heartbeat_s = 0;
    std::size_t warnings_sent = 0;
  };
  struct Waiting {
    Participant who;
    double since_s = 0;
  };
  void grant(const Participant& p, double now_s, std::vector<ControlNotice>& out);
  void end_turn(const std::string& reason, const std::string& by, std::vector<ControlNotice>& out);
  void dequeue(ClientId client);
  void grant_next(double now_s, std::vector<ControlNotice>& out);

  ControlRules rules_;
  std::optional<Turn> controller_;
  std::deque<Waiting> queue_;
};

}  // namespace labo::server
