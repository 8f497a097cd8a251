#include "server/api/face_registrar.hpp"

#include <opencv2/imgcodecs.hpp>

#include "server/auth/session_store.hpp"

namespace labo::server {

namespace {

RegistrationOutcome refused(int status, std::string error) {
  RegistrationOutcome o;
  o.status = status;
  o.error = std::move(error);
  return o;
}

// The photos in grey; an error naming the first that does not decode.
std::variant<std::vector<cv::Mat>, std::string> decode(const std::vector<std::string>& photos, const std::string& field) {
  std::vector<cv::Mat> out;
  for (std::size_t i = 0; i < photos.size(); ++i) {
    const cv::Mat bytes(1, static_cast<int>(photos[i].size()), CV_8UC1, const_cast<char*>(photos[i].data()));
    cv::Mat gray = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
    if (gray.empty()) return field + " photo " + std::to_string(i + 1) + " cannot be decoded";
    out.push_back(std::move(gray));
  }
  return out;
}

}  // namespace

FaceRegistrar::FaceRegistrar(const PeopleSettings& settings, PeopleStore& store)
    : settings_(settings), store_(store), worker_([this] { run(); }) {}

FaceRegistrar::~FaceRegistrar() { stop(); }

bool FaceRegistrar::submit(RegistrationForm form, std::string by, std::function<void(RegistrationOutcome)> done) {
  std::lock_guard lock(mutex_);
  if (stopping_ || jobs_.size() >= kMaxWaiting) return false;
  jobs_.push_back({std::move(form), std::move(by), std::move(done)});
  wake_.notify_one();
  return true;
}

void FaceRegistrar::stop() {
  std::deque<Job> waiting;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !worker_.joinable()) return;
    stopping_ = true;
    waiting.swap(jobs_);
    wake_.notify_one();
  }
  for (Job& job : waiting) job.done(refused(503, "the server is shutting down"));
  if (worker_.joinable()) worker_.join();
}

void FaceRegistrar::run() {
  while (true) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    RegistrationOutcome outcome;
    try {
      outcome = register_person(job);
    } catch (const std::exception& e) {
      outcome = refused(500, std::string("registration failed: ") + e.what());
    }
    job.done(std::move(outcome));
  }
}

RegistrationOutcome FaceRegistrar::register_person(const Job& job) {
  const RegistrationForm& form = job.form;
  auto frontal = decode(form.frontal, "frontal");
  if (const auto* error = std::get_if<std::string>(&frontal)) return refused(400, *error);
  auto turns = decode(form.turns, "turn");
  if (const auto* error = std::get_if<std::string>(&turns)) return refused(400, *error);
  if (!estimator_) estimator_ = std::make_unique<face::FacePoseEstimator>(settings_.face, PinholeCamera(settings_.front_camera));
  const double ipd_m = form.interpupillary_distance_m.value_or(settings_.face.interpupillary_distance_m);
  RegistrationOutcome outcome;
  try {
    outcome.person = face::register_person(*estimator_, std::get<std::vector<cv::Mat>>(frontal), form.name, ipd_m);
  } catch (const face::RegistrationError& e) {
    return refused(422, e.what());
  }
  const auto& turn_frames = std::get<std::vector<cv::Mat>>(turns);
  if (!turn_frames.empty()) {
    try {
      outcome.turn = face::refine_person_from_turns(*estimator_, outcome.person, turn_frames);
    } catch (const face::RegistrationError& e) {
      return refused(422, std::string("head turn refused: ") + e.what());
    }
    outcome.person = outcome.turn->person;
  }
  const bool existed = store_.exists(form.name);
  const RegistrationRecord record{static_cast<int>(form.frontal.size()), outcome.turn ? outcome.turn->views : 0, unix_now_s(), job.by};
  if (!store_.write(outcome.person, record, form.replace))
    return refused(409, "'" + form.name + "' is registered already: send replace=true to replace the shape");
  outcome.replaced = existed;
  return outcome;
}

}  // namespace labo::server
