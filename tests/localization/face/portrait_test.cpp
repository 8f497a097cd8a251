#include <catch2/catch.hpp>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/candide3.hpp"
#include "core/source_tree.hpp"
#include "face_test_pose.hpp"
#include "localization/face/group_photo.hpp"
#include "localization/face/portrait.hpp"
#include "localization/face/textured_head_renderer.hpp"

using namespace labo;
using namespace labo::face;
using labo::face::testing::pose;

namespace {

// The astronaut's head (assets/astronaut.png, from scripts/setup.sh) drawn through the front camera.
struct Heads {
  PinholeCamera camera = PinholeCamera::ardrone2_front();
  Candide3Model candide = Candide3Model::load(Candide3Model::default_path());
  FacePoseEstimator estimator{default_face_config(), camera};
  std::optional<TexturedHeadRenderer> renderer;
  Heads() {
    const cv::Mat photo = cv::imread((labo::source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
    REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
    renderer.emplace(candide, texture_head_from_photo(estimator, candide, photo, 0.063), camera);
  }
  cv::Mat render(const std::vector<Eigen::Isometry3d>& poses) {
    cv::Mat img(camera.height(), camera.width(), CV_8UC1, cv::Scalar(120));
    for (const auto& T : poses) renderer->render(T, img);
    return img;
  }
};

}  // namespace

TEST_CASE("face portrait: a face cut by the picture's border is refused, the whole face serves") {
  Heads h;
  const cv::Mat frontal = h.render({pose(0, 0, 0, {0, -0.02, 0.6})});
  const PortraitFace whole = find_portrait_face(h.estimator, frontal, {});
  REQUIRE(whole.serves());
  CHECK(whole.interocular_px > 40);
  // Cut through the subject's right eye: the detector still finds the face, its landmarks leave the picture.
  const int cut = static_cast<int>(whole.landmarks(0, 37));
  const cv::Mat cut_picture = frontal.colRange(cut, frontal.cols).clone();
  const PortraitFace cut_face = find_portrait_face(h.estimator, cut_picture, {});
  CHECK_FALSE(cut_face.serves());
  CHECK((cut_face.refusal == PortraitRefusal::CutByBorder || cut_face.refusal == PortraitRefusal::NoFace));
  CHECK_FALSE(find_portrait_face(h.estimator, cv::Mat(), {}).serves());
}

TEST_CASE("face portrait: a group photograph's faces are cut out by the detector, left to right") {
  Heads h;
  const cv::Mat gray = h.render({pose(0, 0, 0, {0.3, -0.02, 1.1}), pose(0, 0, 0, {-0.3, -0.02, 1.1}),
                                 pose(5, 0, 0, {0.0, 0.0, 1.1})});
  cv::Mat bgr;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  const auto portraits = portraits_in_group_photo(h.estimator, bgr, {.side_interocular = 4.0, .prefix = "group"});
  REQUIRE(portraits.size() == 3);
  CHECK(portraits[0].name == "group_01");
  CHECK(portraits[2].name == "group_03");
  for (std::size_t i = 0; i < portraits.size(); ++i) {
    INFO(portraits[i].name << ": " << portraits[i].face.reason);
    CHECK(portraits[i].face.serves());
    CHECK(portraits[i].crop_bgr.type() == CV_8UC3);
    if (i > 0) CHECK(portraits[i].box.x > portraits[i - 1].box.x);
  }
  // Each crop textures a head of its own.
  cv::Mat crop_gray;
  cv::cvtColor(portraits[1].crop_bgr, crop_gray, cv::COLOR_BGR2GRAY);
  CHECK_NOTHROW(texture_head_from_photo(h.estimator, h.candide, crop_gray, 0.063));
  CHECK_THROWS_AS(portraits_in_group_photo(h.estimator, gray), std::invalid_argument);
}

TEST_CASE("face portrait: a photograph that cannot serve is refused as the teacher's head texture") {
  Heads h;
  CHECK_THROWS_WITH(texture_head_from_photo(h.estimator, h.candide, h.render({}), 0.063),
                    Catch::Contains("head texture refused: no face found"));
  CHECK_THROWS_WITH(texture_head_from_photo(h.estimator, h.candide, h.render({pose(35, 0, 0, {0, -0.02, 0.8})}), 0.063),
                    Catch::Contains("head texture refused: head turned too far"));
  CHECK_THROWS_WITH(texture_head_from_photo(h.estimator, h.candide,
                                            h.render({pose(0, 0, 0, {-0.2, -0.02, 0.9}), pose(0, 0, 0, {0.2, -0.02, 0.9})}),
                                            0.063),
                    Catch::Contains("2 faces found"));
}
