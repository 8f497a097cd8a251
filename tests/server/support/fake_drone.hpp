#pragma once
// Test doubles for the runtime: a DroneLink that records what it is told and delivers frames and
// navdata when asked (or from its own 30 fps thread), and a FlightCore that walks a scripted
// inspection through its stages. Tests and the browser test's fixture server only.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <utility>

#include "drone/ardrone2/h264_codec.hpp"
#include "server/runtime/flight_core.hpp"

namespace labo::server::test {

class FakeDroneLink final : public DroneLink {
 public:
  ~FakeDroneLink() override { stop_pump(); }
  void set_listener(DroneLinkListener* l) override {
    std::lock_guard lock(mutex_);
    listener_ = l;
  }
  void takeoff() override { takeoffs++; }
  void land() override { lands++; }
  void emergency() override {
    emergency_at = std::chrono::steady_clock::now();
    emergencies++;
  }
  void flat_trim() override {}
  void move(const MoveCommand&) override { moves++; }
  void hover() override {}
  void select_camera(CameraId camera) override {
    std::lock_guard lock(mutex_);
    camera_ = camera;
  }
  CameraId camera() const {
    std::lock_guard lock(mutex_);
    return camera_;
  }
  void set_config(const std::string&, const std::string&) override {}
  LinkState state() const override { return LinkState::Connected; }
  LinkStatistics statistics() const override { return {}; }

  // A moving test card: stripes that scroll, and the frame number written on it.
  // Textured frames (smoothed noise, like a real room) cost the JPEG encoder what camera images do.
  void set_textured(bool textured) {
    if (!textured) return texture_.release();
    texture_.create(360, 640, CV_8UC3);
    cv::RNG(3).fill(texture_, cv::RNG::UNIFORM, 0, 255);
    cv::GaussianBlur(texture_, texture_, {5, 5}, 1.2);
  }
  // With H.264 on, each frame is also encoded (an IDR every 15 frames, like the drone) and its access
  // unit delivered before the frame, as ArdroneLink does.
  void set_h264(bool on) {
    if (on) encoder_ = std::make_unique<ardrone2::H264Encoder>(ardrone2::H264EncoderSettings{.bitrate_kbps = 4000});
    else encoder_.reset();
  }
  void deliver_frame(std::uint32_t n, Seconds t) {
    frame_.create(360, 640, CV_8UC3);
    if (texture_.empty()) frame_.setTo(cv::Scalar(90, 110, 90));
    else texture_.copyTo(frame_);
    for (int x = -80; x < 640; x += 80) cv::rectangle(frame_, cv::Rect(x + static_cast<int>(n * 4 % 80), 120, 40, 120), {200, 200, 200}, cv::FILLED);
    // The bottom camera (once selected) shows the floor: a dark card with its name on it.
    const CameraId cam = camera();
    if (cam == CameraId::Bottom) frame_.setTo(cv::Scalar(40, 60, 90));
    cv::putText(frame_, (cam == CameraId::Bottom ? "bottom, frame " : "frame ") + std::to_string(n), {40, 320},
                cv::FONT_HERSHEY_SIMPLEX, 1.0, {255, 255, 255}, 2);
    VideoFrame f{t, cam, n, frame_};
    if (encoder_) encoder_->encode(frame_, encoded_);
    std::lock_guard lock(mutex_);
    if (!listener_) return;
    if (encoder_) listener_->on_encoded_video({t, cam, n, encoded_.keyframe, 640, 360, encoded_.data});
    listener_->on_video(f);
  }
  void deliver_navdata(Seconds t, double altitude_m) {
    NavdataSample s;
    s.t = t;
    s.altitude_m = altitude_m;
    s.battery_percent = 87;
    std::lock_guard lock(mutex_);
    if (listener_) listener_->on_navdata(s);
  }
  // Frames at `fps` and navdata at 15 Hz from a thread, stamped with `clock`.
  void start_pump(const Clock& clock, double fps) {
    running_ = true;
    pump_ = std::thread([this, &clock, fps] {
      std::uint32_t n = 0;
      auto next = std::chrono::steady_clock::now();
      while (running_) {
        deliver_frame(n, clock.now());
        if (n % 2 == 0) deliver_navdata(clock.now(), 1.0);
        ++n;
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / fps));
        std::this_thread::sleep_until(next);
      }
    });
  }
  void stop_pump() {
    running_ = false;
    if (pump_.joinable()) pump_.join();
  }

  std::atomic<int> takeoffs{0}, lands{0}, emergencies{0}, moves{0};
  std::chrono::steady_clock::time_point emergency_at{};

 private:
  mutable std::mutex mutex_;
  DroneLinkListener* listener_ = nullptr;
  CameraId camera_ = CameraId::Front;
  cv::Mat frame_, texture_;
  std::unique_ptr<ardrone2::H264Encoder> encoder_;
  ardrone2::EncodedFrame encoded_;
  std::atomic<bool> running_{false};
  std::thread pump_;
};

// Walks an inspection through named stages, `stage_s` seconds each, and reports a tracked panel.
class ScriptedCore final : public FlightCore {
 public:
  explicit ScriptedCore(double stage_s = 1.0, double request_delay_s = 0.0) : stage_s_(stage_s), request_delay_s_(request_delay_s) {}
  void on_navdata(const NavdataSample& s) override { battery_ = s.battery_percent; }
  void on_video(const VideoFrame& f) override {
    frames++;
    last_frame_t_ = f.t;
  }
  void on_link_state(LinkState, Seconds) override {}
  FlightAction tick(Seconds t) override {
    now_ = t;
    FlightAction a;
    a.select_camera = std::exchange(camera_wanted_, std::nullopt);
    if (mission_ == "inspect") {
      const int stage = 1 + static_cast<int>((t - started_) / stage_s_);
      stage_index_ = std::min(stage, 6);
      stage_ = stage <= 6 ? std::to_string(stage) + " " + kStages[stage - 1] : "done";
      if (stage > 6) {
        mission_ = "idle";
        ++missions_ended_;
        last_result_ = "succeeded: inspected 'oscilloscope' and landed";
      }
      a.kind = FlightAction::Kind::Move;
      a.move.pitch = 0.1;
    }
    return a;
  }
  CommandVerdict request(const MissionCommand& c, Seconds t) override {
    if (request_delay_s_ > 0) std::this_thread::sleep_for(std::chrono::duration<double>(request_delay_s_));
    requests++;
    switch (c.kind) {
      case MissionCommandKind::Inspect:
        if (c.instrument != "oscilloscope") return {false, "no instrument '" + c.instrument + "'"};
        mission_ = "inspect";
        started_ = t;
        flying_ = true;
        return {true, "inspecting " + c.instrument};
      case MissionCommandKind::EmergencyStop:
        mission_ = "emergency";
        stage_ = "motors cut";
        flying_ = false;
        return {true, "motors cut"};
      case MissionCommandKind::Land:
      case MissionCommandKind::Stop:
        flying_ = false;
        mission_ = "idle";
        return {true, "landing"};
      case MissionCommandKind::SelectCamera:
        if (mission_ == "inspect") return {false, "select_camera: mission 'inspect' chooses the camera while it runs"};
        camera_wanted_ = c.camera;
        return {true, "select_camera"};
      default:
        flying_ = c.kind != MissionCommandKind::ReturnHome;
        return {true, to_string(c.kind)};
    }
  }
  // As the flight stack: refused while it flies, accepted on the ground.
  CommandVerdict set_down_on_platform() override {
    if (flying_) return {false, "set-down: the drone is flying; land it, then set it on its platform"};
    return {true, "the drone was set on its platform: its place is the base's again"};
  }
  FlightSnapshot status() override {
    FlightSnapshot s;
    s.telemetry.mission = mission_;
    s.telemetry.stage = stage_;
    s.telemetry.flying = flying_;
    s.telemetry.battery_percent = battery_;
    s.telemetry.altitude_m = flying_ ? 1.0 : 0.0;
    s.telemetry.pose = {0.5 * std::sin(now_), 0.3 * std::cos(now_), flying_ ? 1.0 : 0.0, 0.1 * now_};
    s.telemetry.desired = PoseXyzYaw{1.2, 0.0, 1.0, 0.0};
    s.telemetry.source = mission_ == "inspect" ? PoseSource::Homography : PoseSource::Slam;
    s.telemetry.link_quality = 0.9;
    // Progress as the flight stack reports it: a stage count only while the inspection runs; an
    // emergency ends it uncounted (the timeline names it from the mission).
    s.progress = {mission_, stage_index_, mission_ == "inspect" ? 6 : 0, stage_, missions_ended_, last_result_};
    s.telemetry.slam_points = slam_points_;
    s.overlay.panel.corners = {{220, 100}, {420, 100}, {420, 220}, {220, 220}};
    s.overlay.panel.axes = AxesPx{{320, 160}, {380, 160}, {320, 220}, {300, 140}};
    s.overlay.panel.measured_t = last_frame_t_;  // "tracked" on the newest frame
    s.overlay.panel.template_px = {400, 240};
    if (stage_ != last_stage_) {
      s.events.push_back({"stage", mission_, stage_, mission_ + ": " + stage_});
      last_stage_ = stage_;
    }
    return s;
  }
  std::vector<InstrumentSummary> instruments() const override { return {{"oscilloscope", "Oscilloscope", 0.3, 0.15, 2.0, 0.5}}; }

  std::atomic<int> frames{0};
  std::atomic<int> requests{0};

 private:
  static constexpr const char* kStages[6] = {"take off", "explore", "approach", "hold", "return", "land"};
  double stage_s_, request_delay_s_;
  std::string mission_ = "idle", stage_, last_stage_;
  double started_ = 0, now_ = 0, battery_ = 0, last_frame_t_ = -1;
  int stage_index_ = 0, missions_ended_ = 0;
  std::string last_result_;
  // The SLAM map from above: a ring of 120 points 1.2 m round the base (inside the lab file's room), one revision.
  std::shared_ptr<const fusion::SlamPointsXy> slam_points_ = [] {
    auto p = std::make_shared<fusion::SlamPointsXy>();
    p->revision = 1;
    p->map_id = 1;
    p->cell_m = 0.10;
    for (int i = 0; i < 120; ++i) p->xy_world.emplace_back(1.2f * std::cos(i * 0.0524f), 1.2f * std::sin(i * 0.0524f));
    return p;
  }();
  bool flying_ = false;
  std::optional<CameraId> camera_wanted_;
};

}  // namespace labo::server::test
