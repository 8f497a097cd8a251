#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "render_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::test;

namespace {

SceneState looking_at_wall() {
  return still_scene(body_looking_at({2.0, 0.5, 1.2}, {2.0, 3.0, 1.3}));  // the north bench and its wall
}

double gradient_energy(const cv::Mat& bgr) {
  cv::Mat gray, dx;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::Sobel(gray, dx, CV_32F, 1, 0);
  return cv::norm(dx, cv::NORM_L1);
}

}  // namespace

TEST_CASE("render: the same seed and scene give the same image, another seed or instant other noise") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer a(lab, ardrone_cameras(), std::nullopt, 7), b(lab, ardrone_cameras(), std::nullopt, 7),
      c(lab, ardrone_cameras(), std::nullopt, 8);
  SceneState s = looking_at_wall();
  s.t = 1.25;
  s.angular_velocity_body_radps = {0, 0, 0.8};
  cv::Mat ia, ia2, ib, ic, later;
  a.render(CameraId::Front, s, ia);
  a.render(CameraId::Front, s, ia2);
  b.render(CameraId::Front, s, ib);
  c.render(CameraId::Front, s, ic);
  CHECK(cv::norm(ia, ia2, cv::NORM_INF) == 0);
  CHECK(cv::norm(ia, ib, cv::NORM_INF) == 0);
  CHECK(cv::norm(ia, ic, cv::NORM_L1) > 0.5 * ia.total());
  s.t += 1.0 / 30;
  a.render(CameraId::Front, s, later);
  CHECK(cv::norm(ia, later, cv::NORM_L1) > 0.5 * ia.total());
  for (const CameraId id : {CameraId::Front, CameraId::Bottom}) {
    a.render(id, s, ia);
    CHECK(ia.type() == CV_8UC3);
    CHECK(ia.cols == 640);
    CHECK(ia.rows == 360);
  }
}

TEST_CASE("render: turning during the exposure blurs along the motion, sized by the shutter time") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderOptions o = sharp_options();
  o.motion_blur = true;
  o.shutter_s = 0.010;
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, o);
  SceneState s = looking_at_wall();
  cv::Mat still, turning;
  renderer.render(CameraId::Front, s, still);
  CHECK(renderer.last_stats(CameraId::Front).blur_px < 0.01f);
  s.angular_velocity_body_radps = {0, 0, 1.0};  // 57 deg/s of yaw
  renderer.render(CameraId::Front, s, turning);
  // fx * rate * shutter = 5.7 px at the centre; more towards the distorted edges.
  const float blur = renderer.last_stats(CameraId::Front).blur_px;
  CHECK(blur > 5.0f);
  CHECK(blur < 9.0f);
  CHECK(gradient_energy(turning) < 0.7 * gradient_energy(still));
  // A slow drift (0.3 px at the centre) blurs a little: less than the turn, but not nothing.
  s.angular_velocity_body_radps = {0, 0, 0.05};
  cv::Mat drifting;
  renderer.render(CameraId::Front, s, drifting);
  CHECK(renderer.last_stats(CameraId::Front).blur_px < 1.0f);
  CHECK(gradient_energy(drifting) < 0.99 * gradient_energy(still));
  CHECK(gradient_energy(drifting) > 0.7 * gradient_energy(still));
  CHECK(gradient_energy(drifting) > gradient_energy(turning));
  // Below MotionBlur::kMinMotion_px everywhere (0.006 px at the centre) the image is unchanged.
  s.angular_velocity_body_radps = {0, 0, 0.001};
  cv::Mat hovering;
  renderer.render(CameraId::Front, s, hovering);
  CHECK(renderer.last_stats(CameraId::Front).blur_px < MotionBlur::kMinMotion_px);
  CHECK(cv::norm(still, hovering, cv::NORM_INF) == 0);
}

TEST_CASE("render: exposure gain scales the image, noise has the configured spread") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer sharp(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  LabRenderOptions noisy_options = sharp_options();
  noisy_options.noise = true;
  noisy_options.noise_sigma = 3.0;
  LabRenderer noisy(lab, ardrone_cameras(), std::nullopt, 1, noisy_options);
  SceneState s = looking_at_wall();
  s.exposure_gain = 0.5;
  cv::Mat dark, nominal, with_noise;
  sharp.render(CameraId::Front, s, dark);
  s.exposure_gain = 1.0;
  sharp.render(CameraId::Front, s, nominal);
  CHECK(cv::mean(dark)[1] == Approx(0.5 * cv::mean(nominal)[1]).epsilon(0.02));
  noisy.render(CameraId::Front, s, with_noise);
  cv::Mat diff;
  cv::subtract(with_noise, nominal, diff, cv::noArray(), CV_32F);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff.reshape(1), mean, sd);
  CHECK(std::abs(mean[0]) < 0.3);
  CHECK(sd[0] == Approx(3.0).epsilon(0.1));
}
