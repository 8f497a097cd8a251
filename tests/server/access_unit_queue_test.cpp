#include <catch2/catch.hpp>

#include "server/http/access_unit_queue.hpp"

using namespace labo;
using namespace labo::server;

namespace {

WireAccessUnit unit(std::uint32_t n, bool keyframe) {
  WireAccessUnit u;
  u.frame_number = n;
  u.keyframe = keyframe;
  u.wire = std::make_shared<const std::string>("unit " + std::to_string(n));
  u.geometry = std::make_shared<const std::string>("geometry " + std::to_string(n));
  return u;
}

// Every message the queue hands out, in order, as "text:..." or "binary:...".
std::vector<std::string> drain(AccessUnitQueue& q) {
  std::vector<std::string> out;
  bool binary = false;
  while (const auto m = q.pop(binary)) out.push_back((binary ? "binary:" : "text:") + *m);
  return out;
}

}  // namespace

TEST_CASE("web: an H.264 viewer starts at an IDR and gets each unit's geometry just before it") {
  AccessUnitQueue q(4);
  CHECK(q.waiting_for_keyframe());
  CHECK(q.push(unit(1, false)).dropped == 1);  // no IDR yet: nothing a decoder could use
  CHECK_FALSE(q.push(unit(2, false)).queued);
  CHECK(q.push(unit(3, true)).queued);
  CHECK(q.push(unit(4, false)).queued);
  CHECK(drain(q) == std::vector<std::string>{"text:geometry 3", "binary:unit 3", "text:geometry 4", "binary:unit 4"});
  CHECK(q.empty());
  // A unit without geometry goes alone.
  WireAccessUnit bare = unit(5, false);
  bare.geometry.reset();
  q.push(bare);
  CHECK(drain(q) == std::vector<std::string>{"binary:unit 5"});
}

TEST_CASE("web: an H.264 viewer that falls behind drops what it queued and waits for the next IDR") {
  AccessUnitQueue q(3);
  q.push(unit(10, true));
  q.push(unit(11, false));
  q.push(unit(12, false));
  // Full: the next unit finds no room. Everything queued goes, and so does this P frame.
  const auto behind = q.push(unit(13, false));
  CHECK(behind.fell_behind);
  CHECK(behind.dropped == 4);
  CHECK_FALSE(behind.queued);
  CHECK(q.empty());
  CHECK(q.waiting_for_keyframe());
  CHECK(q.push(unit(14, false)).dropped == 1);
  CHECK(q.push(unit(15, true)).queued);
  CHECK(drain(q) == std::vector<std::string>{"text:geometry 15", "binary:unit 15"});

  // Full when an IDR arrives: the IDR replaces the backlog at once.
  q.push(unit(16, false));
  q.push(unit(17, false));
  q.push(unit(18, false));
  const auto idr = q.push(unit(30, true));
  CHECK(idr.fell_behind);
  CHECK(idr.queued);
  CHECK(idr.dropped == 3);
  CHECK(q.size() == 1);

  // A new subscription starts again at an IDR, whatever was queued.
  q.restart();
  CHECK(q.empty());
  CHECK_FALSE(q.push(unit(31, false)).queued);
}

TEST_CASE("web: an H.264 viewer's queue holds its bound of shared messages and lets go of the rest") {
  AccessUnitQueue q(2);
  const WireAccessUnit first = unit(1, true);
  q.push(first);
  CHECK(first.wire.use_count() == 2);
  q.push(unit(2, false));
  q.push(unit(3, false));  // behind: the queue lets go of unit 1
  CHECK(first.wire.use_count() == 1);
  CHECK(first.geometry.use_count() == 1);
}
