#pragma once
// Registers faces from uploaded photos on its own worker thread: decoding the photos, the face
// detector, the CANDIDE-3 shape fit and a head turn's depth refinement take a second or more, which
// the server's I/O threads must not spend. One registration at a time, a few waiting; more are
// refused (the caller answers 503). The worker's FacePoseEstimator is built on its first job (it loads
// the landmark model) and kept.
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "localization/face/person_registration.hpp"
#include "server/api/people_store.hpp"
#include "server/api/registration_form.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

struct RegistrationOutcome {
  int status = 201;   // 201 registered; 409 registered meanwhile; 422 refused by the face code; 500; 503
  std::string error;  // when not 201: what was wrong
  face::PersonShape person;
  std::optional<face::TurnRefinement> turn;  // with a head turn
  bool replaced = false;
};

class FaceRegistrar {
 public:
  static constexpr std::size_t kMaxWaiting = 2;

  FaceRegistrar(const PeopleSettings& settings, PeopleStore& store);
  ~FaceRegistrar();
  FaceRegistrar(const FaceRegistrar&) = delete;
  FaceRegistrar& operator=(const FaceRegistrar&) = delete;

  // Queues the registration; `done` is called once, from the worker. False (and `done` never called)
  // when kMaxWaiting registrations already wait or the registrar has stopped.
  bool submit(RegistrationForm form, std::string by, std::function<void(RegistrationOutcome)> done);
  // Refuses what waits (503), lets the running registration finish, joins the worker.
  void stop();

 private:
  struct Job {
    RegistrationForm form;
    std::string by;
    std::function<void(RegistrationOutcome)> done;
  };
  void run();
  RegistrationOutcome register_person(const Job& job);

  PeopleSettings settings_;
  PeopleStore& store_;
  std::unique_ptr<face::FacePoseEstimator> estimator_;  // the worker's only
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace labo::server
