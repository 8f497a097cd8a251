#pragma once
// The real-time side of `labodrone serve`: threads around a DroneLink and a FlightCore.
//  - the link's own threads deliver navdata and frames (DroneLinkListener): they only copy into a
//    bounded navdata ring and two latest-frame slots, and return;
//  - the flight thread owns the FlightCore: it feeds it navdata, runs queued mission requests,
//    ticks at control_hz and sends the action to the link. It never waits for vision: the newest
//    frame's vision is prepared here, run on the vision worker's thread (VisionWorker) and its
//    results applied here with their capture time; frames that come while the worker is busy are
//    skipped, the newest kept;
//  - the video thread takes the newest frame, draws the overlays from the latest snapshot, encodes
//    JPEG and publishes it to the sink (a slow encoder drops frames, never queues them), while
//    anyone watches the JPEG path; and, a few times a second while a panel is tracked, the panel
//    rectified to its template's front view (the reading view);
//  - each access unit of the drone's H.264 stream goes to the sink from the link's thread as it
//    came (no decoding, no re-encoding), with the latest snapshot's overlay geometry, while anyone
//    watches the H.264 path; and, while an H.264 viewer's link cannot carry it, the video thread
//    encodes the newest frame once more into the shared low rendition (one encoder for all of them).
// Emergency stop goes to the link from the caller's thread at once, then to the core.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/lab/flight_service.hpp"
#include "server/runtime/flight_core.hpp"
#include "server/runtime/runtime_timing.hpp"
#include "server/runtime/vision_worker.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_encoder.hpp"
#include "server/video/low_rendition.hpp"
#include "server/video/overlay_geometry.hpp"
#include "server/video/panel_reading_view.hpp"

namespace labo::server {

struct FlightRuntimeOptions {
  double control_hz = 50;
  int jpeg_quality = 75;
  double reading_view_hz = 4;  // the instrument reading view's rate while a panel is tracked
  LowRenditionSettings low_rendition;
  // The drone's cameras and bit rate as its backend knows them, and how to ask the drone for another
  // bit rate (throws std::invalid_argument when refused; empty: no such setting).
  VideoCapabilities video;
  std::function<void(int kbps)> set_video_bitrate;
  std::optional<PinholeCamera> front_camera;  // its lens is undone in the reading view
  LabOutline lab_outline;  // the lab file's room, benches and base, for the page's map
  // After the flight software has placed an instrument: the same in the world the drone flies (the
  // simulated lab draws its panel; throws std::exception naming what failed). Empty: a real lab,
  // where the admin has put the instrument there.
  std::function<void(const lab::InstrumentSpec&)> place_in_world;
  std::size_t navdata_ring = 256;
  double request_timeout_s = 2.0;
};

class FlightRuntime final : public FlightService, private DroneLinkListener {
 public:
  // `clock` is the clock the link stamps its samples with (its epoch is mapped to Unix time here).
  FlightRuntime(DroneLink& link, FlightCore& core, const Clock& clock, FlightRuntimeOptions options, Logger log);
  ~FlightRuntime() override;

  void start();
  void set_sink(FlightEventSink* sink) override;
  CommandVerdict request(const MissionCommand& command) override;
  FlightTelemetry telemetry() const override;
  std::vector<InstrumentSummary> instruments() const override;
  LabOutline lab_outline() const override { return options_.lab_outline; }
  CommandVerdict add_instrument(const lab::InstrumentSpec& spec) override;
  CommandVerdict remove_instrument(const std::string& id) override;
  CommandVerdict set_down_on_platform() override;
  void land_and_stop(double timeout_s) override;
  VideoCapabilities video_capabilities() const override;
  CommandVerdict set_video_bitrate(int kbps) override;

  double unix_ms_of(Seconds t) const { return (t + clock_to_unix_s_) * 1000.0; }
  // Tick intervals, vision latency and frame counts of the flight thread so far.
  RuntimeTimingSummary timing() const override { return timing_.summary(); }

 private:
  void on_navdata(const NavdataSample& sample) override;
  void on_video(const VideoFrame& frame) override;
  void on_encoded_video(const EncodedVideo& unit) override;
  void on_link_state(LinkState state, Seconds t) override;
  void flight_loop();
  // The vision worker's results, applied; then the newest frame handed to it when it is free.
  void step_vision(VideoFrame& newest, bool& have_newest);
  void video_loop();
  // The frame into the low rendition, with its geometry, to the sink (the video thread's).
  void publish_low_rendition(const VideoFrame& frame, const OverlayModel& overlay, const FlightTelemetry& telemetry,
                             bool keyframe);
  void apply(const FlightAction& action);
  void stop_threads();

  struct PendingRequest {
    MissionCommand command;
    // Set: a change to the lab (an instrument placed or removed) rather than the command.
    std::function<CommandVerdict(FlightCore&)> change_lab;
    std::promise<CommandVerdict> verdict;
  };
  std::optional<CommandVerdict> queue_request(std::shared_ptr<PendingRequest> pending);
  CommandVerdict change_lab(std::function<CommandVerdict(FlightCore&)> change);
  CommandVerdict execute(const PendingRequest& request);

  DroneLink& link_;
  FlightCore& core_;
  const Clock& clock_;
  FlightRuntimeOptions options_;
  Logger log_;
  double clock_to_unix_s_ = 0;
  mutable std::mutex instruments_mutex_;
  std::vector<InstrumentSummary> instruments_;  // under instruments_mutex_: the flight thread adds

  std::mutex input_mutex_;  // navdata ring, frame slots, requests
  std::condition_variable input_cv_;
  std::deque<NavdataSample> navdata_;
  // Newest frame for the flight software and for the encoder. The link's pixels are copied in (it
  // may reuse its buffer); a consumer swaps the slot's Mat with its own, so no copy allocates.
  struct FrameSlot {
    VideoFrame frame;
    bool fresh = false;
  };
  FrameSlot core_slot_;
  FrameSlot video_slot_;
  std::condition_variable video_cv_;
  std::deque<std::shared_ptr<PendingRequest>> requests_;
  std::atomic<LinkState> link_state_{LinkState::Disconnected};
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> frames_in_{0};
  bool vision_ready_ = false;  // under input_mutex_: the worker finished a job

  RuntimeTiming timing_;
  RateLimiter vision_log_limit_{5.0};
  fusion::VisionJob vision_job_;          // the flight thread's, swapped with the worker's
  fusion::VisionResults vision_results_;  // likewise
  StageTimeline timeline_;                // the flight thread's, copied into each snapshot

  mutable std::mutex snapshot_mutex_;
  FlightSnapshot snapshot_;
  double video_fps_ = 0;

  std::mutex sink_mutex_;
  FlightEventSink* sink_ = nullptr;
  mutable std::mutex video_mutex_;  // options_.video's bit rate, changed by an admin

  FrameEncoder encoder_;
  cv::Mat annotated_;
  PanelReadingView reading_view_;  // the video thread's
  LowRendition low_rendition_;     // the video thread's
  OverlayGeometryWriter low_geometry_;
  // The link's video thread's (on_encoded_video): pooled wire buffers, the snapshot copied in.
  AccessUnitPacker packer_;
  OverlayGeometryWriter geometry_;
  OverlayModel unit_overlay_;
  FlightTelemetry unit_telemetry_;
  std::thread flight_thread_;
  std::thread video_thread_;
  VisionWorker vision_;  // last: its thread calls back into input_cv_
};

}  // namespace labo::server
