#pragma once
// One connected browser as the RemoteLab sees it. The WebSocket session implements it; tests can
// implement it without sockets. send_* are thread-safe and never block: each client keeps a bounded
// queue of JSON events and a single latest-frame slot for video.
#include <memory>
#include <string>

#include "server/auth/session_store.hpp"
#include "server/lab/control_queue.hpp"

namespace labo {

class LabClient {
 public:
  virtual ~LabClient() = default;
  virtual ClientId id() const = 0;
  virtual const SessionInfo& session() const = 0;
  virtual void send_event(std::shared_ptr<const std::string> json) = 0;
  virtual void send_frame(std::shared_ptr<const std::string> wire) = 0;
  virtual void disconnect(const std::string& reason) = 0;
};

}  // namespace labo
