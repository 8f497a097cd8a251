#include <catch2/catch.hpp>

#include "control/flight_stack.hpp"
#include "tests/control/model_flight.hpp"

// find_teacher with a registered person to follow: pipelines that cannot hand the shape to a face
// front-end refuse the mission rather than fly it after a face they were not told about. (Accepted,
// the ack reads "searching for <name>": tests/e2e/teacher_flow.mjs on the simulated lab.)

using namespace labo;

TEST_CASE("control: find teacher with a person to follow is refused by pipelines without a face front-end") {
  test::ModelFlight f;
  f.run(0.5);
  control::MissionRequest r;
  r.kind = control::RequestKind::FindTeacher;
  r.person = std::make_shared<const face::PersonShape>(face::PersonShape{"ada", 0.063, Eigen::VectorXd::Zero(11), 0.5, {}});
  const control::CommandResult verdict = f.request(r);
  CHECK_FALSE(verdict.accepted);
  CHECK(verdict.reason == "find_teacher: these pipelines have no face front-end to follow ada");
  CHECK(f.stack->status().mission == "idle");
  CHECK(f.stack->status().last_event == "refused: " + verdict.reason);
  r.person.reset();  // without a person, as before
  CHECK(f.request(r).accepted);
}
