#pragma once
// What TelloLink and ReplayLink share, without any I/O: state and video datagrams in (with their
// receive time), NavdataSample and VideoFrame events out, every bad input counted by kind (and logged
// at most once a second per kind). Live and replayed flights go through the very same code.
//
// TelloStateReceiver also keeps the flight phase (TelloFlightPhase) from the commands' events, since
// the state string has none: each sample's control_state is the link's account at that moment. The
// commands' events come from the link's control thread and the datagrams from its state thread: the
// phase is under a lock; the parse and the handler run on the state thread alone, in order.
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/drone_link.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_command.hpp"
#include "drone/tello/tello_flight_phase.hpp"
#include "drone/tello/tello_state.hpp"

namespace labo::tello {

using ardrone2::LinkCounters;

class TelloStateReceiver {
 public:
  using Handler = std::function<void(const NavdataSample&, const TelloState&)>;
  TelloStateReceiver(LinkCounters& counters, Handler handler);

  // One UDP 8890 datagram. True when it was a valid state string.
  bool datagram(std::span<const std::uint8_t> bytes, Seconds t);
  // The commands' side of the flight phase.
  void command_sent(std::string_view command, Seconds t);
  void command_finished(const CommandOutcome& outcome, Seconds t);
  void sticks(bool centred);
  int control_state() const;
  int unexpected_landings() const;

 private:
  LinkCounters& counters_;
  Handler handler_;
  TelloStateParser parser_;
  mutable std::mutex phase_mutex_;
  TelloFlightPhase phase_;
  TelloState state_;        // state thread only
  NavdataSample sample_;    // state thread only
  std::uint32_t sequence_ = 0;
};

// Frames are labelled by their size: the downward camera's (kDownvisionWidth x kDownvisionHeight,
// after "downvision 1" on a Tello EDU) Bottom, any other Front.
class TelloVideoReceiver {
 public:
  using Handler = std::function<void(const VideoFrame&)>;
  using EncodedHandler = std::function<void(const EncodedVideo&)>;
  // `encoded`, when given, receives each access unit (from the first IDR after a reset on), before
  // the handler gets its decoded frame; its size is the decoder's (0 before a first decoded frame).
  TelloVideoReceiver(LinkCounters& counters, Handler handler, EncodedHandler encoded = {});
  // One UDP 11111 datagram.
  void datagram(std::span<const std::uint8_t> bytes, Seconds t);
  // A new stream (streamon again, reconnection): drop partial data, wait for the next IDR.
  void reset();

 private:
  void decode(std::span<const std::uint8_t> access_unit);
  static CameraId camera_of(int width, int height);

  LinkCounters& counters_;
  Handler handler_;
  EncodedHandler encoded_;
  bool forward_seen_idr_ = false;
  AnnexBAssembler assembler_;
  ardrone2::H264Decoder decoder_;
  VideoFrame frame_;
  Seconds t_ = 0;  // receive time of the datagram being fed
  std::uint32_t frame_number_ = 0;
};

}  // namespace labo::tello
