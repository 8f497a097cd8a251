#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "core/candide3.hpp"
#include "core/source_tree.hpp"
#include "face_test_pose.hpp"
#include "localization/face/face_commands.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/teacher_head.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "tests/support/scratch_dir.hpp"
#include "tests/support/cli_run.hpp"
#include "tests/support/cout_capture.hpp"

using namespace labo;
using namespace labo::face;
using labo::test::ScratchDir;

namespace {

int run_register(const std::vector<std::string>& args, std::string* output = nullptr) {
  test::CoutCapture capture;
  const int rc = run_face_register_command(parse_args(face_register_command_spec(), args));
  if (output) *output = capture.text();
  return rc;
}

// Pictures of the astronaut head (assets/astronaut.png, from scripts/setup.sh) through the front camera.
class HeadPictures {
 public:
  HeadPictures() {
    const cv::Mat photo = cv::imread((labo::source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
    REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
    renderer_.emplace(candide_, texture_head_from_photo(estimator_, candide_, photo, 0.063), camera_);
  }
  cv::Mat render(double yaw_deg, double pitch_deg) { return render_at({testing::pose(yaw_deg, pitch_deg, 0, {0, -0.02, 0.8})}); }
  // One head per pose, over a plain background.
  cv::Mat render_at(const std::vector<Eigen::Isometry3d>& poses) {
    cv::Mat img(camera_.height(), camera_.width(), CV_8UC1, cv::Scalar(120));
    for (const auto& T : poses) renderer_->render(T, img);
    return img;
  }

 private:
  PinholeCamera camera_ = PinholeCamera::ardrone2_front();
  Candide3Model candide_ = Candide3Model::load(Candide3Model::default_path());
  FacePoseEstimator estimator_{default_face_config(), camera_};
  std::optional<TexturedHeadRenderer> renderer_;
};

}  // namespace

TEST_CASE("face register: a head turn refines the person, bad --turns folders are refused") {
  const ScratchDir dir("face_register");
  HeadPictures pictures;
  cv::imwrite((dir / "frontal.png").string(), pictures.render(0, 0));
  std::filesystem::create_directories(dir / "turn");
  for (int i = 0; i < 40; ++i) {
    const double s = i / 40.0, wave = std::sin(2 * std::numbers::pi * std::fmod(2 * s, 1.0));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    cv::imwrite((dir / "turn" / name).string(), pictures.render(s < 0.5 ? 25 * wave : 0, s < 0.5 ? 0 : 15 * wave));
  }
  const std::string frontal = (dir / "frontal.png").string(), out = (dir / "ada.json").string();
  std::string printed;
  REQUIRE(run_register({frontal, "--name", "ada", "--turns", (dir / "turn").string(), "--out", out}, &printed) == 0);
  CHECK_THAT(printed, Catch::Contains("head turn: ") && Catch::Contains("of 40 pictures tracked"));
  std::ifstream saved(out);
  const std::string text((std::istreambuf_iterator<char>(saved)), {});
  CHECK_THAT(text, Catch::Contains("landmark_offsets_mm"));

  CHECK_THROWS_WITH(run_register({frontal, "--name", "ada", "--turns", (dir / "missing").string(), "--out", out}),
                    Catch::Contains("not a folder"));
  std::filesystem::create_directories(dir / "empty");
  CHECK_THROWS_WITH(run_register({frontal, "--name", "ada", "--turns", (dir / "empty").string(), "--out", out}),
                    Catch::Contains("no PNG or JPEG pictures"));
  std::filesystem::create_directories(dir / "small");
  cv::imwrite((dir / "small" / "a.png").string(), cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)));
  CHECK_THROWS_WITH(run_register({frontal, "--name", "ada", "--turns", (dir / "small").string(), "--out", out}),
                    Catch::Contains("picture is 100x100, expected the front camera's"));
  // A still head: the turn is refused (exit 2, the reason on stderr), nothing written.
  std::filesystem::create_directories(dir / "still");
  const cv::Mat still = pictures.render(0, 0);
  for (int i = 0; i < 12; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "still_%02d.png", i);
    cv::imwrite((dir / "still" / name).string(), still);
  }
  const std::string still_out = (dir / "still.json").string();
  CHECK(run_register({frontal, "--name", "ada", "--turns", (dir / "still").string(), "--out", still_out}) == 2);
  CHECK_FALSE(std::filesystem::exists(still_out));

  // Several frontal pictures (consecutive frames of the still head) are averaged; each is checked.
  const std::string several_out = (dir / "several.json").string();
  const std::string second = (dir / "still" / "still_00.png").string();
  REQUIRE(run_register({frontal, second, "--name", "ada", "--out", several_out}, &printed) == 0);
  CHECK(std::filesystem::exists(several_out));
  CHECK_THROWS_WITH(run_register({frontal, (dir / "small" / "a.png").string(), "--name", "ada", "--out", several_out}),
                    Catch::Contains("a.png: picture is 100x100"));
}

TEST_CASE("face register: a picture that cannot serve as a portrait is refused with the reason, exit 2") {
  const ScratchDir dir("face_register_refusals");
  HeadPictures pictures;
  const auto refusal = [&](const std::string& file, const cv::Mat& picture) {
    const std::string path = (dir / file).string(), out = (dir / (file + ".json")).string();
    cv::imwrite(path, picture);
    const test::CliRun r = test::run_command(run_face_register_command, face_register_command_spec(),
                                             {path, "--name", "ada", "--out", out});
    CHECK(r.code == 2);
    CHECK_FALSE(std::filesystem::exists(out));  // nothing registered silently wrong
    return r.err;
  };
  using testing::pose;
  CHECK_THAT(refusal("blank.png", pictures.render_at({})), Catch::Contains("refused: no face found"));
  CHECK_THAT(refusal("two.png", pictures.render_at({pose(0, 0, 0, {-0.2, -0.02, 0.9}), pose(0, 0, 0, {0.2, -0.02, 0.9})})),
             Catch::Contains("2 faces found, expected one person"));
  // At 2.2 m the eye centres are ~16 px apart in the front camera: found, but too small to register.
  CHECK_THAT(refusal("far.png", pictures.render_at({pose(0, 0, 0, {0, -0.02, 2.2})})),
             Catch::Contains("face too small: eye centres") && Catch::Contains("expected at least 20 px"));
  CHECK_THAT(refusal("turned.png", pictures.render(32, 0)),
             Catch::Contains("head turned too far (yaw") && Catch::Contains("expected within 15° of frontal"));
  CHECK_THAT(refusal("nodding.png", pictures.render(0, 25)), Catch::Contains("head turned too far"));
  // The same head frontal at 0.8 m serves.
  const std::string ok = (dir / "ok.png").string();
  cv::imwrite(ok, pictures.render(0, 0));
  CHECK(test::run_command(run_face_register_command, face_register_command_spec(),
                          {ok, "--name", "ada", "--out", (dir / "ok.json").string()}).code == 0);
}
