#include <catch2/catch.hpp>
#include <vector>

#include "core/cli_args.hpp"
#include "core/log.hpp"
#include "core/time.hpp"

using namespace labo;

TEST_CASE("time: the simulated clock moves only when told") {
  SimClock clock(1.5);
  CHECK(clock.now() == 1.5);
  clock.advance(0.25);
  CHECK(clock.now() == 1.75);
  clock.set(10);
  CHECK(clock.now() == 10);
}

TEST_CASE("log: structured lines with quoted values and levels") {
  std::vector<std::string> lines;
  Logger log("drone", LogLevel::Info, [&](const std::string& l) { lines.push_back(l); });
  log.info(1.25, "link up").kv("host", "192.168.1.1").kv("rate_hz", 15);
  log.debug(1.3, "hidden");
  log.child("video").warn(2, "bad frame").kv("reason", "corrupt H.264");
  REQUIRE(lines.size() == 2);
  CHECK(lines[0] == "t=1.250 level=info component=drone msg=\"link up\" host=192.168.1.1 rate_hz=15");
  CHECK(lines[1] == "t=2.000 level=warn component=drone.video msg=\"bad frame\" reason=\"corrupt H.264\"");
  CHECK_THROWS_WITH(parse_log_level("loud"), Catch::Contains("not one of debug, info, warn, error, off"));
}

TEST_CASE("log: the rate limiter allows one line per kind per interval and counts the rest") {
  RateLimiter limiter(1.0);
  std::size_t suppressed = 99;
  CHECK(limiter.allow("bad_checksum", 0.0, &suppressed));
  CHECK(suppressed == 0);
  CHECK_FALSE(limiter.allow("bad_checksum", 0.2));
  CHECK_FALSE(limiter.allow("bad_checksum", 0.9));
  CHECK(limiter.allow("truncated", 0.9));
  CHECK(limiter.allow("bad_checksum", 1.0, &suppressed));
  CHECK(suppressed == 2);
}

TEST_CASE("cli: options, positionals and the errors of bad arguments") {
  const CommandSpec spec{"homography", "TEMPLATE IMAGE", "x", {{"--method", "M", ""}, {"--json", "", ""}}, 2, 2};
  const std::vector<std::string> ok{"t.png", "--method", "sift", "i.png", "--json"};
  const ParsedArgs a = parse_args(spec, ok);
  CHECK(a.positionals == std::vector<std::string>{"t.png", "i.png"});
  CHECK(a.value_or("--method", "auto") == "sift");
  CHECK(a.flag("--json"));
  const std::vector<std::string> unknown{"a", "b", "--fast"};
  CHECK_THROWS_WITH(parse_args(spec, unknown), Catch::Contains("unknown option '--fast' for 'homography'"));
  const std::vector<std::string> missing{"a", "b", "--method"};
  CHECK_THROWS_WITH(parse_args(spec, missing), Catch::Contains("option '--method' needs a value M"));
  const std::vector<std::string> too_few{"a"};
  CHECK_THROWS_WITH(parse_args(spec, too_few), Catch::Contains("takes TEMPLATE IMAGE, got 1 argument(s)"));
  const CommandSpec serve{"serve", "", "", {{"--port", "N", ""}}, 0, 0};
  const std::vector<std::string> bad_port{"--port", "99999"};
  CHECK_THROWS_WITH(parse_args(serve, bad_port).integer_or("--port", 8080, 1, 65535),
                    Catch::Contains("--port: '99999' is not an integer in [1, 65535]"));
}
