#pragma once
// Builders of the committed fixtures under tests/data/ardrone2/ (regenerate them with
// `build/release/tests/test_drone "[.generate]"`): navdata packets in the drone's real layouts and a
// raw TCP 5555 capture made the way the drone streams (libx264 through PaVE, with junk and a
// 68-byte-header stretch).
#include <cstdint>
#include <filesystem>
#include <vector>
#include "core/source_tree.hpp"

namespace labo::test {

std::filesystem::path fixture_dir();  // LABO_TEST_DATA_DIR/ardrone2
std::vector<std::uint8_t> read_bytes(const std::filesystem::path& file);
void write_bytes(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes);

std::vector<std::uint8_t> real_bootstrap_packet();  // the forum capture, 24 bytes
std::vector<std::uint8_t> demo_packet();            // demo + vision_detect: 500 bytes, as by default
std::vector<std::uint8_t> full_packet();            // every known option, plus an unknown tag 28
std::vector<std::uint8_t> video_capture(int frames);

}  // namespace labo::test
