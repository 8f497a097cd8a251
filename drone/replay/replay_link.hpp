#pragma once
// ReplayLink: a DroneLink that plays a recording (drone/replay/recording.hpp) back through the very
// same receivers as the live link that wrote it (ArdroneLink: navdata parser, PaVE demuxer, H.264
// decoder; TelloLink: state parser, flight phase, Annex-B assembler, H.264 decoder), so an offline run
// sees byte-identical input and yields the same events with the same times. A Tello's replies are
// matched to the commands recorded before them, as the live link matched them. Lockstep: nothing happens
// until advance_to(t) or run_to_end(); events reach the listener synchronously on the caller's thread.
// Commands are ignored (the recording already holds what was sent); they are counted.
#include <filesystem>
#include <memory>

#include "core/log.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/link_receiver.hpp"
#include "drone/drone_link.hpp"
#include "drone/replay/recording.hpp"
#include "drone/tello/tello_receivers.hpp"

namespace labo::replay {

class ReplayLink final : public DroneLink {
 public:
  // Throws RecordingError when the file is not a recording.
  ReplayLink(const std::filesystem::path& recording, Logger logger);

  // Feeds every record with time <= t. Returns false once the recording is exhausted.
  bool advance_to(Seconds t);
  void run_to_end();
  // Time of the next record, or +inf at the end.
  Seconds next_time() const;
  bool truncated() const { return reader_.truncated(); }

  void set_listener(DroneLinkListener* listener) override { listener_ = listener; }
  void takeoff() override { counters_.add("replay_command_ignored"); }
  void land() override { counters_.add("replay_command_ignored"); }
  void emergency() override { counters_.add("replay_command_ignored"); }
  void flat_trim() override { counters_.add("replay_command_ignored"); }
  void move(const MoveCommand&) override { counters_.add("replay_command_ignored"); }
  void hover() override { counters_.add("replay_command_ignored"); }
  void select_camera(CameraId) override { counters_.add("replay_command_ignored"); }
  void set_config(const std::string&, const std::string&) override { counters_.add("replay_command_ignored"); }
  LinkState state() const override { return state_; }
  LinkStatistics statistics() const override { return counters_.snapshot(); }

 private:
  void play(const Record& record);
  void play_note(std::string_view note, Seconds t);
  void play_tello_command(std::string_view text, Seconds t);
  void play_tello_reply(std::span<const std::uint8_t> bytes, Seconds t);
  void load_next();

  Logger logger_;
  ardrone2::LinkCounters counters_;
  RecordingReader reader_;
  Record record_;
  bool have_record_ = false;
  DroneLinkListener* listener_ = nullptr;
  LinkState state_ = LinkState::Disconnected;
  std::unique_ptr<ardrone2::NavdataReceiver> navdata_;
  std::unique_ptr<ardrone2::VideoReceiver> video_;
  std::unique_ptr<tello::TelloStateReceiver> tello_state_;
  std::unique_ptr<tello::TelloVideoReceiver> tello_video_;
  std::string tello_awaiting_;  // the Tello command sent and not answered yet
};

}  // namespace labo::replay
