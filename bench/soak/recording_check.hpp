#pragma once
// Whether a flight recording is complete and replayable: the file holds every byte the writer
// reported, the reader walks its records to the end without a cut or a bad record, and ReplayLink
// plays it through the driver's parsers and decoder to its end.
#include <cstdint>
#include <filesystem>
#include <string>

namespace labo::bench {

struct RecordingCheck {
  std::uint64_t file_bytes = 0;
  std::uint64_t records = 0, record_bytes = 0;  // record_bytes: signature + headers + payloads read
  std::uint64_t navdata = 0, frames = 0;        // what the replay delivered
  bool read_to_end = false;
  std::string error;  // why it was not, when it was not
};

RecordingCheck check_recording(const std::filesystem::path& file);

}  // namespace labo::bench
