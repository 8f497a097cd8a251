// Replays the fuzz regression corpus (tests/data/fuzz/<target>/) through the harness bodies, so
// every input a fuzzer once found keeps being checked by the normal tests.
#include <catch2/catch.hpp>
#include <filesystem>

#include "fuzz/fuzz_targets.hpp"
#include "tests/drone/ardrone2/fixtures.hpp"
#include "core/source_tree.hpp"

namespace {

template <typename Target>
std::size_t replay_corpus(const std::string& name, Target target) {
  const auto dir = (labo::source_root() / "tests" / "data") / "fuzz" / name;
  std::size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const auto bytes = labo::test::read_bytes(entry.path());
    INFO(entry.path().string());
    CHECK(target(bytes));
    ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("link: fuzz regression corpus replays clean", "[link][fuzz]") {
  CHECK(replay_corpus("navdata", labo::fuzz::navdata_target) >= 3);
  CHECK(replay_corpus("pave", labo::fuzz::pave_target) >= 2);
  CHECK(replay_corpus("at", labo::fuzz::at_target) >= 2);
  CHECK(replay_corpus("tello_state", labo::fuzz::tello_state_target) >= 2);
  CHECK(replay_corpus("tello_video", labo::fuzz::tello_video_target) >= 1);
  CHECK(replay_corpus("tello_reply", labo::fuzz::tello_reply_target) >= 1);
}
