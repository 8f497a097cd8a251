#include "drone/replay/replay_link.hpp"

#include <limits>
#include <string_view>

#include "drone/tello/tello_rc.hpp"

namespace labo::replay {

ReplayLink::ReplayLink(const std::filesystem::path& recording, Logger logger)
    : logger_(std::move(logger)), counters_(logger_), reader_(recording) {
  navdata_ = std::make_unique<ardrone2::NavdataReceiver>(
      counters_, [this](const NavdataSample& s, const ardrone2::NavdataPacket& p) {
        if (listener_ && p.has(ardrone2::kTagDemo)) listener_->on_navdata(s);  // as ArdroneLink does
      });
  video_ = std::make_unique<ardrone2::VideoReceiver>(
      counters_, [this](const VideoFrame& f) {
        if (listener_) listener_->on_video(f);
      },
      [this](const EncodedVideo& unit) {
        if (listener_) listener_->on_encoded_video(unit);
      });
  tello_state_ = std::make_unique<tello::TelloStateReceiver>(counters_, [this](const NavdataSample& s, const tello::TelloState&) {
    if (listener_) listener_->on_navdata(s);
  });
  tello_video_ = std::make_unique<tello::TelloVideoReceiver>(
      counters_, [this](const VideoFrame& f) {
        if (listener_) listener_->on_video(f);
      },
      [this](const EncodedVideo& unit) {
        if (listener_) listener_->on_encoded_video(unit);
      });
  load_next();
}

void ReplayLink::load_next() { have_record_ = reader_.next(record_); }

Seconds ReplayLink::next_time() const {
  return have_record_ ? record_.t : std::numeric_limits<Seconds>::infinity();
}

bool ReplayLink::advance_to(Seconds t) {
  while (have_record_ && record_.t <= t) {
    play(record_);
    load_next();
  }
  return have_record_;
}

void ReplayLink::run_to_end() {
  while (have_record_) {
    play(record_);
    load_next();
  }
}

void ReplayLink::play(const Record& r) {
  counters_.add("replay_records");
  switch (r.channel) {
    case RecordChannel::NavdataIn:
      navdata_->datagram(r.bytes, r.t);
      break;
    case RecordChannel::NavdataOut:
      navdata_->reset_sequence();  // the live link resets its expectation with every kick it sends
      break;
    case RecordChannel::VideoIn:
      video_->bytes(r.bytes, r.t);
      break;
    case RecordChannel::AtOut:
      break;
    case RecordChannel::Note:
      play_note(std::string_view(reinterpret_cast<const char*>(r.bytes.data()), r.bytes.size()), r.t);
      break;
    case RecordChannel::TelloCommandOut:
      play_tello_command(std::string_view(reinterpret_cast<const char*>(r.bytes.data()), r.bytes.size()), r.t);
      break;
    case RecordChannel::TelloReplyIn:
      play_tello_reply(r.bytes, r.t);
      break;
    case RecordChannel::TelloStateIn:
      tello_state_->datagram(r.bytes, r.t);
      break;
    case RecordChannel::TelloVideoIn:
      tello_video_->datagram(r.bytes, r.t);
      break;
  }
}

void ReplayLink::play_note(std::string_view note, Seconds t) {
  if (note == kNoteVideoConnected) {
    video_->reset();
    tello_video_->reset();
  } else if (note == kNoteCameraFront || note == kNoteCameraBottom) {
    video_->set_camera(note == kNoteCameraBottom ? CameraId::Bottom : CameraId::Front);
    video_->reset();
  } else if (note.starts_with(kNoteLinkStatePrefix)) {
    const std::string_view name = note.substr(std::string_view(kNoteLinkStatePrefix).size());
    for (LinkState s : {LinkState::Disconnected, LinkState::Connecting, LinkState::Connected, LinkState::Degraded,
                        LinkState::Lost}) {
      if (to_string(s) == name) {
        state_ = s;
        if (listener_) listener_->on_link_state(s, t);
      }
    }
  } else if (note.starts_with(kNoteTelloGaveUpPrefix) && !tello_awaiting_.empty()) {
    const std::string_view why = note.substr(std::string_view(kNoteTelloGaveUpPrefix).size());
    tello::CommandOutcome outcome;
    outcome.result = why.starts_with("abandoned") ? tello::CommandOutcome::Result::Abandoned
                                                  : tello::CommandOutcome::Result::TimedOut;
    outcome.command = std::move(tello_awaiting_);
    tello_awaiting_.clear();
    tello_state_->command_finished(outcome, t);
  }
}

// What the live TelloLink did when it sent this: rc moves the sticks, anything else waits for a reply.
void ReplayLink::play_tello_command(std::string_view text, Seconds t) {
  if (text.starts_with("rc ")) {
    tello::RcSticks sticks;
    if (tello::parse_rc_arguments(text.substr(3), sticks)) tello_state_->sticks(sticks.centred());
    return;
  }
  tello_state_->command_sent(text, t);
  tello_awaiting_.assign(text);
}

void ReplayLink::play_tello_reply(std::span<const std::uint8_t> bytes, Seconds t) {
  tello::TelloReply reply;
  if (const tello::ReplyError error = tello::parse_reply(bytes, reply); error != tello::ReplyError::None) {
    counters_.bad_input(to_string(error), t, "reply refused");
    return;
  }
  if (tello_awaiting_.empty()) {
    counters_.bad_input("tello_reply_unsolicited", t, "a reply while no command waits");
    return;
  }
  tello::CommandOutcome outcome{tello::result_of(reply.kind), std::move(tello_awaiting_), std::string(reply.text), t, t, 1};
  tello_awaiting_.clear();
  tello_state_->command_finished(outcome, t);
}

}  // namespace labo::replay
