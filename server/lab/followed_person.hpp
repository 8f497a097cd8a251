#pragma once
// The registered person face-follow follows: a teacher's choice (PUT /api/face_follow), attached by
// the lab to every find_teacher command, whoever sends it. Thread-safe: the REST routes set it, the
// clients' strands read it.
#include <memory>
#include <mutex>
#include <string>

#include "localization/face/person_shape.hpp"

namespace labo::server {

class FollowedPerson {
 public:
  // Null: none chosen (the flight software keeps the face it follows, face.teacher's at start).
  void set(std::shared_ptr<const face::PersonShape> person) {
    std::lock_guard lock(mutex_);
    person_ = std::move(person);
  }
  std::shared_ptr<const face::PersonShape> get() const {
    std::lock_guard lock(mutex_);
    return person_;
  }
  std::string name() const {
    const auto p = get();
    return p ? p->name : std::string();
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const face::PersonShape> person_;
};

}  // namespace labo::server
