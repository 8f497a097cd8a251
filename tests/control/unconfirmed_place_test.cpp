// A drone that landed after flight its navdata did not see takes no mission until its place is
// confirmed: a soak's drone took off twice on an estimate the silence had put 1.4 and 2.7 m away
// and flew into the teacher and a wall. Someone sets it on its platform and says so.
#include <catch2/catch.hpp>

#include "control/flight_stack.hpp"
#include "control/request_policy.hpp"

using namespace labo;
using namespace labo::control;

namespace {

MissionRequest request_of(RequestKind kind) {
  MissionRequest r;
  r.kind = kind;
  return r;
}

NavdataSample navdata_at(Seconds t, int control_state) {
  NavdataSample n;
  n.t = t;
  n.control_state = control_state;
  n.battery_percent = 90;
  n.altitude_m = control_state == 2 ? 0.0 : 1.0;
  n.vx_mps = control_state == 2 ? 0.0 : 0.4;
  return n;
}

}  // namespace

TEST_CASE("control: a landed drone whose place is not confirmed takes no mission, in flight it goes on") {
  const ControlConfig config;
  fusion::LabGeometry lab;
  const Geofence fence(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(3, 3, 2.5), 0.3);
  RequestContext landed;
  landed.unobserved_flight_s = 7.04;
  for (const RequestKind kind : {RequestKind::Takeoff, RequestKind::FindTeacher}) {
    const CommandResult c = check_request(request_of(kind), landed, lab, fence, config);
    INFO(c.reason);
    CHECK_FALSE(c.accepted);
    CHECK_THAT(c.reason, Catch::Contains("place is not confirmed: the navdata stopped for 7.04 s in flight"));
    CHECK_THAT(c.reason, Catch::Contains("POST /api/drone/set-down"));
  }
  RequestContext flying = landed;  // in flight SLAM or a panel may confirm it yet; the safety rules watch
  flying.phase = FlightPhase::Flying;
  CHECK(check_request(request_of(RequestKind::FindTeacher), flying, lab, fence, config).accepted);
  landed.unobserved_flight_s = 0;
  CHECK(check_request(request_of(RequestKind::Takeoff), landed, lab, fence, config).accepted);
}

TEST_CASE("control: a silence in flight, a landing elsewhere, then the drone set on its platform") {
  FlightStackSetup setup;
  setup.lab.base = Eigen::Vector3d(0.5, -1.0, 0.0);
  setup.lab.room_min = Eigen::Vector3d(-3, -3, 0);
  setup.lab.room_max = Eigen::Vector3d(3, 3, 2.5);
  FlightStack stack(setup);  // the real estimator, no vision
  Seconds t = 0;
  auto feed = [&](int control_state, double seconds) {
    for (const Seconds end = t + seconds; t < end;) {
      t += 1.0 / 15;
      stack.on_navdata(navdata_at(t, control_state));
      stack.tick(t);
    }
  };
  feed(3, 2.0);  // flying, as far as the navdata says (the autopilot was never asked to take off)
  const CommandResult in_flight = stack.set_down_on_platform();
  CHECK_FALSE(in_flight.accepted);
  CHECK_THAT(in_flight.reason, Catch::Contains("reports its motors on (navdata control state 3)"));  // the autopilot never took off here

  t += 7.0;  // the silence (a restart, a long cut) ...
  feed(3, 0.5);
  feed(2, 1.0);  // ... and the landing the link loss asked for
  CHECK(stack.status().pose.unobserved_flight_s == Approx(7.1).margin(0.1));  // to the second packet after it
  const CommandResult refused = stack.request(request_of(RequestKind::Takeoff), t);
  INFO(refused.reason);
  CHECK_FALSE(refused.accepted);
  CHECK_THAT(refused.reason, Catch::Contains("not confirmed"));

  const CommandResult set_down = stack.set_down_on_platform();
  INFO(set_down.reason);
  CHECK(set_down.accepted);
  feed(2, 0.5);
  const fusion::PoseEstimate pose = stack.status().pose;
  CHECK(pose.unobserved_flight_s == 0.0);
  CHECK((pose.T_world_body.translation().head<2>() - setup.lab.base.head<2>()).norm() < 0.01);
  CHECK(stack.request(request_of(RequestKind::Takeoff), t).accepted);
}
