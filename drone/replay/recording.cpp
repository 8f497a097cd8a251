#include "drone/replay/recording.hpp"

#include <cmath>
#include <cstring>

namespace labo::replay {

namespace {
constexpr char kSignature[8] = {'L', 'A', 'B', 'O', 'R', 'E', 'C', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kRecordHeaderBytes = 16;

template <typename T>
void put(char* at, T v) {
  std::memcpy(at, &v, sizeof(T));
}
template <typename T>
T get(const char* at) {
  T v;
  std::memcpy(&v, at, sizeof(T));
  return v;
}
}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& file) : out_(file, std::ios::binary), path_(file) {
  if (!out_) throw RecordingError(file.string() + ": cannot create the recording file");
  char header[12];
  std::memcpy(header, kSignature, 8);
  put(header + 8, kVersion);
  out_.write(header, sizeof(header));
  if (out_) bytes_written_ = sizeof(header);
}

void RecordingWriter::write(RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes) {
  // A chunk longer than a record may be is written as consecutive records of the same channel and
  // time, so that nothing is cut (the reader refuses longer records). The links' chunks are socket
  // reads, far below the limit; the split is for what a caller might one day hand over.
  std::lock_guard lock(mutex_);
  do {
    const std::span<const std::uint8_t> part = bytes.first(std::min(bytes.size(), kMaxRecordBytes));
    char header[kRecordHeaderBytes] = {};
    header[0] = static_cast<char>(channel);
    put(header + 4, t);
    put(header + 12, static_cast<std::uint32_t>(part.size()));
    out_.write(header, sizeof(header));
    out_.write(reinterpret_cast<const char*>(part.data()), static_cast<std::streamsize>(part.size()));
    if (out_) bytes_written_ += sizeof(header) + part.size();
    bytes = bytes.subspan(part.size());
  } while (!bytes.empty());
}

void RecordingWriter::note(Seconds t, const std::string& text) {
  write(RecordChannel::Note, t, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

void RecordingWriter::flush() {
  std::lock_guard lock(mutex_);
  out_.flush();
}

std::uint64_t RecordingWriter::bytes_written() const {
  std::lock_guard lock(mutex_);
  return bytes_written_;
}

RecordingReader::RecordingReader(const std::filesystem::path& file) : in_(file, std::ios::binary), path_(file) {
  if (!in_) throw RecordingError(file.string() + ": cannot open");
  char header[12];
  if (!in_.read(header, sizeof(header)) || std::memcmp(header, kSignature, 8) != 0)
    throw RecordingError(file.string() + ": not a LaboDrone recording (expected the signature LABOREC1)");
  const auto version = get<std::uint32_t>(header + 8);
  if (version != kVersion)
    throw RecordingError(file.string() + ": recording version " + std::to_string(version) + ", expected 1");
}

bool RecordingReader::is_recording(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char sig[8];
  return in.read(sig, 8) && std::memcmp(sig, kSignature, 8) == 0;
}

bool RecordingReader::next(Record& record) {
  char header[kRecordHeaderBytes];
  in_.read(header, sizeof(header));
  if (in_.gcount() == 0) return false;
  const std::string where = path_.string() + ": record " + std::to_string(index_);
  if (in_.gcount() != static_cast<std::streamsize>(sizeof(header))) {
    truncated_ = true;
    return false;
  }
  const auto channel = static_cast<std::uint8_t>(header[0]);
  if (channel < 1 || channel > kMaxRecordChannel) throw RecordingError(where + ": unknown channel " + std::to_string(channel));
  const auto t = get<double>(header + 4);
  const auto length = get<std::uint32_t>(header + 12);
  if (!std::isfinite(t)) throw RecordingError(where + ": time is not finite");
  if (length > kMaxRecordBytes) throw RecordingError(where + ": length " + std::to_string(length) + " beyond 16 MiB");
  record.channel = static_cast<RecordChannel>(channel);
  record.t = t;
  record.bytes.resize(length);
  in_.read(reinterpret_cast<char*>(record.bytes.data()), length);
  if (in_.gcount() != static_cast<std::streamsize>(length)) {
    truncated_ = true;
    return false;
  }
  ++index_;
  return true;
}

RecordedDrone recorded_drone(const std::filesystem::path& file) {
  RecordingReader reader(file);
  Record record;
  while (reader.next(record)) {
    if (record.channel == RecordChannel::Note) continue;
    return static_cast<std::uint8_t>(record.channel) >= static_cast<std::uint8_t>(RecordChannel::TelloCommandOut)
               ? RecordedDrone::Tello
               : RecordedDrone::Ardrone;
  }
  return RecordedDrone::Unknown;
}

}  // namespace labo::replay
