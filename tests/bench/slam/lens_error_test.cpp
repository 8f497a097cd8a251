#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "bench/slam/lens_error.hpp"
#include "bench/slam/slam_bench_command.hpp"
#include "core/cli_args.hpp"

using namespace labo;
using namespace labo::bench;

TEST_CASE("bench slam: a lens error is four numbers, applied to SLAM's lens model") {
  const LensError e = parse_lens_error("0.03,-5,0.01,-0.02");
  CHECK(e.focal_fraction == Approx(0.03));
  CHECK(e.principal_px == Approx(-5));
  CHECK(e.k1 == Approx(0.01));
  CHECK(e.k2 == Approx(-0.02));
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const CameraIntrinsics& k = camera.intrinsics();
  const PinholeCamera off_camera = with_lens_error(camera, e);
  const CameraIntrinsics& off = off_camera.intrinsics();
  CHECK(off.fx == Approx(1.03 * k.fx));
  CHECK(off.fy == Approx(1.03 * k.fy));
  CHECK(off.cx == Approx(k.cx - 5));
  CHECK(off.cy == Approx(k.cy - 5));
  CHECK(off.k1 == Approx(k.k1 + 0.01));
  CHECK(off.k2 == Approx(k.k2 - 0.02));
  CHECK(off.width == k.width);
}

TEST_CASE("bench slam: a lens error that is not four numbers in range is refused, naming what is wrong") {
  const auto refused = [](const std::string& text, const std::string& says) {
    INFO(text);
    CHECK_THROWS_WITH(parse_lens_error(text), Catch::Contains(says));
  };
  refused("0.03,0,0", "expected four");
  refused("0.03,0,0,0,0", "expected four");
  refused("0.03,x,0,0", "'x' is not a number");
  refused("0.03,5px,0,0", "'5px' is not a number");
  refused("", "expected four");
  refused("0.03,0,0,0,", "ends with ','");
  refused("0.03,,0,0", "'' is not a number");
  refused("0.5,0,0,0", "focal fraction 0.5 outside");
  refused("0,80,0,0", "principal point shift");
  refused("0,0,nan,0", "k1");
  CHECK_THROWS_AS(parse_lens_error("1,2"), UsageError);
}

TEST_CASE("bench slam: a lens error on the synthetic room's flights only is refused before any flight") {
  const std::vector<std::string> args{"--flight", "tour", "--lens-error", "0.03,0,0,0"};
  CHECK_THROWS_WITH(run_bench_slam_command(parse_args(bench_slam_command_spec(), args)),
                    Catch::Contains("--lens-error applies to the simulated lab's flights only"));
}
