// HeapRelease trims on its schedule: not before `every_s` has passed since the first tick, then once
// per period.
#include <catch2/catch.hpp>

#include "server/http/heap_release.hpp"

using namespace labo::server;

TEST_CASE("heap release: trims once per period, counted from the first tick") {
  HeapRelease release(60.0);
  release.tick(1000.0);  // the first tick starts the clock
  release.tick(1059.9);
  CHECK(release.releases() == 0);
  release.tick(1060.0);
  CHECK(release.releases() == 1);
  release.tick(1100.0);  // 40 s after the last release
  CHECK(release.releases() == 1);
  release.tick(1125.0);
  CHECK(release.releases() == 2);
}
