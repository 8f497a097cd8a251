#include "server/runtime/flight_runtime.hpp"

#include <chrono>

#include "server/video/overlay_renderer.hpp"

namespace labo::server {

using lab::InstrumentSpec;


namespace {
double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

FlightRuntime::FlightRuntime(DroneLink& link, FlightCore& core, const Clock& clock, FlightRuntimeOptions options, Logger log)
    : link_(link),
      core_(core),
      clock_(clock),
      options_(options),
      log_(std::move(log)),
      clock_to_unix_s_(unix_now_s() - clock.now()),
      instruments_(core.instruments()),
      encoder_(options.jpeg_quality),
      reading_view_(options.reading_view_hz, options.jpeg_quality, options.front_camera),
      low_rendition_(options.low_rendition),
      vision_([this] {
        {
          std::lock_guard lock(input_mutex_);
          vision_ready_ = true;
        }
        input_cv_.notify_one();
      }) {}

FlightRuntime::~FlightRuntime() {
  stop_threads();
  link_.set_listener(nullptr);
}

void FlightRuntime::start() {
  running_ = true;
  flight_thread_ = std::thread([this] { flight_loop(); });
  video_thread_ = std::thread([this] { video_loop(); });
  link_.set_listener(this);
}

void FlightRuntime::set_sink(FlightEventSink* sink) {
  std::lock_guard lock(sink_mutex_);
  sink_ = sink;
}

std::vector<InstrumentSummary> FlightRuntime::instruments() const {
  std::lock_guard lock(instruments_mutex_);
  return instruments_;
}

// --- link threads: copy in, wake a consumer, return -------------------------------------------------

void FlightRuntime::on_navdata(const NavdataSample& sample) {
  {
    std::lock_guard lock(input_mutex_);
    if (navdata_.size() >= options_.navdata_ring) navdata_.pop_front();  // the flight thread stalled: keep the newest
    navdata_.push_back(sample);
  }
  input_cv_.notify_one();
}

void FlightRuntime::on_video(const VideoFrame& frame) {
  frames_in_++;
  timing_.count_frame_in();
  {
    std::lock_guard lock(input_mutex_);
    if (core_slot_.fresh) timing_.count_frame_skipped();  // the flight thread had not taken the last one
    for (FrameSlot* slot : {&core_slot_, &video_slot_}) {
      slot->frame.t = frame.t;
      slot->frame.camera = frame.camera;
      slot->frame.frame_number = frame.frame_number;
      frame.bgr.copyTo(slot->frame.bgr);
      slot->fresh = true;
    }
  }
  input_cv_.notify_one();
  video_cv_.notify_one();
}

void FlightRuntime::on_encoded_video(const EncodedVideo& unit) {
  {
    std::lock_guard lock(sink_mutex_);
    if (!sink_ || !sink_->wants_access_units()) return;
  }
  {
    std::lock_guard lock(snapshot_mutex_);
    unit_overlay_ = snapshot_.overlay;  // assignments: the members keep their capacity
    unit_telemetry_ = snapshot_.telemetry;
  }
  WireAccessUnit out = packer_.pack(unit, unix_ms_of(unit.t));
  out.geometry = geometry_.write(unit_overlay_, unit_telemetry_,
                                 {unit.frame_number, out.capture_unix_ms, unit.camera, unit.width, unit.height},
                                 clock_to_unix_s_);
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_access_unit(out);
}

void FlightRuntime::on_link_state(LinkState state, Seconds t) {
  const LinkState previous = link_state_.exchange(state);
  if (previous == state) return;
  log_.info(t, "link state").kv("state", to_string(state));
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_flight_event({"link", "", "", "link " + to_string(state)});
}

// --- requests from the web threads ------------------------------------------------------------------

VideoCapabilities FlightRuntime::video_capabilities() const {
  std::lock_guard lock(video_mutex_);
  return options_.video;
}

CommandVerdict FlightRuntime::set_video_bitrate(int kbps) {
  std::lock_guard lock(video_mutex_);
  const VideoCapabilities& v = options_.video;
  if (!v.adjustable_bitrate || !options_.set_video_bitrate)
    return {false, (v.drone.empty() ? std::string("this drone") : v.drone) + ": the link cannot ask the drone for a video bit rate"};
  if (kbps < v.min_bitrate_kbps || kbps > v.max_bitrate_kbps)
    return {false, v.drone + " video bit rate: " + std::to_string(v.min_bitrate_kbps) + ".." + std::to_string(v.max_bitrate_kbps) +
                       " kbit/s expected, got " + std::to_string(kbps)};
  try {
    options_.set_video_bitrate(kbps);
  } catch (const std::invalid_argument& e) {
    return {false, e.what()};
  }
  options_.video.bitrate_kbps = kbps;
  log_.info(clock_.now(), "video bit rate set").kv("kbps", kbps);
  return {true, "the drone is asked for " + std::to_string(kbps) + " kbit/s"};
}

CommandVerdict FlightRuntime::request(const MissionCommand& command) {
  if (command.kind == MissionCommandKind::SelectCamera && command.camera == CameraId::Bottom) {
    // What the drone cannot do is refused here, with its reason, before the flight software sees it.
    const VideoCapabilities video = video_capabilities();
    if (!video.bottom_camera) return {false, "select_camera: " + video.no_bottom_camera};
  }
  if (command.kind == MissionCommandKind::EmergencyStop) {
    link_.emergency();  // first, from this thread: nothing queued may delay the motor cut
    log_.warn(clock_.now(), "emergency stop sent to the drone");
  }
  auto pending = std::make_shared<PendingRequest>();
  pending->command = command;
  if (auto verdict = queue_request(pending)) return *verdict;
  if (command.kind == MissionCommandKind::EmergencyStop) return {true, "emergency sent to the drone"};
  return {false, "the flight software did not answer within " + std::to_string(options_.request_timeout_s) + " s"};
}

CommandVerdict FlightRuntime::add_instrument(const InstrumentSpec& spec) {
  const CommandVerdict verdict = change_lab([spec](FlightCore& core) { return core.add_instrument(spec); });
  if (!verdict.accepted || !options_.place_in_world) return verdict;
  try {
    options_.place_in_world(spec);
  } catch (const std::exception& e) {
    return {false, "instrument '" + spec.id + "' placed for the flight software but not in the simulated lab: " + e.what()};
  }
  log_.info(clock_.now(), "instrument placed").kv("id", spec.id);
  return verdict;
}

CommandVerdict FlightRuntime::remove_instrument(const std::string& id) {
  return change_lab([id](FlightCore& core) { return core.remove_instrument(id); });
}

CommandVerdict FlightRuntime::set_down_on_platform() {
  const Seconds t = clock_.now();
  const CommandVerdict verdict = change_lab([](FlightCore& core) { return core.set_down_on_platform(); });
  if (verdict.accepted) log_.info(t, "the drone was set on its platform");
  return verdict;
}

CommandVerdict FlightRuntime::change_lab(std::function<CommandVerdict(FlightCore&)> change) {
  auto pending = std::make_shared<PendingRequest>();
  pending->change_lab = std::move(change);
  return queue_request(pending).value_or(
      CommandVerdict{false, "the flight software did not answer within " + std::to_string(options_.request_timeout_s) + " s"});
}

// Queued for the flight thread; empty when it did not answer within request_timeout_s.
std::optional<CommandVerdict> FlightRuntime::queue_request(std::shared_ptr<PendingRequest> pending) {
  auto verdict = pending->verdict.get_future();
  {
    std::lock_guard lock(input_mutex_);
    requests_.push_back(std::move(pending));
  }
  input_cv_.notify_one();
  if (verdict.wait_for(std::chrono::duration<double>(options_.request_timeout_s)) != std::future_status::ready)
    return std::nullopt;
  return verdict.get();
}

// The flight thread's.
CommandVerdict FlightRuntime::execute(const PendingRequest& r) {
  if (!r.change_lab) return core_.request(r.command, clock_.now());
  CommandVerdict verdict = r.change_lab(core_);
  if (verdict.accepted) {
    std::lock_guard lock(instruments_mutex_);
    instruments_ = core_.instruments();
  }
  return verdict;
}

FlightTelemetry FlightRuntime::telemetry() const {
  std::lock_guard lock(snapshot_mutex_);
  return snapshot_.telemetry;
}

// --- flight thread ----------------------------------------------------------------------------------

void FlightRuntime::apply(const FlightAction& a) {
  if (a.select_camera) link_.select_camera(*a.select_camera);
  switch (a.kind) {
    case FlightAction::Kind::None: break;
    case FlightAction::Kind::Move: link_.move(a.move); break;
    case FlightAction::Kind::Hover: link_.hover(); break;
    case FlightAction::Kind::Takeoff:
      // A take-off is only accepted while landed: calibrate the IMU's roll/pitch on the ground first
      // (AT*FTRIM, sent before the take-off's AT*REF). Without it the attitude carries the last
      // calibration's offset (~0.6 deg), which the estimator's model reads as a steady push.
      link_.flat_trim();
      link_.takeoff();
      break;
    case FlightAction::Kind::Land: link_.land(); break;
    case FlightAction::Kind::Emergency: link_.emergency(); break;
  }
}

void FlightRuntime::flight_loop() {
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / options_.control_hz));
  auto next_tick = clock::now();
  std::vector<NavdataSample> samples;
  samples.reserve(options_.navdata_ring);
  VideoFrame frame;
  std::deque<std::shared_ptr<PendingRequest>> requests;
  std::uint64_t last_frames = 0;
  Seconds last_fps_t = clock_.now();
  double fps = 0;
  LinkState told_state = LinkState::Disconnected;
  bool have_frame = false;  // `frame` holds a frame the vision has not seen yet
  auto last_tick = clock::time_point{};
  while (running_) {
    {
      std::unique_lock lock(input_mutex_);
      input_cv_.wait_until(lock, next_tick,
                           [&] { return !running_ || !requests_.empty() || core_slot_.fresh || vision_ready_; });
      samples.assign(navdata_.begin(), navdata_.end());
      navdata_.clear();
      if (core_slot_.fresh) {
        if (have_frame) timing_.count_frame_skipped();  // the worker was busy for the whole frame
        std::swap(frame, core_slot_.frame);
        core_slot_.fresh = false;
        have_frame = true;
      }
      vision_ready_ = false;
      requests.swap(requests_);
    }
    if (!running_) break;
    if (const LinkState state = link_state_.load(); state != told_state) {
      core_.on_link_state(state, clock_.now());  // from this thread: the core is single-threaded
      told_state = state;
    }
    for (const auto& s : samples) core_.on_navdata(s);
    for (auto& r : requests) r->verdict.set_value(execute(*r));
    requests.clear();
    step_vision(frame, have_frame);
    if (const auto tick_time = clock::now(); tick_time >= next_tick) {
      if (last_tick != clock::time_point{})
        timing_.add_tick_interval(std::chrono::duration<double, std::milli>(tick_time - last_tick).count());
      last_tick = tick_time;
      const Seconds now = clock_.now();
      apply(core_.tick(now));
      FlightSnapshot snap = core_.status();
      if (now - last_fps_t >= 1.0) {
        const std::uint64_t frames = frames_in_.load();
        fps = static_cast<double>(frames - last_frames) / (now - last_fps_t);
        last_frames = frames;
        last_fps_t = now;
      }
      snap.telemetry.t_unix_s = now + clock_to_unix_s_;
      snap.telemetry.link_state = to_string(link_state_.load());
      snap.telemetry.video_fps = fps;
      timeline_.observe(snap.telemetry.t_unix_s, snap.progress);
      snap.telemetry.timeline = timeline_.timeline();
      if (!snap.events.empty()) {
        std::lock_guard lock(sink_mutex_);
        if (sink_)
          for (const auto& e : snap.events) sink_->on_flight_event(e);
      }
      {
        std::lock_guard lock(snapshot_mutex_);
        snapshot_ = std::move(snap);
      }
      next_tick += period;
      if (next_tick < clock::now()) next_tick = clock::now() + period;  // overran: don't try to catch up
    }
  }
}

void FlightRuntime::step_vision(VideoFrame& newest, bool& have_newest) {
  double run_ms = 0;
  if (vision_.take(vision_results_, run_ms)) {
    if (!vision_results_.failure.empty()) {
      timing_.count_vision_failure();
      std::size_t suppressed = 0;
      if (vision_log_limit_.allow("vision-failure", clock_.now(), &suppressed))
        log_.warn(clock_.now(), "vision: a front-end failed on a frame")
            .kv("error", vision_results_.failure)
            .kv("suppressed", suppressed);
    }
    core_.apply_vision(vision_results_);
    timing_.add_vision((clock_.now() - vision_results_.t) * 1000.0, run_ms, vision_results_.tracking());
  }
  if (!have_newest || !vision_.idle()) return;
  have_newest = false;
  if (!core_.prepare_vision(newest, vision_job_)) return;
  timing_.count_frame_to_vision();
  vision_.submit(vision_job_);
}

// --- video thread -----------------------------------------------------------------------------------

void FlightRuntime::video_loop() {
  VideoFrame frame;
  OverlayModel overlay;
  FlightTelemetry telemetry;
  while (running_) {
    {
      std::unique_lock lock(input_mutex_);
      video_cv_.wait(lock, [&] { return !running_ || video_slot_.fresh; });
      if (!running_) break;
      std::swap(frame, video_slot_.frame);
      video_slot_.fresh = false;
    }
    bool jpeg = false, reading = false, low = false, low_keyframe = false;
    {
      std::lock_guard lock(sink_mutex_);
      if (sink_) {
        jpeg = sink_->wants_jpeg();
        reading = sink_->wants_reading_view();
        low = sink_->wants_low_rendition();
        low_keyframe = low && sink_->take_low_keyframe_request();
      }
    }
    if (!low && low_rendition_.running()) low_rendition_.stop();  // nobody needs it: no encoder runs
    if (!jpeg && !reading && !low) continue;
    {
      std::lock_guard lock(snapshot_mutex_);
      overlay = snapshot_.overlay;
      telemetry = snapshot_.telemetry;
    }
    if (low) publish_low_rendition(frame, overlay, telemetry, low_keyframe);
    if (reading) {
      reading_view_.add_frame(frame, overlay.panel);
      if (auto view = reading_view_.due(overlay.panel, frame.t, clock_to_unix_s_)) {
        std::lock_guard lock(sink_mutex_);
        if (sink_) sink_->on_reading_view(std::move(view));
      }
    }
    if (!jpeg) continue;
    frame.bgr.copyTo(annotated_);
    draw_overlays(annotated_, overlay, telemetry);
    const WireFrame encoded = encoder_.encode(annotated_, frame.frame_number, unix_ms_of(frame.t), frame.camera);
    std::lock_guard lock(sink_mutex_);
    if (sink_) sink_->on_frame(encoded);
  }
}

void FlightRuntime::publish_low_rendition(const VideoFrame& frame, const OverlayModel& overlay,
                                          const FlightTelemetry& telemetry, bool keyframe) {
  WireAccessUnit unit;
  if (!low_rendition_.encode(frame, unix_ms_of(frame.t), keyframe, unit)) return;
  unit.geometry = low_geometry_.write(overlay, telemetry,
                                      {frame.frame_number, unit.capture_unix_ms, frame.camera, frame.bgr.cols, frame.bgr.rows},
                                      clock_to_unix_s_);
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_access_unit(unit);
}

// --- shutdown ---------------------------------------------------------------------------------------

void FlightRuntime::land_and_stop(double timeout_s) {
  if (running_) {
    const CommandVerdict v = request({MissionCommandKind::Land, "", 0});
    log_.info(clock_.now(), "shutdown: landing").kv("accepted", v.accepted).kv("reason", v.reason);
    if (!v.accepted) link_.land();  // the mission layer refused (e.g. already landing): tell the drone directly
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (!telemetry().flying) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    log_.info(clock_.now(), "shutdown: drone on the ground").kv("flying", telemetry().flying);
  }
  stop_threads();
}

void FlightRuntime::stop_threads() {
  if (!running_.exchange(false)) return;
  link_.set_listener(nullptr);
  input_cv_.notify_all();
  video_cv_.notify_all();
  if (flight_thread_.joinable()) flight_thread_.join();
  if (video_thread_.joinable()) video_thread_.join();
  std::lock_guard lock(input_mutex_);
  for (auto& r : requests_) r->verdict.set_value({false, "the server is shutting down"});
  requests_.clear();
}

}  // namespace labo::server
