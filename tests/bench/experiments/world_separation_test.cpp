// The flight software cannot see the simulated lab's world: it is built from the configuration alone.
// Two proofs: (1) the flight stacks of runs in different randomized worlds (and in the nominal one)
// get the same setup, the configuration's, while the worlds they fly in differ; (2) no source file of
// the flight software (localization/, control/, server/ but the simulated lab's backend) names the
// world or anything drawn in it.
// Nor can it see the teacher's walk (no oracle for face-follow): the lab it is given has no teacher
// (checked at compile time), the worlds' teachers walk different paths at different speeds while the
// stacks' setups are the same, and no source of control/ or localization/ names the walk, its
// waypoints, speed or pauses, or the simulated teacher.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "bench/experiments/experiment_common.hpp"
#include "core/source_tree.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

Experiment experiment_in(WorldMode mode) {
  ExperimentOptions o;
  o.config = source_root() / "config" / "default.json";
  o.real_vision = true;
  o.world = mode;
  return make_experiment(o, true);  // with the face: the teacher walks a drawn path in a randomized world
}

// What the flight software is told about the lab and its cameras.
void check_same_setup(const control::FlightStackSetup& a, const control::FlightStackSetup& b) {
  REQUIRE(a.lab.instruments.size() == b.lab.instruments.size());
  for (std::size_t i = 0; i < a.lab.instruments.size(); ++i)
    CHECK(a.lab.instruments[i].T_world_object.isApprox(b.lab.instruments[i].T_world_object, 0.0));
  CHECK(a.lab.platform.T_world_object.isApprox(b.lab.platform.T_world_object, 0.0));
  CHECK(a.lab.base == b.lab.base);
  for (const auto& [x, y] : {std::pair{a.cameras.front, b.cameras.front}, std::pair{a.cameras.bottom, b.cameras.bottom}}) {
    CHECK(x.fx == y.fx);
    CHECK(x.fy == y.fy);
    CHECK(x.cx == y.cx);
    CHECK(x.cy == y.cy);
    CHECK(x.k1 == y.k1);
    CHECK(x.k2 == y.k2);
  }
  CHECK(a.estimation.video_delay_s == b.estimation.video_delay_s);
  CHECK(a.estimation.navdata_delay_s == b.estimation.navdata_delay_s);
  CHECK(a.estimation.model.drag_per_s == b.estimation.model.drag_per_s);
  CHECK(a.control.mission.standoff_m == b.control.mission.standoff_m);
}

// What the flight software's lab geometry is made of: the teacher is no part of it.
template <typename Lab>
constexpr bool names_a_teacher = requires(const Lab& lab) { lab.teacher; };
static_assert(!names_a_teacher<fusion::LabGeometry>, "the flight software must not be told the teacher's walk");

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Checks that no .cpp or .hpp under `dirs` of the source tree (but `exempt`) names any of `names`;
// returns how many files it read.
int check_sources_never_name(std::initializer_list<const char*> dirs, const std::vector<std::string>& names,
                             const std::filesystem::path& exempt = {}) {
  int files = 0;
  for (const char* dir : dirs) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(source_root() / dir)) {
      const auto ext = entry.path().extension();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp") || entry.path() == exempt) continue;
      ++files;
      const std::string text = read_text(entry.path());
      for (const std::string& name : names) {
        INFO(entry.path().string() << " names " << name);
        CHECK(text.find(name) == std::string::npos);
      }
    }
  }
  return files;
}

}  // namespace

TEST_CASE("bench: the flight stacks of runs in different worlds all get the configuration, not the world") {
  const Experiment nominal = experiment_in(WorldMode::Nominal), randomized = experiment_in(WorldMode::Randomized);
  check_same_setup(nominal.setup, randomized.setup);
  const auto n = make_flight(nominal, 1000), a = make_flight(randomized, 1000), b = make_flight(randomized, 1001);
  // The worlds differ: placements, cameras, delays.
  REQUIRE(a->world());
  REQUIRE(b->world());
  CHECK(a->world()->placements[0].offset_m != b->world()->placements[0].offset_m);
  CHECK(a->true_lab().front.fx != n->true_lab().front.fx);
  CHECK(a->true_lab().front.fx != b->true_lab().front.fx);
  CHECK_FALSE(a->true_lab().lab.platform.T_world_object.isApprox(n->true_lab().lab.platform.T_world_object));
  CHECK(a->world()->link.video_delay_s != b->world()->link.video_delay_s);
  // The teachers walk different paths at different speeds.
  CHECK(a->world()->lab.teacher.waypoints != b->world()->lab.teacher.waypoints);
  CHECK(a->world()->lab.teacher.speed_mps != b->world()->lab.teacher.speed_mps);
  CHECK(a->world()->lab.teacher.waypoints != n->world()->lab.teacher.waypoints);
  // The flight software does not: each stack holds the configuration's lab, cameras and delays.
  for (ExperimentFlight* f : {n.get(), a.get(), b.get()}) check_same_setup(f->stack().setup(), nominal.setup);
  CHECK(n->true_lab().front.fx == nominal.setup.cameras.front.fx);  // the nominal world is the configuration
}

TEST_CASE("bench: no source of the flight software names the simulated lab's world or its draws") {
  const std::filesystem::path root = source_root();
  // The simulated lab's backend builds the world the flight runtime flies in (as emulate does).
  const int files = check_sources_never_name({"localization", "control", "server"},
                                             {"sim_world.hpp", "SimWorld", "make_sim_world", "WorldRanges", "PlantDeviation",
                                              "SensorBiases", "world_mode.hpp", "WorldMode", "WorldFactor"},
                                             root / "server" / "runtime" / "backend_parts.cpp");
  CHECK(files > 100);  // the scan did read the sources
}

TEST_CASE("bench: no source of control/ or localization/ names the teacher's walk, its speed or the simulated teacher") {
  // The face front-end may know the teacher's face (their photo, the distance between their eyes):
  // who they are, not where they walk.
  const int files = check_sources_never_name({"localization", "control"},
                                             {"TeacherSpec", "TeacherMotion", "TeacherRoute", "teacher_motion.hpp",
                                              "teacher_walk.hpp", "random_teacher_walk", "TeacherWalkRanges", "HeadMotionSpec",
                                              "waypoints", "teacher.speed", "teacher.pause", "teacher_speed", "cycle_s"});
  CHECK(files > 80);  // the scan did read the sources
}
