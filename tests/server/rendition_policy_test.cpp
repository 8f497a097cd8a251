#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "server/video/rendition_policy.hpp"

using namespace labo;
using namespace labo::server;

namespace {

// A viewer's connection in 0.25 s steps: the rendition's stream is offered at its rate, the link
// acknowledges at most `link_kbps` of what waits. Everything offered waits in the send queue here
// (the session's ring and the socket alike).
struct SimulatedViewer {
  RenditionPolicy policy;
  double source_kbps = 4000, low_kbps = 1000, link_kbps;
  double t = 0, offered = 0, acked = 0;
  std::vector<std::pair<double, Rendition>> switches;

  explicit SimulatedViewer(double link) : link_kbps(link) {}
  void run(double seconds) {
    for (const double end = t + seconds; t < end;) {
      t += 0.25;
      const double rate = policy.rendition() == Rendition::Low ? low_kbps : source_kbps;
      offered += rate * 1000 / 8 * 0.25;
      acked = std::min(offered, acked + link_kbps * 1000 / 8 * 0.25);
      const ViewerSample s{t, static_cast<std::uint64_t>(offered), static_cast<std::uint64_t>(offered),
                           static_cast<std::uint64_t>(offered - acked), 0, 0};
      const Rendition before = policy.rendition();
      if (policy.update(s) != before) switches.emplace_back(t, policy.rendition());
    }
  }
};

}  // namespace

TEST_CASE("web: a viewer whose link carries the drone's stream stays on it") {
  SimulatedViewer v(10000);
  v.run(120);
  CHECK(v.switches.empty());
  CHECK(v.policy.rendition() == Rendition::Source);
  CHECK(v.policy.throughput_kbps() == Approx(4000).margin(50));
  CHECK(v.policy.lag_s() < 0.1);
}

TEST_CASE("web: a viewer on a 2 Mbit/s link moves to the low rendition within 2 s and probes the source ever less often") {
  SimulatedViewer v(2000);
  v.run(2);
  REQUIRE(v.policy.rendition() == Rendition::Low);
  CHECK(v.policy.reason().find("kbit/s") != std::string::npos);
  v.run(120);
  // Each probe fails within a few seconds; the waits between them double: 15, 30, 60, then at most 120 s.
  std::vector<double> probes;
  for (const auto& [t, r] : v.switches)
    if (r == Rendition::Source) probes.push_back(t);
  REQUIRE(probes.size() >= 3);
  CHECK(probes[1] - probes[0] > 30);
  CHECK(probes[2] - probes[1] > 60);
  CHECK(v.policy.probe_after_s() == Approx(120));
  // The time spent on the source (where this link lags) is a small part of the run.
  double on_source = 0;
  for (std::size_t i = 0; i < v.switches.size(); ++i)
    if (v.switches[i].second == Rendition::Source && i + 1 < v.switches.size()) on_source += v.switches[i + 1].first - v.switches[i].first;
  CHECK(on_source < 0.1 * v.t);
}

TEST_CASE("web: a viewer whose link recovers returns to the drone's stream at the next probe and stays") {
  SimulatedViewer v(2000);
  v.run(5);
  REQUIRE(v.policy.rendition() == Rendition::Low);
  v.link_kbps = 20000;
  v.run(16);
  CHECK(v.policy.rendition() == Rendition::Source);
  CHECK(v.policy.reason().find("trying the drone's stream again") != std::string::npos);
  v.run(60);
  CHECK(v.policy.rendition() == Rendition::Source);
  CHECK(v.policy.probe_after_s() == Approx(15));  // the probe held: the next slow spell starts from 15 s again
}

TEST_CASE("web: a ring overflow moves a viewer down at once, and a pinned choice ignores the link") {
  RenditionPolicy p;
  p.update({0.0, 0, 0, 0, 0, 0});
  CHECK(p.update({0.25, 1000, 1000, 0, 0, 1}) == Rendition::Low);
  CHECK(p.reason().find("queue behind") != std::string::npos);

  RenditionPolicy pinned({}, RenditionChoice::Source);
  for (int i = 1; i < 40; ++i) CHECK(pinned.update({0.25 * i, 1000000ull * i, 1000000ull * i, 900000ull * i, 0, 0}) == Rendition::Source);
  pinned.choose(RenditionChoice::Low, 10);
  CHECK(pinned.rendition() == Rendition::Low);
  CHECK(pinned.update({10.25, 0, 0, 0, 0, 0}) == Rendition::Low);
}
