#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;

namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("labodrone_slam_test_" + std::to_string(::getpid()) + "_" + name);
}

void truncate_file(const std::filesystem::path& from, const std::filesystem::path& to, std::uintmax_t bytes) {
  std::ifstream in(from, std::ios::binary);
  std::vector<char> data(bytes);
  in.read(data.data(), static_cast<std::streamsize>(bytes));
  std::ofstream(to, std::ios::binary).write(data.data(), static_cast<std::streamsize>(bytes));
}

}  // namespace

TEST_CASE("slam: map save/load round trip, and refusals of bad map files") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 7.0);
  SlamSystem mapper(camera, testing::synchronous());
  const auto run = testing::run(mapper, room, frames);
  REQUIRE(run.results.back().T_cam_map);
  const auto file = temp_file("map.bin");
  mapper.save_map(file);
  const SlamStatus saved = mapper.status();

  SECTION("a new system loads it and relocalizes in the same map") {
    SlamSystem user(camera, testing::synchronous());
    user.load_map(file);
    const SlamStatus loaded = user.status();
    CHECK(loaded.keyframes == saved.keyframes);
    CHECK(loaded.map_points == saved.map_points);
    CHECK(loaded.state == TrackingState::Lost);
    std::optional<Eigen::Isometry3d> pose;
    for (int i = 0; i < 10 && !pose; ++i) {
      const SlamResult r = user.track(room.render(frames.back().T_world_cam, 500u + static_cast<unsigned>(i)), 100.0 + i);
      if (r.state == TrackingState::Good) pose = r.T_cam_map;
    }
    REQUIRE(pose);
    CHECK((pose->inverse().translation() - run.tracked.back().estimate_T_map_cam.translation()).norm() < 0.05);
  }

  SECTION("a truncated file is refused and the current map is kept") {
    const auto cut = temp_file("cut.bin");
    truncate_file(file, cut, std::filesystem::file_size(file) / 2);
    try {
      mapper.load_map(cut);
      FAIL("truncated map accepted");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()).find("truncated") != std::string::npos);
    }
    CHECK(mapper.status().keyframes == saved.keyframes);
    std::filesystem::remove(cut);
  }

  SECTION("a corrupted byte is caught by the checksum") {
    const auto bad = temp_file("bad.bin");
    std::filesystem::copy_file(file, bad, std::filesystem::copy_options::overwrite_existing);
    {
      std::fstream f(bad, std::ios::binary | std::ios::in | std::ios::out);
      f.seekp(200);
      f.put('\x5a');
    }
    SlamSystem other(camera, testing::synchronous());
    CHECK_THROWS_WITH(other.load_map(bad), Catch::Contains("checksum"));
    std::filesystem::remove(bad);
  }

  SECTION("a map built with another camera is refused with the field that differs") {
    CameraIntrinsics k = camera.intrinsics();
    k.fx += 5;
    SlamSystem other(PinholeCamera(k), testing::synchronous());
    CHECK_THROWS_WITH(other.load_map(file), Catch::Contains("another camera") && Catch::Contains("fx"));
    CHECK(other.status().keyframes == 0);
  }

  SECTION("a file that is not a map") {
    const auto junk = temp_file("junk.bin");
    std::ofstream(junk) << "hello";
    SlamSystem other(camera, testing::synchronous());
    CHECK_THROWS_WITH(other.load_map(junk), Catch::Contains("not a LaboDrone map"));
    CHECK_THROWS_WITH(other.load_map(temp_file("missing.bin")), Catch::Contains("cannot open"));
    std::filesystem::remove(junk);
  }
  std::filesystem::remove(file);
}
