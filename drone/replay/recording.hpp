#pragma once
// The flight recording format (docs/recording.md): every raw datagram and TCP chunk, in and out, with
// its time on the link's clock, in one append-only file. A recording replays through the very same
// parsers and decoder (ReplayLink), so an offline run sees byte-identical input.
//
//   file   = "LABOREC1" (8 bytes) u32 version (=1) record*
//   record = u8 channel, u8 reserved (0), u16 reserved (0), f64 t_s, u32 length, length bytes
// little-endian; channel: 1 AT out (UDP 5556), 2 navdata out (UDP 5554), 3 navdata in, 4 video in
// (one TCP 5555 read), 5 note (UTF-8 text: link state changes, config sent); a Tello's: 6 command
// out (UDP 8889, "rc" included), 7 reply in (UDP 8889), 8 state in (UDP 8890), 9 video in (one UDP
// 11111 datagram). Records are in write order; the link's threads write concurrently, so times are
// monotonic per channel only.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace labo::replay {

enum class RecordChannel : std::uint8_t {
  AtOut = 1,
  NavdataOut = 2,
  NavdataIn = 3,
  VideoIn = 4,
  Note = 5,
  TelloCommandOut = 6,
  TelloReplyIn = 7,
  TelloStateIn = 8,
  TelloVideoIn = 9,
};
inline constexpr std::uint8_t kMaxRecordChannel = 9;
inline constexpr std::size_t kMaxRecordBytes = 16u << 20;

// Notes the replay acts on (others are for people reading a recording).
inline constexpr const char* kNoteLinkStatePrefix = "link_state ";  // + to_string(LinkState)
inline constexpr const char* kNoteVideoConnected = "video_connected";
inline constexpr const char* kNoteCameraFront = "video_camera front";
inline constexpr const char* kNoteCameraBottom = "video_camera bottom";
// A Tello command that ended without its reply: + "timed_out <command>" or "abandoned <command>".
inline constexpr const char* kNoteTelloGaveUpPrefix = "tello_command_gave_up ";

class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thread-safe writer (the link's threads share one).
class RecordingWriter {
 public:
  explicit RecordingWriter(const std::filesystem::path& file);  // throws RecordingError
  void write(RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes);
  void note(Seconds t, const std::string& text);
  void flush();
  // The bytes the file holds once flushed (signature and records): what a check of a recording's
  // completeness compares the file's size with. A write the stream refused is not counted.
  std::uint64_t bytes_written() const;

 private:
  mutable std::mutex mutex_;
  std::ofstream out_;
  std::uint64_t bytes_written_ = 0;
  std::filesystem::path path_;
};

struct Record {
  RecordChannel channel = RecordChannel::Note;
  Seconds t = 0;
  std::vector<std::uint8_t> bytes;
};

class RecordingReader {
 public:
  // Throws RecordingError naming the file when it is not a recording.
  explicit RecordingReader(const std::filesystem::path& file);
  // Next record into `record` (its buffer reused); false at the end. A record cut short at the end
  // of the file (a crash during the flight) ends the reading and sets truncated(); any other
  // inconsistency (unknown channel, absurd length, non-finite time) throws RecordingError.
  bool next(Record& record);
  bool truncated() const { return truncated_; }
  // True when the file starts with the recording signature.
  static bool is_recording(const std::filesystem::path& file);

 private:
  std::ifstream in_;
  std::filesystem::path path_;
  std::uint64_t index_ = 0;
  bool truncated_ = false;
};

// Which drone a recording's link spoke to: the first record of a protocol channel says (AT, navdata
// or PaVE video: an AR.Drone; channels 6-9: a Tello); Unknown when it holds none. Throws
// RecordingError as RecordingReader does.
enum class RecordedDrone { Unknown, Ardrone, Tello };
RecordedDrone recorded_drone(const std::filesystem::path& file);

}  // namespace labo::replay
