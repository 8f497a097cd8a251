#include "drone/replay/replay_link.hpp"

#include <limits>
#include <string_view>

namespace labo {

ReplayLink::ReplayLink(const std::filesystem::path& recording, Logger logger)
    : logger_(std::move(logger)), counters_(logger_), reader_(recording) {
  navdata_ = std::make_unique<ardrone2::NavdataReceiver>(
      counters_, [this](const NavdataSample& s, const ardrone2::NavdataPacket&) {
        if (listener_) listener_->on_navdata(s);
      });
  video_ = std::make_unique<ardrone2::VideoReceiver>(
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
    case RecordChannel::Note: {
      const std::string_view note(reinterpret_cast<const char*>(r.bytes.data()), r.bytes.size());
      if (note == kNoteVideoConnected) {
        video_->reset();
      } else if (note == kNoteCameraFront || note == kNoteCameraBottom) {
        video_->set_camera(note == kNoteCameraBottom ? CameraId::Bottom : CameraId::Front);
        video_->reset();
      } else if (note.starts_with(kNoteLinkStatePrefix)) {
        const std::string_view name = note.substr(std::string_view(kNoteLinkStatePrefix).size());
        for (LinkState s : {LinkState::Disconnected, LinkState::Connecting, LinkState::Connected, LinkState::Degraded,
                            LinkState::Lost}) {
          if (to_string(s) == name) {
            state_ = s;
            if (listener_) listener_->on_link_state(s, r.t);
          }
        }
      }
      break;
    }
  }
}

}  // namespace labo
