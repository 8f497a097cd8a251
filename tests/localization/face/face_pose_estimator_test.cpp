#include <catch2/catch.hpp>
#include <cmath>

#include "face_test_pose.hpp"
#include <filesystem>
#include <fstream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/face/frame_degrader.hpp"
#include "core/candide3.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/landmark_detector.hpp"
#include "localization/face/person_registration.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "core/source_tree.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using labo::test::ScratchDir;
using namespace labo::face;
using labo::bench::degraded_registration_pictures;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// The front camera without distortion keeps the rendered cases easy to reason about; the benchmark
// runs with the real distortion.
PinholeCamera test_camera() {
  CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
  k.k1 = k.k2 = k.p1 = k.p2 = k.k3 = 0;
  return PinholeCamera(k);
}

using testing::pose;

cv::Mat blank() { return cv::Mat(360, 640, CV_8UC1, cv::Scalar(120)); }

// One estimator and a renderer of the astronaut head (assets/astronaut.png, made by scripts/setup.sh).
struct RenderedHeadFixture {
  explicit RenderedHeadFixture(FaceConfig c = default_face_config()) : config(std::move(c)) {}
  FaceConfig config;
  Candide3Model candide = Candide3Model::load(config.model);
  FacePoseEstimator estimator{config, test_camera()};
  TexturedHeadRenderer renderer{candide, load_head(), test_camera()};

  TexturedHead load_head() {
    const auto path = labo::source_root() / "assets" / "astronaut.png";
    const cv::Mat photo = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
    TexturedHead head = texture_head_from_photo(estimator, candide, photo, 0.063);
    estimator.set_person({"astronaut", 0.063, head.shape_params, 0, {}}, false);
    return head;
  }
  cv::Mat render(std::initializer_list<Eigen::Isometry3d> poses) {
    cv::Mat img = blank();
    for (const auto& T : poses) renderer.render(T, img);
    return img;
  }
};
}  // namespace

TEST_CASE("face: bad frames are lost with a reason, never a pose") {
  FacePoseEstimator estimator(default_face_config(), test_camera());
  CHECK(estimator.process(cv::Mat(), 0).reason == FaceLostReason::BadImage);
  CHECK(estimator.process(cv::Mat(360, 640, CV_8UC3, cv::Scalar::all(0)), 0).reason == FaceLostReason::BadImage);
  CHECK(estimator.process(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), 0).reason == FaceLostReason::BadImage);
  const FaceResult none = estimator.process(blank(), 0.1);
  CHECK(none.state == FaceState::Lost);
  CHECK(none.reason == FaceLostReason::NoFace);
  cv::Mat noise(360, 640, CV_8UC1);
  cv::randu(noise, 0, 255);
  for (int i = 0; i < 3; ++i) CHECK_FALSE(estimator.process(noise, 0.2 + i).tracking());
}

TEST_CASE("face: after a reset the estimator starts a track as a new one does") {
  // The full-frame search cycles its scales over lost frames (0.5, 1, 2); a head at 0.8 m is found at
  // 1, not at 0.5. Frames searched before a reset must not change what the frames after it give.
  RenderedHeadFixture fresh, used;
  used.estimator.process(blank(), 0);  // searched at 0.5: the next search would be at 1
  used.estimator.reset();
  const cv::Mat frame = fresh.render({pose(0, 0, 0, {0, -0.02, 0.8})});
  for (int i = 0; i < 3; ++i) {
    const FaceResult a = fresh.estimator.process(frame, i / 30.0), b = used.estimator.process(frame, i / 30.0);
    CHECK(a.faces_found == b.faces_found);
    CHECK(a.tracking() == b.tracking());
    if (a.tracking() && b.tracking()) CHECK(a.T_cam_face.isApprox(b.T_cam_face, 1e-12));
  }
}

TEST_CASE("face: config and person files are validated") {
  const auto doc = ConfigDocument::parse(R"({"pnp_method": "posit"})", "test.json");
  CHECK_THROWS_AS(read_face_config(doc.root(), "."), ConfigError);
  const auto typo = ConfigDocument::parse(R"({"pnp_metod": "epnp"})", "test.json");
  CHECK_THROWS_AS(read_face_config(typo.root(), "."), ConfigError);
  // The head-turn depth refinement's section: values out of range and unknown keys name the key.
  const std::pair<const char*, const char*> bad_refinements[] = {
      {R"({"depth_refinement": {"min_views": 0}})", "min_views"},
      {R"({"depth_refinement": {"max_depth_change_mm": 50}})", "max_depth_change_mm"},
      {R"({"depth_refinement": {"huber_px": -1}})", "huber_px"},
      {R"({"depth_refinement": {"min_view": 10}})", "min_view"},
      // A track's first-frame views: 1-20 passes, a mirror yaw of 0-90 degrees.
      {R"({"start_view_passes": 0})", "start_view_passes"},
      {R"({"start_view_passes": 21})", "start_view_passes"},
      {R"({"start_mirror_yaw_deg": -5})", "start_mirror_yaw_deg"},
      {R"({"start_mirror_yaw_deg": 95})", "start_mirror_yaw_deg"},
      {R"({"head_tracking": "yes"})", "head_tracking"},
      {R"({"restart_unfit_tracked_frames": 1})", "restart_unfit_tracked_frames"}};
  for (const auto& [text, key] : bad_refinements) {
    const auto d = ConfigDocument::parse(text, "test.json");
    CHECK_THROWS_WITH(read_face_config(d.root(), "."), Catch::Contains(key));
  }
  const auto good = ConfigDocument::parse(R"({"pnp_method": "epnp_lm", "interpupillary_distance_mm": 60,
      "limits": {"max_yaw_deg": 60, "max_start_yaw_deg": 35}})", "test.json");
  const FaceConfig c = read_face_config(good.root(), ".");
  CHECK(c.solver.method == PnpMethod::EpnpLm);
  CHECK(c.head_tracking);
  CHECK_FALSE(read_face_config(ConfigDocument::parse(R"({"head_tracking": false})", "test.json").root(), ".").head_tracking);
  CHECK_FALSE(c.restart_unfit_tracked_frames);
  CHECK(read_face_config(ConfigDocument::parse(R"({"restart_unfit_tracked_frames": true})", "t.json").root(), ".")
            .restart_unfit_tracked_frames);
  CHECK(c.limits.max_start_yaw_rad == Approx(35 * kDeg));
  CHECK(c.interpupillary_distance_m == Approx(0.060));

  const ScratchDir scratch("face_people");
  const std::filesystem::path& dir = scratch.path();
  PersonShape p{"ada", 0.061, Eigen::VectorXd::Constant(14, 0.2), 1.5, {}};
  save_person_shape(p, person_shape_path(dir, "ada"));
  const PersonShape back = load_person_shape(person_shape_path(dir, "ada"), 14);
  CHECK(back.interpupillary_distance_m == Approx(0.061));
  CHECK(back.shape_params.isApprox(p.shape_params));
  CHECK(back.R_frontal_model.isIdentity(1e-12));
  // The registration's pose, which the person's frame takes for frontal: stored as angles, read back.
  PersonShape turned = p;
  turned.name = "bea";
  turned.R_frontal_model = head_rotation({}).transpose() * head_rotation({3 * kDeg, -7 * kDeg, 2 * kDeg});
  save_person_shape(turned, person_shape_path(dir, "bea"));
  CHECK(load_person_shape(person_shape_path(dir, "bea"), 14).R_frontal_model.isApprox(turned.R_frontal_model, 1e-9));
  for (const char* bad : {R"("frontal_pose_deg": {"yaw": 0, "pitch": 45, "roll": 0})",
                          R"("frontal_pose_deg": {"yaw": 0, "pitch": 0})", R"("frontal_pose_deg": {"yaw": "x", "pitch": 0, "roll": 0})", R"("frontal_pose_deg": 3)"}) {
    CAPTURE(bad);
    std::ofstream(dir / "bad.json") << R"({"name": "bad", "interpupillary_distance_mm": 63, "shape_params": )"
                                    << "[0,0,0,0,0,0,0,0,0,0,0,0,0,0], " << bad << "}";
    CHECK_THROWS_WITH(load_person_shape(dir / "bad.json", 14), Catch::Contains("frontal_pose_deg."));
  }
  CHECK_THROWS(load_person_shape(person_shape_path(dir, "ada"), 13));       // wrong unit count
  CHECK_THROWS(load_person_shape(dir / "missing.json", 14));
  CHECK_THROWS_AS(person_shape_path(dir, "../etc/passwd"), std::invalid_argument);
}

TEST_CASE("face: a rendered head is tracked at the right pose") {
  RenderedHeadFixture f;
  for (const auto& truth : {pose(0, 0, 0, {0, -0.02, 0.8}), pose(20, 10, -10, {0.05, 0.0, 1.2})}) {
    f.estimator.reset();
    FaceResult r;
    for (int i = 0; i < 4; ++i) r = f.estimator.process(f.render({truth}), i / 30.0);
    REQUIRE(r.tracking());
    CHECK((r.T_cam_face.translation() - truth.translation()).norm() < 0.05);
    CHECK(Eigen::AngleAxisd(r.T_cam_face.linear() * truth.linear().transpose()).angle() < 5 * kDeg);
    CHECK(r.quality > 0.2);
    CHECK(r.line_of_sight_cam.z() < -0.8);
    CHECK(r.landmarks.cols() == 68);
  }
}

TEST_CASE("face: several faces, a face cut by the border, a profile") {
  RenderedHeadFixture f;
  const Eigen::Isometry3d left = pose(0, 0, 0, {-0.2, -0.02, 0.9}), right = pose(0, 0, 0, {0.2, -0.02, 0.9});
  SECTION("two faces and no track: refused") {
    FaceResult r;
    // The full-frame search cycles its scales (0.5, 1, 2): within three frames it sees both.
    for (int i = 0; i < 3 && r.faces_found <= 0; ++i) r = f.estimator.process(f.render({left, right}), i / 30.0);
    CHECK(r.faces_found == 2);
    CHECK(r.reason == FaceLostReason::SeveralFaces);
  }
  SECTION("a second face appears: the one nearest the track is followed") {
    for (int i = 0; i < 3; ++i) f.estimator.process(f.render({right}), i / 30.0);
    REQUIRE(f.estimator.process(f.render({right}), 0.1).tracking());
    FaceResult r;
    for (int i = 0; i < 12; ++i) r = f.estimator.process(f.render({left, right}), 0.13 + i / 30.0);  // detector runs
    REQUIRE(r.tracking());
    CHECK(r.T_cam_face.translation().x() > 0.1);
  }
  SECTION("a face half out of the image is lost, not posed") {
    const FaceResult r = f.estimator.process(f.render({pose(0, 0, 0, {0.48, -0.02, 0.8})}), 0);
    CHECK_FALSE(r.tracking());
  }
  SECTION("a profile is lost") {
    for (int i = 0; i < 3; ++i) CHECK_FALSE(f.estimator.process(f.render({pose(88, 0, 0, {0, -0.02, 0.8})}), i).tracking());
  }
}

TEST_CASE("face: registration fits a frontal picture and refuses none or several faces") {
  RenderedHeadFixture f;
  const PersonShape p = register_person(f.estimator, f.render({pose(0, 0, 0, {0, -0.02, 0.8})}), "teacher", 0.063);
  CHECK(p.shape_params.size() == 14);
  CHECK(p.fit_rms_px < 5.0);
  CHECK((p.shape_params - f.renderer.head().shape_params).cwiseAbs().maxCoeff() < 0.3);
  CHECK_THROWS_WITH(register_person(f.estimator, blank(), "teacher", 0.063), Catch::Contains("no face"));
  CHECK_THROWS_WITH(register_person(f.estimator,
                                    f.render({pose(0, 0, 0, {-0.2, -0.02, 0.9}), pose(0, 0, 0, {0.2, -0.02, 0.9})}),
                                    "teacher", 0.063),
                    Catch::Contains("2 faces"));
  CHECK_THROWS_WITH(register_person(f.estimator, f.render({pose(35, 0, 0, {0, -0.02, 0.8})}), "teacher", 0.063),
                    Catch::Contains("turned"));

  // Several pictures of the still head: their landmarks are averaged (the same picture twice gives
  // the one picture's person); each must hold one face, and a refusal names the picture.
  const cv::Mat frontal = f.render({pose(0, 0, 0, {0, -0.02, 0.8})});
  const PersonShape once = register_person(f.estimator, frontal, "teacher", 0.063);
  const PersonShape twice = register_person(f.estimator, std::vector<cv::Mat>{frontal, frontal}, "teacher", 0.063);
  CHECK(twice.shape_params.isApprox(once.shape_params, 1e-9));
  CHECK(twice.fit_rms_px == Approx(once.fit_rms_px).epsilon(1e-9));
  const PersonShape moved =
      register_person(f.estimator, std::vector<cv::Mat>{frontal, f.render({pose(0, 0, 0, {0.01, -0.02, 0.8})})}, "teacher", 0.063);
  CHECK((moved.shape_params - f.renderer.head().shape_params).cwiseAbs().maxCoeff() < 0.3);
  CHECK_THROWS_WITH(register_person(f.estimator, std::vector<cv::Mat>{frontal, blank()}, "teacher", 0.063),
                    Catch::Contains("frontal picture 1 refused: no face found"));
  CHECK_THROWS_WITH(register_person(f.estimator, std::vector<cv::Mat>{}, "teacher", 0.063), Catch::Contains("none given"));
}

TEST_CASE("face: a head turn refines the registered landmarks, too little turn is refused") {
  RenderedHeadFixture f;
  const PersonShape p = register_person(f.estimator, f.render({pose(0, 0, 0, {0, -0.02, 0.8})}), "teacher", 0.063);
  // Left, right (first half), then up, down (second half), as a person asked to turn slowly would.
  std::vector<cv::Mat> turn;
  for (int i = 0; i < 40; ++i) {
    const double s = i / 40.0, wave = std::sin(2 * std::numbers::pi * std::fmod(2 * s, 1.0));
    turn.push_back(f.render({pose(s < 0.5 ? 25 * wave : 0, s < 0.5 ? 0 : 15 * wave, 0, {0, -0.02, 0.8})}));
  }
  const TurnRefinement r = refine_person_from_turns(f.estimator, p, turn);
  CHECK(r.views >= 30);
  CHECK(r.yaw_span_deg > 35);
  CHECK(r.pitch_span_deg > 20);
  CHECK(r.rms_after_px < r.rms_before_px);
  REQUIRE(r.person.landmark_offsets_m.cols() == f.estimator.model().size());
  CHECK(r.person.landmark_offsets_m.cwiseAbs().maxCoeff() <= 0.02);
  // In depth only: along the person's frontal frame's z.
  const Eigen::Matrix3Xd mapped = f.estimator.model().points_m(p.shape_params, p.interpupillary_distance_m);
  const Eigen::Matrix3Xd moved = person_landmarks_m(r.person, mapped) - person_landmarks_m(p, mapped);
  CHECK(moved.topRows(2).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(moved.row(2).cwiseAbs().maxCoeff() > 1e-4);
  CHECK(f.estimator.person().landmark_offsets_m.cols() == f.estimator.model().size());

  const std::vector<cv::Mat> still(12, f.render({pose(0, 0, 0, {0, -0.02, 0.8})}));
  CHECK_THROWS_WITH(refine_person_from_turns(f.estimator, p, still),
                    Catch::Contains("the head turned") && Catch::Contains("expected at least"));
  const std::vector<cv::Mat> empty_room(12, blank());
  CHECK_THROWS_WITH(refine_person_from_turns(f.estimator, p, empty_room), Catch::Contains("tracked in 0 of 12 frames"));
  CHECK_THROWS_WITH(refine_person_from_turns(f.estimator, p, {cv::Mat(10, 10, CV_8UC1, cv::Scalar(0))}),
                    Catch::Contains("turn frame 0: not the camera's size"));
}

TEST_CASE("face: the landmarks of a rolled face are found in an upright crop and turned back") {
  RenderedHeadFixture f;
  const cv::Mat upright = f.render({pose(0, 0, 0, {0, -0.02, 0.7})});
  const auto faces = f.estimator.find_faces(upright);
  REQUIRE(faces.size() == 1);
  const cv::Rect2d box = faces.front().box;
  LandmarkDetector landmarks(f.config.shape_predictor);
  Eigen::Matrix2Xd reference;
  landmarks.detect(upright, box, reference);
  // The whole picture turned 25° clockwise about the box centre (the eye line's angle becomes +25°).
  const double angle = 25 * kDeg;
  const cv::Point2f c(static_cast<float>(box.x + box.width / 2 - 0.5), static_cast<float>(box.y + box.height / 2 - 0.5));
  const cv::Mat M = cv::getRotationMatrix2D(c, -25.0, 1.0);
  cv::Mat rolled;
  cv::warpAffine(upright, rolled, M, upright.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  Eigen::Matrix2Xd turned;
  landmarks.detect(rolled, box, turned, angle);
  double sum = 0;
  for (Eigen::Index i = 0; i < 68; ++i) {
    const cv::Vec3d p(reference(0, i), reference(1, i), 1.0);
    const cv::Matx23d m(M);
    const cv::Vec2d expected = m * p;
    sum += std::hypot(turned(0, i) - expected[0], turned(1, i) - expected[1]);
  }
  CHECK(sum / 68 < 1.5);  // pixels; a wrong turn direction or centre moves them by tens of pixels
}

TEST_CASE("face: a frontal view of a turned head removes the predictor's pull towards frontal") {
  // dlib's ERT places a head turned 40° as if turned ~33° (docs/face.md); run on a view made frontal
  // through the mesh at the last pose, its landmarks give the turn.
  const Eigen::Isometry3d truth = pose(40, 0, 0, {0.02, -0.02, 0.8});
  std::array<double, 2> yaw_error_deg{};
  for (const bool frontal : {false, true}) {
    FaceConfig config = default_face_config();
    config.frontal_view = frontal;
    config.limits.max_start_yaw_rad = 90 * kDeg;  // the track starts at 40°
    RenderedHeadFixture f(config);
    FaceResult r;
    for (int i = 0; i < 6; ++i) r = f.estimator.process(f.render({truth}), i / 30.0);
    REQUIRE(r.tracking());
    yaw_error_deg[frontal] = std::abs(r.angles.yaw - head_angles(truth.linear()).yaw) / kDeg;
  }
  CHECK(yaw_error_deg[0] > 3.0);
  // The view-landmarks-pose loop of a still head settles at ~2.1° here (frames 2-6 after a first frame
  // posed on the view: 0.7, 1.5, 2.06, 2.07°), the crop's at 3.2-4.2°.
  CHECK(yaw_error_deg[1] < 2.5);
}

TEST_CASE("face: the first frame of a track is posed on the frontal view too") {
  // A new track has no pose to make the frontal view from; the crop's landmarks see a head turned
  // 40° as turned ~37.5°. The estimator poses them once and runs the predictor again on the frontal
  // view at that pose, so even the first frame gets the turn (the relative-motion errors of a whole
  // track are measured from it).
  const Eigen::Isometry3d truth = pose(40, 0, 0, {0.02, -0.02, 0.8});
  std::array<double, 2> yaw_error_deg{}, distance_error_m{};
  for (const bool frontal : {false, true}) {
    FaceConfig config = default_face_config();
    config.frontal_view = frontal;
    config.limits.max_start_yaw_rad = 90 * kDeg;  // the track starts at 40°
    RenderedHeadFixture f(config);
    // The full-frame search cycles its scales while nothing is tracked: the first tracked frame.
    FaceResult r;
    for (int i = 0; i < 3 && !r.tracking(); ++i) r = f.estimator.process(f.render({truth}), i / 30.0);
    REQUIRE(r.tracking());
    yaw_error_deg[frontal] = std::abs(r.angles.yaw - head_angles(truth.linear()).yaw) / kDeg;
    distance_error_m[frontal] = std::abs(r.T_cam_face.translation().z() - truth.translation().z());
  }
  CHECK(yaw_error_deg[0] > 2.0);
  CHECK(yaw_error_deg[1] < 2.0);
  CHECK(distance_error_m[1] < distance_error_m[0]);
}

TEST_CASE("face: a track starts only on a face turned less than max_start_yaw, then follows it further") {
  // A track's first pose is biased at a large yaw (seen less turned and farther) and, under the
  // relative-motion protocol, its error is carried through the track: the estimator waits for a less
  // turned face to start from, and a started track keeps following the head as it turns further.
  FaceConfig limited = default_face_config();
  limited.limits.max_start_yaw_rad = 30 * kDeg;  // off by default (control's search needs turned starts)
  RenderedHeadFixture f{limited};
  const Eigen::Vector3d at(0.02, -0.02, 1.0);
  double t = 0;
  int refused = 0;
  for (int i = 0; i < 4; ++i, t += 1 / 30.0) {
    const FaceResult r = f.estimator.process(f.render({pose(44, 0, 0, at)}), t);
    CHECK_FALSE(r.tracking());
    refused += r.reason == FaceLostReason::TurnedAtStart;
  }
  CHECK(refused >= 1);  // the others: the full-frame search's scales that miss the face
  FaceResult r;
  for (int i = 0; i < 3 && !r.tracking(); ++i, t += 1 / 30.0) r = f.estimator.process(f.render({pose(20, 0, 0, at)}), t);
  REQUIRE(r.tracking());
  for (const double yaw : {26.0, 32.0, 38.0, 44.0}) {
    r = f.estimator.process(f.render({pose(yaw, 0, 0, at)}), t);
    t += 1 / 30.0;
    REQUIRE(r.tracking());
  }
  CHECK(std::abs(r.angles.yaw / kDeg - 44.0) < 5.0);

  // Without the limit (the shipped default) the same turned face starts a track at once.
  const FaceConfig unlimited = default_face_config();
  REQUIRE(unlimited.limits.max_start_yaw_rad >= 89 * kDeg);
  RenderedHeadFixture g(unlimited);
  FaceResult first;
  for (int i = 0; i < 3 && !first.tracking(); ++i) first = g.estimator.process(g.render({pose(44, 0, 0, at)}), i / 30.0);
  CHECK(first.tracking());
}

TEST_CASE("face: a turned face's first pose is made on views with its far side mirrored, iterated") {
  // A track's first frame at 44.7° of yaw, 1.3 m, rolled 20° (the start of the face benchmark's
  // sequence free_5_138cm, docs/face.md "The start of a turned face"): one frontal view made at the
  // crop's pose (~12° short of the turn) leaves the face seen less turned and farther, and under the
  // relative-motion protocol every later frame's motion is measured from it. The views of a start,
  // iterated with the far side mirrored (seen obliquely, it is stretched from few pixels), get the
  // distance. The person is registered as the benchmark's: from 8 frames of the still frontal head,
  // blurred, noisy and through H.264 (surface landmarks from the frontal view); the blur is the
  // benchmark's middle.
  //
  // The bounds come from the spread over registration videos, seeds 1000-1059 (the same test with
  // `degraded_registration_pictures`' seed varied; the test runs seed 1): with the mirrored,
  // iterated views the three starts are +12 ± 9 mm (-2 to +47; 3 of 60 beyond 30), +14 ± 4 (-1 to
  // +22) and +13 ± 4 mm (+2 to +22) off; with one view +78 ± 3 (71 to 85), +26 ± 4 and +13 ± 4 mm; the
  // mirrored starts' summed error is 0.11-0.68 of the one view's. The bounds are those maxima with
  // about two standard deviations of margin. The remaining +13 mm at 44.7° is the start's own: the
  // renderer's true shape (no registration) gives +17 mm at 1.0 m; at 0°, 20° and 32° of yaw the same
  // registrations start within 10 mm.
  struct Case {
    Eigen::Isometry3d truth;
    double max_error_m;  // with the mirrored, iterated views
  };
  const Case cases[] = {{pose(-44.7, 6.4, -20.6, {0.05, -0.03, 1.30}), 0.060},
                        {pose(-44.7, 0, 0, {0.05, -0.03, 1.30}), 0.030},
                        {pose(-44.7, 0, 0, {0.05, -0.03, 1.00}), 0.030}};
  std::array<double, 2> sum_error_m{};
  for (const bool mirrored : {false, true}) {
    FaceConfig config = default_face_config();
    config.frontal_view = true;
    config.surface_landmarks = true;
    config.start_view_passes = mirrored ? 6 : 1;
    config.start_mirror_yaw_rad = mirrored ? 25 * kDeg : 0.0;
    RenderedHeadFixture f(config);
    const auto pictures = degraded_registration_pictures(f.render({pose(0, 0, 0, {0, -0.02, 0.8})}), 8, {},
                                                         test_camera(), 1);
    f.estimator.set_person(register_person(f.estimator, pictures, "teacher", 0.063), true);
    for (const Case& c : cases) {
      f.estimator.reset();
      cv::Mat frame = f.render({c.truth});
      cv::GaussianBlur(frame, frame, cv::Size(0, 0), 0.8);
      // The full-frame search cycles its scales while nothing is tracked: the first tracked frame.
      FaceResult r;
      for (int i = 0; i < 3 && !r.tracking(); ++i) r = f.estimator.process(frame, i / 30.0);
      REQUIRE(r.tracking());
      const double error_m = std::abs(r.T_cam_face.translation().z() - c.truth.translation().z());
      if (mirrored) CHECK(error_m < c.max_error_m);
      sum_error_m[mirrored] += error_m;
    }
  }
  WARN("first frames' distance error, sum: " << sum_error_m[0] << " m with one view, " << sum_error_m[1] << " m mirrored and iterated");
  CHECK(sum_error_m[0] > 0.08);  // the bias this is about
  CHECK(sum_error_m[1] < 0.8 * sum_error_m[0]);
}

TEST_CASE("face: the registered points are where tracking's frontal-view landmarks lie") {
  // Tracking finds its landmarks on the frontal view, registration on the detector's crop, and the
  // predictor does not put them at quite the same points of the face in the two. With the frontal view
  // on, registration places the person's points where the view's landmarks meet the mesh at the
  // fitted pose; with the crop's points a frontal head would be tracked ~1° low in pitch (the view's
  // landmarks against the crop's points, docs/face.md "The pitch offset").
  FaceConfig crop_config = default_face_config();
  crop_config.surface_landmarks = true;
  FaceConfig view_config = crop_config;
  view_config.frontal_view = true;
  RenderedHeadFixture crop(crop_config), f(view_config);
  const cv::Mat frontal = f.render({pose(0, 0, 0, {0, -0.02, 0.8})});
  const PersonShape from_crop = register_person(crop.estimator, frontal, "teacher", 0.063);
  const PersonShape from_view = register_person(f.estimator, frontal, "teacher", 0.063);
  CHECK(f.estimator.person().name == "astronaut");  // registration leaves the estimator's person alone
  CHECK(from_view.shape_params.isApprox(from_crop.shape_params, 1e-12));  // the same fit, other points
  std::array<double, 2> pitch_error_deg{};
  for (const PersonShape* person : {&from_crop, &from_view}) {
    f.estimator.set_person(*person, true);
    double sum = 0;
    int n = 0;
    for (const auto& truth : {pose(0, 0, 0, {0, -0.02, 0.8}), pose(0, 0, 0, {0.03, 0.0, 1.3})}) {
      f.estimator.reset();
      for (int i = 0; i < 20; ++i) {
        const FaceResult r = f.estimator.process(f.render({truth}), i / 30.0);
        if (i < 4) continue;  // the full-frame search's first frames, the track's start
        REQUIRE(r.tracking());
        // The still head's pose moves by ±0.5° from frame to frame (the view is made at the last
        // pose); its mean is the offset.
        sum += (r.angles.pitch - head_angles(truth.linear()).pitch) / kDeg;
        ++n;
      }
    }
    pitch_error_deg[person == &from_view] = sum / n;
  }
  WARN("mean pitch error " << pitch_error_deg[0] << " / " << pitch_error_deg[1]);
  CHECK(std::abs(pitch_error_deg[1]) < std::abs(pitch_error_deg[0]));

  // The view's landmarks need the view: none without it.
  CHECK_FALSE(crop.estimator.landmarks_in_frontal_view(frontal, cv::Rect2d(280, 120, 80, 80), pose(0, 0, 0, {0, -0.02, 0.8})));
}

TEST_CASE("face: a person's frame is the one in which their registration pictures show the head upright") {
  // The model's fit to one face's landmarks can hold the head a degree or two rolled (the gallery's
  // solvay_01, _05, _19: 1.6-2.0° median roll error before), and as the points' x and y come from the
  // landmarks' pixels every tracked pose would carry it. The registration pictures show the head
  // upright, so the person's frame takes the fitted roll out; a head registered rolled 5° is then
  // tracked 5° off when upright: the pictures define upright.
  RenderedHeadFixture f;
  const auto mean_angles_deg = [&](const Eigen::Isometry3d& truth) {
    f.estimator.reset();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int i = 0; i < 16; ++i) {
      const FaceResult r = f.estimator.process(f.render({truth}), i / 30.0);
      if (i < 4) continue;
      REQUIRE(r.tracking());
      const HeadAngles t = head_angles(truth.linear());
      sum += Eigen::Vector3d(r.angles.yaw - t.yaw, r.angles.pitch - t.pitch, r.angles.roll - t.roll) / kDeg;
      ++n;
    }
    return Eigen::Vector3d(sum / n);
  };
  const Eigen::Isometry3d frontal = pose(0, 0, 0, {0, -0.02, 0.8});
  const PersonShape person = register_person(f.estimator, f.render({frontal}), "teacher", 0.063);
  const HeadAngles taken_out = head_angles(head_rotation({}) * person.R_frontal_model);
  CHECK(taken_out.yaw == 0.0);
  CHECK(taken_out.pitch == 0.0);
  f.estimator.set_person(person, true);
  const Eigen::Vector3d at_registration = mean_angles_deg(frontal);
  CHECK(std::abs(at_registration.z()) < 0.3);
  CHECK(at_registration.cwiseAbs().maxCoeff() < 1.0);
  CHECK(mean_angles_deg(pose(15, 10, 0, {0.05, 0.0, 1.0})).cwiseAbs().maxCoeff() < 2.5);

  const PersonShape rolled = register_person(f.estimator, f.render({pose(0, 0, 5, {0, -0.02, 0.8})}), "teacher", 0.063);
  CHECK(head_angles(head_rotation({}) * rolled.R_frontal_model).roll / kDeg == Approx(5.0).margin(1.0));
  f.estimator.set_person(rolled, true);
  CHECK(mean_angles_deg(frontal).z() == Approx(-5.0).margin(1.0));
}
