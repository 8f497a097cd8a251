#pragma once
// What ArdroneLink and ReplayLink share, without any I/O: raw navdata datagrams and TCP video chunks
// in (with their receive time), NavdataSample and VideoFrame events out, every bad input counted by
// kind. Live and replayed flights therefore go through the very same code. One receiver per thread.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/navdata_parser.hpp"
#include "drone/ardrone2/pave.hpp"
#include "drone/drone_link.hpp"

namespace labo::ardrone2 {

class NavdataReceiver {
 public:
  using Handler = std::function<void(const NavdataSample&, const NavdataPacket&)>;
  NavdataReceiver(LinkCounters& counters, Handler handler);
  // One UDP 5554 datagram. True when it was valid and in order (the link is alive).
  bool datagram(std::span<const std::uint8_t> bytes, Seconds t);
  void reset_sequence() { sequence_.reset(); }
  // The last datagram's sequence started counting again (NavdataSequenceFilter::restarted()).
  bool sequence_restarted() const { return sequence_.restarted(); }

 private:
  LinkCounters& counters_;
  Handler handler_;
  NavdataParser parser_;
  NavdataPacket packet_;
  NavdataSequenceFilter sequence_;
  NavdataSample sample_;
};

class VideoReceiver {
 public:
  using Handler = std::function<void(const VideoFrame&)>;
  using EncodedHandler = std::function<void(const EncodedVideo&)>;
  // A frame sent in several PaVE packets (slices) is joined before it is decoded. `encoded`, when
  // given, receives each access unit before it is decoded, from the first IDR after a reset on.
  VideoReceiver(LinkCounters& counters, Handler handler, EncodedHandler encoded = {});
  // Bytes from TCP 5555 as they came.
  void bytes(std::span<const std::uint8_t> bytes, Seconds t);
  // A new TCP connection or a camera switch: drop partial data, wait for the next IDR.
  void reset();
  // The camera frames are attributed to (the stream does not say which camera it carries).
  void set_camera(CameraId camera) { camera_ = camera; }

 private:
  // The access unit `pave` completes (its own payload, or the joined slices of its frame); empty
  // while a frame's slices are still coming or when one was lost.
  std::span<const std::uint8_t> assemble(const PaveFrame& pave);
  void forward(std::span<const std::uint8_t> unit, const PaveHeader& h, Seconds t);

  LinkCounters& counters_;
  Handler handler_;
  EncodedHandler encoded_;
  PaveDemuxer demuxer_;
  H264Decoder decoder_;
  VideoFrame frame_;
  CameraId camera_ = CameraId::Front;
  std::vector<std::uint8_t> slices_;  // the slices of a frame sent in several PaVE packets, so far
  std::uint32_t slices_frame_ = 0;
  std::uint8_t slices_next_ = 0;      // the slice index expected next (0: a new frame)
  bool forward_seen_idr_ = false;
};

}  // namespace labo::ardrone2
