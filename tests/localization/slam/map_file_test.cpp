#include <catch2/catch.hpp>
#include <filesystem>
#include <cstring>
#include <fstream>

#include "localization/slam/io/map_file.hpp"
#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;
using namespace labo::bench;  // the synthetic room and its flights

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

std::uint64_t fnv1a(const std::vector<char>& bytes, std::size_t size) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= static_cast<std::uint8_t>(bytes[i]);
    h *= 1099511628211ull;
  }
  return h;
}

// A tiny map: two keyframes with one feature each, one point seen by both, one loop edge.
void tiny_map(SlamMap& map) {
  for (int k = 0; k < 2; ++k) {
    Keyframe kf;
    kf.t = k;
    kf.T_cam_map.translation() = Eigen::Vector3d(0.1 * k, 0, 0);
    Feature f;
    f.px = Eigen::Vector2d(300 + k, 200);
    f.image_px = f.px.cast<float>();
    kf.frame.features.push_back(f);
    kf.frame.descriptors.push_back(Descriptor{});
    map.add_keyframe(std::move(kf));
  }
  MapPoint p;
  p.p_map = Eigen::Vector3d(0, 0, 2);
  p.observations = {{0, 0}, {1, 0}};
  p.reference_keyframe = 0;
  map.add_point(std::move(p));
  LoopEdge e{1, 0, {}};
  e.measured.scale = 0.97;
  e.measured.R = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  e.measured.t = Eigen::Vector3d(0.1, 0.2, 0.3);
  map.add_loop_edge(e);
}

}  // namespace

TEST_CASE("slam: map file keeps the loop edges, a file of another version is refused with the reason") {
  const CameraIntrinsics camera = PinholeCamera::ardrone2_front().intrinsics();
  SlamMap map;
  tiny_map(map);
  const auto file = temp_file("loops.bin");
  write_map_file(file, camera, map);
  SlamMap loaded;
  read_map_file(file, camera, loaded);
  REQUIRE(loaded.loop_edges().size() == 1);
  const LoopEdge& e = loaded.loop_edges()[0];
  CHECK(e.current == 1);
  CHECK(e.loop == 0);
  CHECK(e.measured.scale == 0.97);
  CHECK(e.measured.R.isApprox(map.loop_edges()[0].measured.R));
  CHECK(e.measured.t.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));

  // The same bytes stamped version 1 (before loop edges), with a valid checksum: refused by version.
  std::vector<char> bytes(std::filesystem::file_size(file));
  std::ifstream(file, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const std::uint32_t old_version = 1;
  std::memcpy(bytes.data() + 8, &old_version, 4);
  const std::size_t body = bytes.size() - 16;
  const std::uint64_t sum = fnv1a(bytes, body);
  std::memcpy(bytes.data() + body, &sum, 8);
  const auto old_file = temp_file("v1.bin");
  std::ofstream(old_file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  SlamMap untouched;
  CHECK_THROWS_WITH(read_map_file(old_file, camera, untouched), Catch::Contains("version 1, expected 2 to 3"));

  // A loop edge naming a keyframe that does not exist is refused.
  SlamMap bad;
  tiny_map(bad);
  bad.add_loop_edge({5, 0, {}});
  write_map_file(file, camera, bad);
  CHECK_THROWS_WITH(read_map_file(file, camera, untouched), Catch::Contains("loop edge between keyframes that do not exist"));
  std::filesystem::remove(file);
  std::filesystem::remove(old_file);
}

TEST_CASE("slam: map file keeps the gravity directions, a version 2 file (without them) still loads") {
  const CameraIntrinsics camera = PinholeCamera::ardrone2_front().intrinsics();
  SlamMap map;
  tiny_map(map);
  const Eigen::Vector3d down0 = Eigen::Vector3d(0.02, 0.99, -0.1).normalized();
  map.keyframes_mutable()[0].down_cam = down0;  // keyframe 1 had no attitude
  map.set_down_map(Eigen::Vector3d(0.0, 0.05, 1.0));
  const auto file = temp_file("gravity.bin");
  write_map_file(file, camera, map);
  SlamMap loaded;
  read_map_file(file, camera, loaded);
  REQUIRE(loaded.keyframes()[0].down_cam);
  CHECK(loaded.keyframes()[0].down_cam->isApprox(down0, 1e-15));
  CHECK_FALSE(loaded.keyframes()[1].down_cam);
  REQUIRE(loaded.down_map());
  CHECK(loaded.down_map()->isApprox(*map.down_map(), 1e-15));

  // The same map without gravity, written as version 2 did: the per-keyframe and map direction flags
  // (one zero byte each) are the only difference. Keyframe layout of the tiny map: time 8, pose 96,
  // feature count 4, one feature 72, small image size 8 = 188 bytes, after a header of 104 bytes.
  SlamMap plain;
  tiny_map(plain);
  write_map_file(file, camera, plain);
  std::vector<char> bytes(std::filesystem::file_size(file));
  std::ifstream(file, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  constexpr std::size_t kHeader = 8 + 4 + 11 * 8 + 4, kKeyframe = 8 + 96 + 4 + 72 + 8;
  REQUIRE(bytes[kHeader + kKeyframe] == 0);
  REQUIRE(bytes[kHeader + 2 * kKeyframe + 1] == 0);
  REQUIRE(bytes[bytes.size() - 17] == 0);
  bytes.erase(bytes.end() - 17);  // the map's flag, just before the checksum
  bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(kHeader + 2 * kKeyframe + 1));
  bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(kHeader + kKeyframe));
  const std::uint32_t v2 = 2;
  std::memcpy(bytes.data() + 8, &v2, 4);
  const std::size_t body = bytes.size() - 16;
  const std::uint64_t sum = fnv1a(bytes, body);
  std::memcpy(bytes.data() + body, &sum, 8);
  const auto old_file = temp_file("v2.bin");
  std::ofstream(old_file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  SlamMap old;
  read_map_file(old_file, camera, old);
  CHECK(old.keyframes().size() == 2);
  CHECK(old.points().size() == 1);
  CHECK(old.loop_edges().size() == 1);
  CHECK_FALSE(old.down_map());

  // A gravity direction that is not a unit vector (written by hand into a valid file) is refused.
  write_map_file(file, camera, map);
  bytes.assign(std::filesystem::file_size(file), 0);
  std::ifstream(file, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const double doubled = 2.0 * down0.x();
  std::memcpy(bytes.data() + kHeader + kKeyframe + 1, &doubled, 8);
  const std::uint64_t sum2 = fnv1a(bytes, bytes.size() - 16);
  std::memcpy(bytes.data() + bytes.size() - 16, &sum2, 8);
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  SlamMap untouched;
  CHECK_THROWS_WITH(read_map_file(file, camera, untouched), Catch::Contains("keyframe gravity direction is not a unit vector"));
  std::filesystem::remove(file);
  std::filesystem::remove(old_file);
}

TEST_CASE("slam: map save/load round trip, and refusals of bad map files") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 5.5);
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
