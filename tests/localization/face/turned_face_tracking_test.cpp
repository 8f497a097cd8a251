#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "teacher_scene.hpp"

// A teacher's head turning away from the drone in the simulated lab, rendered as the lab's camera
// renders it in flight, through the shipped face configuration: how far the track holds.

using namespace labo;
using namespace labo::face;
using labo::face::testing::TeacherScene;

namespace {
constexpr double kFps = 30.0;
constexpr double kDeg = std::numbers::pi / 180.0;

FaceConfig shipped_face_config() {
  const auto file = source_root() / "config" / "default.json";
  const ConfigDocument doc = ConfigDocument::load(file);
  return fusion::read_front_end_settings(doc.root(), file.parent_path()).face;
}

struct TurnCounts {
  int turned = 0, tracked = 0, restarted = 0;
};

// The head turned away to 55° and back over 4 s, one way then the other, 1.5 m in front of the drone
// at eye height (face-follow's distance in the flights where the face flickered).
TurnCounts track_turning_head(bool restart_unfit) {
  TeacherScene t(false);
  FaceConfig config = shipped_face_config();
  config.restart_unfit_tracked_frames = restart_unfit;
  FacePoseEstimator estimator(config, t.renderer.camera(CameraId::Front));
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  t.camera_at = Eigen::Vector3d(at.x() - 1.5, at.y(), t.lab.teacher.eye_height_m);
  double now = 0;
  FaceResult r;
  for (int i = 0; i < 10 && !r.tracking(); ++i, now += 1 / kFps) r = estimator.process(t.gray(t.scene(at, std::numbers::pi)), now);
  REQUIRE(r.tracking());
  TurnCounts n;
  for (const double side : {1.0, -1.0}) {
    for (int i = 0; i <= 4 * kFps; ++i, now += 1 / kFps) {
      const double away = 55 * kDeg * std::sin(std::numbers::pi * i / (4 * kFps));
      r = estimator.process(t.gray(t.scene(at, std::numbers::pi + side * away)), now);
      if (away < 35 * kDeg || away > 50 * kDeg) continue;
      ++n.turned;
      n.tracked += r.tracking();
      n.restarted += r.restarted && r.tracking();
    }
  }
  return n;
}
}  // namespace

TEST_CASE("face: a head turning 35-50 degrees away in the lab: with restart_unfit_tracked_frames a tracked frame that does not fit is made again as a track's first") {
  // In flight a face turned 35-50° from the drone was lost on every other frame ("landmarks do not
  // fit"): a tracked frame's single frontal view, unmirrored, no longer fits where a first frame's
  // iterated, mirrored views still do. Here 21 of the 68 frames turned 35-50° are tracked as shipped,
  // 33 with the option (12 of them made again). The rest: beyond ~52° the detector no longer confirms
  // the face, and turning back it is found again only within ~46° (docs/face.md, Known limits).
  const TurnCounts shipped = track_turning_head(false);
  const TurnCounts restarting = track_turning_head(true);
  INFO("tracked " << shipped.tracked << " of " << shipped.turned << " as shipped, " << restarting.tracked << " with the option ("
                  << restarting.restarted << " made again)");
  CHECK(shipped.restarted == 0);
  CHECK(restarting.restarted > 0);
  CHECK(restarting.tracked >= shipped.tracked + 6);
}
