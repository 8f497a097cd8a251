#include "server/lab/control_queue.hpp"

#include <algorithm>

namespace labo::server {

void ControlQueue::grant(const Participant& p, double now_s, std::vector<ControlNotice>& out) {
  Turn turn{p, now_s, -1, now_s, 0};
  if (p.role == Role::Student) turn.deadline_s = now_s + rules_.time_limit_s;
  // Warnings longer than the turn itself are skipped, not sent at once.
  std::vector<double> w = rules_.warnings_s;
  std::sort(w.rbegin(), w.rend());
  turn.warnings_sent = static_cast<std::size_t>(std::count_if(w.begin(), w.end(), [&](double s) { return s >= rules_.time_limit_s; }));
  controller_ = turn;
  dequeue(p.client);
  out.push_back({ControlNotice::Kind::Granted, p.client, turn.deadline_s < 0 ? -1 : rules_.time_limit_s, ""});
}

void ControlQueue::end_turn(const std::string& reason, const std::string& by, std::vector<ControlNotice>& out) {
  if (!controller_) return;
  out.push_back({ControlNotice::Kind::Ended, controller_->who.client, 0, reason, by});
  controller_.reset();
}

void ControlQueue::dequeue(ClientId client) {
  std::erase_if(queue_, [&](const Waiting& q) { return q.who.client == client; });
}

void ControlQueue::grant_next(double now_s, std::vector<ControlNotice>& out) {
  if (controller_ || queue_.empty()) return;
  const Participant next = queue_.front().who;
  queue_.pop_front();
  grant(next, now_s, out);
}

std::vector<ControlNotice> ControlQueue::request(const Participant& p, double now_s) {
  std::vector<ControlNotice> out;
  if (is_controller(p.client)) return out;
  if (!controller_) {
    grant(p, now_s, out);
  } else if (!queue_position(p.client)) {
    queue_.push_back({p, now_s});
  }
  return out;
}

std::vector<ControlNotice> ControlQueue::release(ClientId client, double now_s) {
  std::vector<ControlNotice> out;
  if (is_controller(client)) {
    end_turn("released", "", out);
    grant_next(now_s, out);
  } else {
    dequeue(client);
  }
  return out;
}

std::vector<ControlNotice> ControlQueue::take_over(const Participant& p, double now_s) {
  std::vector<ControlNotice> out;
  if (p.role == Role::Student || is_controller(p.client)) return out;
  if (controller_) {
    const Participant previous = controller_->who;
    end_turn("taken over by " + p.user, "", out);
    // A student who was replaced waits first in line; a teacher or admin does not queue.
    if (previous.role == Role::Student) queue_.push_front({previous, now_s});
  }
  grant(p, now_s, out);
  return out;
}

std::vector<ControlNotice> ControlQueue::end_turn(const std::string& by, const std::string& reason, double now_s) {
  std::vector<ControlNotice> out;
  end_turn(reason, by, out);
  grant_next(now_s, out);
  return out;
}

std::vector<ControlNotice> ControlQueue::leave(ClientId client, double now_s) {
  std::vector<ControlNotice> out;
  dequeue(client);
  if (is_controller(client)) {
    controller_.reset();  // nobody to notify: the client is gone
    grant_next(now_s, out);
  }
  return out;
}

void ControlQueue::heartbeat(ClientId client, double now_s) {
  if (is_controller(client)) controller_->last_heartbeat_s = now_s;
}

std::vector<ControlNotice> ControlQueue::tick(double now_s) {
  std::vector<ControlNotice> out;
  if (!controller_) {
    grant_next(now_s, out);
    return out;
  }
  if (now_s - controller_->last_heartbeat_s > rules_.heartbeat_timeout_s) {
    end_turn("heartbeat lost", "", out);
  } else if (controller_->deadline_s >= 0) {
    const double remaining = controller_->deadline_s - now_s;
    if (remaining <= 0) {
      end_turn("time limit", "", out);
    } else {
      std::vector<double> w = rules_.warnings_s;
      std::sort(w.rbegin(), w.rend());
      while (controller_->warnings_sent < w.size() && remaining <= w[controller_->warnings_sent]) {
        out.push_back({ControlNotice::Kind::Warning, controller_->who.client, remaining, ""});
        ++controller_->warnings_sent;
      }
    }
  }
  grant_next(now_s, out);
  return out;
}

std::optional<std::size_t> ControlQueue::queue_position(ClientId client) const {
  for (std::size_t i = 0; i < queue_.size(); ++i)
    if (queue_[i].who.client == client) return i + 1;
  return std::nullopt;
}

ControlSnapshot ControlQueue::snapshot(double now_s) const {
  ControlSnapshot s;
  if (controller_) {
    s.controller = controller_->who;
    s.remaining_s = controller_->deadline_s < 0 ? -1 : std::max(0.0, controller_->deadline_s - now_s);
    s.held_s = now_s - controller_->started_s;
  }
  for (const Waiting& w : queue_) {
    s.queue.push_back(w.who);
    s.waited_s.push_back(now_s - w.since_s);
  }
  return s;
}

}  // namespace labo::server
