#include <catch2/catch.hpp>

#include "control/flight_stack.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "drone/lab/lab_description.hpp"
#include "teacher_walks.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::control;

TEST_CASE("control: lab_geometry_from maps config/lab.json's room, base, instruments and platform") {
  const LabDescription lab = load_lab_description(default_lab_path());
  const fusion::LabGeometry g = fusion::lab_geometry_from(lab);
  CHECK(g.room_min.isApprox(Eigen::Vector3d(-1.5, -3.0, 0.0)));
  CHECK(g.room_max.isApprox(Eigen::Vector3d(6.5, 3.0, 3.0)));
  // The drone starts on the platform's top, 0.10 m above the floor, facing +x.
  CHECK(g.base.isApprox(Eigen::Vector3d(0.0, 0.0, 0.10)));
  CHECK(g.base_yaw_rad == Approx(0.0).margin(1e-12));

  REQUIRE(g.instruments.size() == 3);
  const fusion::PlanarTarget* osc = g.find_instrument("oscilloscope");
  REQUIRE(osc);
  CHECK(osc->name == "Oscilloscope DS-1054");
  CHECK(osc->width_m == Approx(0.40));
  CHECK(osc->height_m == Approx(0.20));
  CHECK(osc->T_world_object.translation().isApprox(Eigen::Vector3d(5.85, -1.2, 1.0)));
  // Facing 180 deg: a viewer looks along +x, which is the object's z (into the panel); y is down.
  CHECK(osc->T_world_object.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  CHECK(osc->T_world_object.linear().col(1).isApprox(-Eigen::Vector3d::UnitZ(), 1e-9));
  CHECK(std::filesystem::exists(osc->template_path));
  CHECK(osc->sift_switch_distance_m == Approx(2.0));
  CHECK(osc->sift_min_inliers == 20);
  const fusion::PlanarTarget* gen = g.find_instrument("signal_generator");
  REQUIRE(gen);
  CHECK(gen->sift_switch_distance_m == Approx(1.8));
  CHECK(gen->sift_min_inliers == 16);
  CHECK_FALSE(g.find_instrument("platform"));  // the platform is not an instrument to inspect

  CHECK(g.platform.id == "platform");
  CHECK(g.platform.width_m == Approx(0.60));
  CHECK(g.platform.T_world_object.translation().isApprox(Eigen::Vector3d(0.0, 0.0, 0.10)));
  CHECK(g.platform.T_world_object.linear().col(2).isApprox(-Eigen::Vector3d::UnitZ(), 1e-9));  // z down, into it
  CHECK(std::filesystem::exists(g.platform.template_path));
  // The ultrasound's surfaces: the platform's top at its centre, a bench top, the floor elsewhere.
  CHECK(g.surfaces.height_at({0.0, 0.0}) == Approx(0.10));
  CHECK(g.surfaces.height_at({6.2, -2.0}) == Approx(0.9));  // bench_east, beside the instruments
  CHECK(g.surfaces.height_at({1.0, -1.0}) == Approx(0.0));
  CHECK(g.surfaces.near_edge({0.3, 0.0}, 0.05));           // the platform's edge
}

TEST_CASE("control: a FlightStack on the lab's geometry accepts its instruments and refuses others by name") {
  control::FlightStackSetup setup;
  setup.lab = fusion::lab_geometry_from(load_lab_description(default_lab_path()));
  control::FlightStack stack(setup);
  control::MissionRequest r;
  r.kind = control::RequestKind::Inspect;
  r.instrument_id = "multimeter";
  const control::CommandResult refused = stack.request(r, 0.0);
  CHECK_FALSE(refused.accepted);
  CHECK_THAT(refused.reason, Catch::Contains("multimeter") && Catch::Contains("oscilloscope") &&
                                 Catch::Contains("signal_generator") && Catch::Contains("power_supply"));
  r.instrument_id = "power_supply";
  const control::CommandResult accepted = stack.request(r, 0.0);
  INFO(accepted.reason);
  CHECK(accepted.accepted);
}

TEST_CASE("control: the face-follow tests' teacher walks config/lab.json's path") {
  // test::lab_path() pins the path's figures for the face-follow tests; this keeps it the lab's, so a
  // change of the lab file shows up here instead of silently leaving those tests on an old path.
  const TeacherSpec lab = load_lab_description(default_lab_path()).teacher;
  const TeacherSpec pinned = test::lab_path();
  REQUIRE(lab.waypoints.size() == pinned.waypoints.size());
  for (std::size_t i = 0; i < lab.waypoints.size(); ++i) CHECK(lab.waypoints[i].isApprox(pinned.waypoints[i]));
  CHECK(lab.speed_mps == Approx(pinned.speed_mps));
  CHECK(lab.pause_s == Approx(pinned.pause_s));
  CHECK(lab.eye_height_m == Approx(pinned.eye_height_m));
}
