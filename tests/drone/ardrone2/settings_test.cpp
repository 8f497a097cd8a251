#include <catch2/catch.hpp>

#include "core/config_reader.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"

using namespace labo;
using namespace labo::ardrone2;

TEST_CASE("link: link and emulator settings are read and validated", "[link]") {
  auto doc = ConfigDocument::parse(R"({"host": "10.0.0.2", "lost_after_s": 3.0, "full_navdata": true})", "t.json");
  const auto s = read_ardrone_link_settings(doc.root());
  CHECK(s.host == "10.0.0.2");
  CHECK(s.lost_after_s == 3.0);
  CHECK(s.full_navdata);
  CHECK(s.at_port == 5556);
  auto typo = ConfigDocument::parse(R"({"hots": "10.0.0.2"})", "t.json");
  CHECK_THROWS_WITH(read_ardrone_link_settings(typo.root()), Catch::Contains("hots"));
  auto order = ConfigDocument::parse(R"({"degraded_after_s": 1.0, "lost_after_s": 0.5})", "t.json");
  CHECK_THROWS_WITH(read_ardrone_link_settings(order.root()), Catch::Contains("lost_after_s"));
  auto port = ConfigDocument::parse(R"({"video_port": 70000})", "t.json");
  CHECK_THROWS_WITH(read_ardrone_emulator_settings(port.root()), Catch::Contains("video_port"));
  CHECK(read_ardrone_link_settings(doc.root()).video_max_bitrate_kbps == 4000);
  auto rate = ConfigDocument::parse(R"({"video_max_bitrate_kbps": 8000})", "t.json");
  CHECK_THROWS_WITH(read_ardrone_link_settings(rate.root()),
                    Catch::Contains("video_max_bitrate_kbps") && Catch::Contains("[250, 4000]"));
  auto low = ConfigDocument::parse(R"({"video_max_bitrate_kbps": 100})", "t.json");
  CHECK_THROWS_WITH(read_ardrone_link_settings(low.root()), Catch::Contains("[250, 4000]"));
  auto ok = ConfigDocument::parse(R"({"at_port": 0, "video_fps": 15})", "t.json");
  CHECK(read_ardrone_emulator_settings(ok.root()).video_fps == 15);
}

TEST_CASE("link: set_config refuses text that would break the AT syntax", "[link]") {
  ArdroneLink link(ArdroneLinkSettings{}, Logger("t", LogLevel::Off));
  CHECK_THROWS_AS(link.set_config("general:x", "a\"b"), std::invalid_argument);
  CHECK_THROWS_AS(link.set_config("nocolon", "1"), std::invalid_argument);
  CHECK_THROWS_AS(link.set_config("general:x", std::string(300, 'a')), std::invalid_argument);
  CHECK_NOTHROW(link.set_config("control:altitude_max", "3000"));
}
