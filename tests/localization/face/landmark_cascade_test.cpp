// LaboDrone's own evaluation of the landmark cascade (landmark_cascade.hpp) against dlib's
// shape_predictor on the same model file, image and box: the landmarks must be the same pixels; and
// files that are not a usable model are refused with a message naming what is wrong.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <unistd.h>

#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/candide3.hpp"
#include "core/source_tree.hpp"
#include "face_test_pose.hpp"
#include "localization/face/face_config.hpp"
#include "localization/face/face_detector.hpp"
#include "localization/face/landmark_cascade.hpp"
#include "localization/face/landmark_detector.hpp"
#include "localization/face/textured_head_renderer.hpp"

using namespace labo;
using namespace labo::face;

namespace {

struct Case {
  cv::Mat image;
  PixelBox box;
};

PixelBox pixel_box(const cv::Rect2d& r) {
  return {std::lround(r.x), std::lround(r.y), std::lround(r.x + r.width - 1), std::lround(r.y + r.height - 1)};
}

// Boxes around `box`: moved by up to `shift` of its side, scaled by 0.7-1.4, its aspect by +-10 %.
void add_jittered(const cv::Mat& image, const cv::Rect2d& box, int count, double shift, std::mt19937& rng,
                  std::vector<Case>& cases) {
  std::uniform_real_distribution<double> move(-shift, shift), scale(0.7, 1.4), aspect(0.9, 1.1);
  cases.push_back({image, pixel_box(box)});
  for (int i = 0; i < count; ++i) {
    const double s = scale(rng), w = box.width * s * aspect(rng), h = box.height * s;
    const double cx = box.x + box.width / 2 + move(rng) * box.width, cy = box.y + box.height / 2 + move(rng) * box.height;
    cases.push_back({image, pixel_box(cv::Rect2d(cx - w / 2, cy - h / 2, w, h))});
  }
}

// A temporary file removed when the test ends.
struct TempFile {
  std::filesystem::path path;
  explicit TempFile(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("labodrone_cascade_" + std::to_string(::getpid()) + "_" + name)) {}
  ~TempFile() { std::filesystem::remove(path); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
};

std::string refusal(const std::filesystem::path& file) {
  try {
    LandmarkCascade cascade(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// A small cascade of random trees, built and written by dlib (5 landmarks, 3 levels).
dlib::shape_predictor random_predictor(std::mt19937& rng, int depth) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), small(-0.02f, 0.02f), threshold(-40.0f, 40.0f);
  constexpr unsigned long kLandmarks = 5, kPixels = 40;
  dlib::matrix<float, 0, 1> mean(2 * kLandmarks);
  const float xs[kLandmarks] = {0.3f, 0.7f, 0.5f, 0.35f, 0.65f}, ys[kLandmarks] = {0.35f, 0.35f, 0.55f, 0.75f, 0.75f};
  for (unsigned long i = 0; i < kLandmarks; ++i) {
    mean(2 * i) = xs[i];
    mean(2 * i + 1) = ys[i];
  }
  std::vector<std::vector<dlib::impl::regression_tree>> forests(3);
  std::vector<std::vector<dlib::vector<float, 2>>> pixels(3);
  const unsigned long splits = (1ul << depth) - 1;
  for (auto& level : pixels) {
    for (unsigned long i = 0; i < kPixels; ++i) level.emplace_back(unit(rng) * 1.2f - 0.1f, unit(rng) * 1.2f - 0.1f);
  }
  for (auto& forest : forests) {
    forest.resize(20);
    for (auto& tree : forest) {
      for (unsigned long s = 0; s < splits; ++s) {
        tree.splits.push_back({rng() % kPixels, rng() % kPixels, threshold(rng)});
      }
      tree.leaf_values.resize(splits + 1);
      for (auto& leaf : tree.leaf_values) {
        leaf.set_size(2 * kLandmarks);
        for (long j = 0; j < leaf.size(); ++j) leaf(j) = small(rng);
      }
    }
  }
  return dlib::shape_predictor(mean, forests, pixels);
}

}  // namespace

TEST_CASE("landmark cascade: the same landmarks as dlib's shape_predictor on faces, boxes and noise") {
  const std::filesystem::path model = LandmarkDetector::default_path();
  dlib::shape_predictor reference;
  {
    std::ifstream in(model, std::ios::binary);
    REQUIRE(in);
    dlib::deserialize(reference, in);
  }
  LandmarkCascade cascade(model);
  REQUIRE(cascade.landmark_count() == 68);
  CHECK(cascade.level_count() == 15);
  CHECK(cascade.tree_count() == 15 * 500);

  std::mt19937 rng(7);
  std::vector<Case> cases;
  // The photograph, its face box from the detector, then moved and scaled, also across the border.
  const cv::Mat photo = cv::imread((source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
  REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
  FaceDetector detector;
  const auto photo_faces = detector.detect_full(photo, 1.0);
  REQUIRE_FALSE(photo_faces.empty());
  add_jittered(photo, photo_faces.front().box, 150, 0.25, rng, cases);
  const cv::Rect2d& pb = photo_faces.front().box;
  add_jittered(photo, cv::Rect2d(-0.4 * pb.width, pb.y, pb.width, pb.height), 20, 0.1, rng, cases);
  add_jittered(photo, cv::Rect2d(photo.cols - 0.6 * pb.width, photo.rows - 0.5 * pb.height, pb.width, pb.height), 20, 0.1,
               rng, cases);

  // Heads rendered from the photograph at the face benchmark's poses and distances, their detector
  // boxes (the head's projected extent when the detector misses a turned face) and moved ones.
  const FaceConfig config = default_face_config();
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  FacePoseEstimator estimator(config, camera.without_distortion());
  const Candide3Model candide = Candide3Model::load(config.model);
  TexturedHeadRenderer renderer(candide, texture_head_from_photo(estimator, candide, photo, 0.063), camera);
  std::uniform_real_distribution<double> yaw(-50, 50), pitch(-25, 25), roll(-25, 25), distance(0.6, 2.2), lateral(-0.25, 0.25);
  int detector_boxes = 0;
  for (int i = 0; i < 40; ++i) {
    const double z = distance(rng);
    const Eigen::Isometry3d T = testing::pose(yaw(rng), pitch(rng), roll(rng), {lateral(rng) * z, 0.5 * lateral(rng) * z, z});
    cv::Mat frame(camera.height(), camera.width(), CV_8UC1, cv::Scalar(60 + 3 * i));
    renderer.render(T, frame);
    const auto faces = detector.detect_full(frame, 2.0);
    cv::Rect2d box;
    if (!faces.empty()) {
      box = faces.front().box;
      ++detector_boxes;
    } else {
      double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
      for (const auto& v : renderer.vertices_m()) {
        if (const auto p = camera.project(T * v)) {
          x0 = std::min(x0, p->x()), y0 = std::min(y0, p->y()), x1 = std::max(x1, p->x()), y1 = std::max(y1, p->y());
        }
      }
      box = cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
    }
    add_jittered(frame, box, 8, 0.15, rng, cases);
  }
  CHECK(detector_boxes > 10);

  // Smoothed noise with random boxes (trees walked down paths no face takes), and a tiny image that
  // boxes overhang on every side (feature pixels outside read 0).
  for (int i = 0; i < 20; ++i) {
    cv::Mat noise(240, 320, CV_8UC1);
    cv::randu(noise, 0, 256);
    cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.0 + i % 4);
    std::uniform_real_distribution<double> x(-40, 280), y(-40, 200), side(20, 200);
    for (int k = 0; k < 5; ++k) {
      const double s = side(rng);
      cases.push_back({noise, pixel_box(cv::Rect2d(x(rng), y(rng), s, s * (0.8 + 0.4 * (k % 2))))});
    }
  }
  const cv::Mat tiny = photo(cv::Rect(static_cast<int>(pb.x + pb.width / 4), static_cast<int>(pb.y + pb.height / 4), 30, 24)).clone();
  for (int k = 0; k < 10; ++k) cases.push_back({tiny, PixelBox{-20 + 2 * k, -15 + k, 50 - k, 40 - 2 * k}});

  Eigen::Matrix2Xd ours;
  std::size_t points = 0, differing = 0;
  double worst_px = 0;
  for (const Case& c : cases) {
    const dlib::full_object_detection theirs =
        reference(dlib::cv_image<unsigned char>(c.image), dlib::rectangle(c.box.left, c.box.top, c.box.right, c.box.bottom));
    cascade.fit(c.image, c.box, ours);
    REQUIRE(ours.cols() == 68);
    for (Eigen::Index i = 0; i < 68; ++i) {
      const auto& p = theirs.part(static_cast<unsigned long>(i));
      const double dx = ours(0, i) - static_cast<double>(p.x()), dy = ours(1, i) - static_cast<double>(p.y());
      ++points;
      if (dx != 0 || dy != 0) {
        ++differing;
        worst_px = std::max(worst_px, std::hypot(dx, dy));
      }
    }
  }
  INFO(cases.size() << " image/box pairs, " << points << " landmarks, " << differing << " differ (worst " << worst_px << " px)");
  CHECK(cases.size() > 600);
  CHECK(differing == 0);
}

TEST_CASE("landmark cascade: another model (random trees of several depths) gives dlib's landmarks too") {
  std::mt19937 rng(11);
  for (int depth : {1, 3, 5}) {
    const dlib::shape_predictor reference = random_predictor(rng, depth);
    const TempFile file("random_" + std::to_string(depth) + ".dat");
    {
      std::ofstream out(file.path, std::ios::binary);
      dlib::serialize(reference, out);
    }
    LandmarkCascade cascade(file.path);
    REQUIRE(cascade.landmark_count() == 5);
    cv::Mat image(120, 160, CV_8UC1);
    cv::randu(image, 0, 256);
    cv::GaussianBlur(image, image, cv::Size(0, 0), 2.0);
    Eigen::Matrix2Xd ours;
    int differing = 0;
    for (int k = 0; k < 50; ++k) {
      const PixelBox box{static_cast<long>(rng() % 100) - 20, static_cast<long>(rng() % 80) - 20, 0, 0};
      const PixelBox b{box.left, box.top, box.left + 20 + static_cast<long>(rng() % 100), box.top + 20 + static_cast<long>(rng() % 80)};
      const auto theirs = reference(dlib::cv_image<unsigned char>(image), dlib::rectangle(b.left, b.top, b.right, b.bottom));
      cascade.fit(image, b, ours);
      for (Eigen::Index i = 0; i < 5; ++i) {
        const auto& p = theirs.part(static_cast<unsigned long>(i));
        differing += ours(0, i) != static_cast<double>(p.x()) || ours(1, i) != static_cast<double>(p.y());
      }
    }
    INFO("depth " << depth);
    CHECK(differing == 0);
  }
}

TEST_CASE("landmark cascade: a missing, short or inconsistent model file is refused, saying what is wrong") {
  using Catch::Matchers::Contains;
  const TempFile missing("missing.dat");
  CHECK_THAT(refusal(missing.path), Contains(missing.path.string()) && Contains("cannot open"));

  const TempFile empty("empty.dat");
  { std::ofstream(empty.path, std::ios::binary); }
  CHECK_THAT(refusal(empty.path), Contains(empty.path.string()) && Contains("the version number cut short or corrupt"));

  const TempFile wrong_version("version.dat");
  {
    std::ofstream out(wrong_version.path, std::ios::binary);
    dlib::serialize(2, out);
  }
  CHECK_THAT(refusal(wrong_version.path), Contains("format version 2, expected 1"));

  // The real model cut after 1 MB (of ~100): its forests end early.
  const TempFile cut("cut.dat");
  {
    std::ifstream in(LandmarkDetector::default_path(), std::ios::binary);
    REQUIRE(in);
    std::vector<char> head(1 << 20);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(cut.path, std::ios::binary).write(head.data(), in.gcount());
  }
  CHECK_THAT(refusal(cut.path), Contains(cut.path.string()) && Contains("the regression forests cut short or corrupt"));

  // Written by dlib's own serialization, then made inconsistent one part at a time.
  const auto write = [](const std::filesystem::path& path, const dlib::matrix<float, 0, 1>& mean,
                        const std::vector<std::vector<dlib::impl::regression_tree>>& forests,
                        const std::vector<std::vector<unsigned long>>& anchors,
                        const std::vector<std::vector<dlib::vector<float, 2>>>& offsets) {
    std::ofstream out(path, std::ios::binary);
    dlib::serialize(1, out);
    dlib::serialize(mean, out);
    dlib::serialize(forests, out);
    dlib::serialize(anchors, out);
    dlib::serialize(offsets, out);
  };
  dlib::matrix<float, 0, 1> mean(4);
  mean = 0.3f, 0.4f, 0.7f, 0.4f;
  dlib::impl::regression_tree tree;
  tree.splits = {{0, 1, 0.5f}};
  tree.leaf_values.assign(2, dlib::matrix<float, 0, 1>(dlib::zeros_matrix<float>(4, 1)));
  const std::vector<std::vector<unsigned long>> anchors{{0, 1}};
  const std::vector<std::vector<dlib::vector<float, 2>>> offsets{{{0.1f, 0.0f}, {-0.1f, 0.0f}}};
  const TempFile bad("bad.dat");

  write(bad.path, mean, {{tree}}, anchors, offsets);
  CHECK(refusal(bad.path).empty());  // the consistent one loads

  dlib::impl::regression_tree incomplete = tree;
  incomplete.leaf_values.resize(3);
  write(bad.path, mean, {{tree, incomplete}}, anchors, offsets);
  CHECK_THAT(refusal(bad.path), Contains("cascade level 0, tree 1 has 1 splits and 3 leaves"));

  dlib::impl::regression_tree far = tree;
  far.splits[0].idx2 = 2;
  write(bad.path, mean, {{far}}, anchors, offsets);
  CHECK_THAT(refusal(bad.path), Contains("tree 0 compares feature pixels 0 and 2, the level has 2"));

  dlib::impl::regression_tree wide = tree;
  wide.leaf_values[1].set_size(6);
  write(bad.path, mean, {{wide}}, anchors, offsets);
  CHECK_THAT(refusal(bad.path), Contains("has a leaf of 6 values, the shape 4"));

  write(bad.path, mean, {{tree}}, {{0, 2}}, offsets);
  CHECK_THAT(refusal(bad.path), Contains("feature pixel 1 is anchored to landmark 2 of 2"));

  write(bad.path, mean, {{tree}, {tree}}, anchors, offsets);
  CHECK_THAT(refusal(bad.path), Contains("2 cascade levels of trees but 1 of anchor landmarks"));

  dlib::matrix<float, 0, 1> odd(3);
  odd = 0.1f, 0.2f, 0.3f;
  write(bad.path, odd, {{tree}}, anchors, offsets);
  CHECK_THAT(refusal(bad.path), Contains("a mean shape of 3 values"));

  // LandmarkDetector passes the reason on, and also refuses a model of another landmark count.
  CHECK_THROWS_WITH(LandmarkDetector(cut.path), Contains("the regression forests cut short or corrupt"));
  write(bad.path, mean, {{tree}}, anchors, offsets);
  CHECK_THROWS_WITH(LandmarkDetector(bad.path), Contains("predicts 2 landmarks, expected 68"));
}
