#include "bench/planar/perturbation_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "localization/planar/track/homography_tracker.hpp"
#include "localization/planar/planar_template.hpp"
#include "bench/planar/synthetic_scene.hpp"

namespace labo::bench {

namespace {

struct Accumulator {
  int converged = 0, trials = 0;
  double rms_sum = 0, iterations = 0;
  std::vector<double> ms, rms;

  void add(const planar::HomographyTrackOutcome& o, double error, double elapsed_ms, double threshold) {
    ++trials;
    ms.push_back(elapsed_ms);
    iterations += o.iterations;
    if (o.converged && error <= threshold) {
      ++converged;
      rms_sum += error;
      rms.push_back(error);
    }
  }
  TrackerSweepStats stats() {
    TrackerSweepStats s;
    if (trials == 0) return s;
    s.convergence_rate = static_cast<double>(converged) / trials;
    s.mean_converged_rms_px = converged > 0 ? rms_sum / converged : 0.0;
    std::sort(ms.begin(), ms.end());
    std::sort(rms.begin(), rms.end());
    s.median_converged_rms_px = rms.empty() ? 0.0 : rms[rms.size() / 2];
    s.median_ms = ms[ms.size() / 2];
    for (double m : ms) s.mean_ms += m / static_cast<double>(ms.size());
    s.mean_iterations = iterations / trials;
    return s;
  }
};

double time_ms(planar::HomographyTracker& tracker, const cv::Mat& scene, const cv::Matx33d& H0, planar::HomographyTrackOutcome& out) {
  const auto start = std::chrono::steady_clock::now();
  out = tracker.track(scene, H0);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::vector<PerturbationRow> run_perturbation_sweep(const PerturbationSettings& settings, const planar::PlanarConfig& config) {
  std::vector<double> sigmas = settings.sigmas_px;
  if (sigmas.empty()) {
    for (int s = 1; s <= 20; ++s) sigmas.push_back(s);
  }
  const int side = settings.template_side_px;
  const cv::Mat templ = make_procedural_panel(cv::Size(side, side), settings.seed);
  const cv::Mat background =
      make_clutter_background(cv::Size(settings.scene_width_px, settings.scene_height_px), settings.seed + 1);
  planar::PlanarConfig ecc_config = config, ic_config = config;
  auto ecc = make_homography_tracker(planar::TrackerKind::Ecc, templ, ecc_config);
  auto ic = make_homography_tracker(planar::TrackerKind::InverseCompositional, templ, ic_config);

  const double x0 = (settings.scene_width_px - side) / 2.0, y0 = (settings.scene_height_px - side) / 2.0;
  const cv::Matx33d H0(1, 0, x0, 0, 1, y0, 0, 0, 1);
  const std::array<cv::Point2d, 4> tc{cv::Point2d(-0.5, -0.5), cv::Point2d(side - 0.5, -0.5),
                                      cv::Point2d(side - 0.5, side - 0.5), cv::Point2d(-0.5, side - 0.5)};
  const auto base = planar::map_corners(H0, tc);
  cv::RNG rng(settings.seed + 2);
  std::vector<PerturbationRow> rows;
  cv::Mat scene, noise(background.size(), CV_16SC1), wide;
  for (double sigma : sigmas) {
    Accumulator a_ecc, a_ic;
    for (int trial = 0; trial < settings.trials; ++trial) {
      std::array<cv::Point2d, 4> truth;
      std::array<cv::Point2f, 4> src, dst;
      for (std::size_t i = 0; i < 4; ++i) {
        truth[i] = base[i] + cv::Point2d(rng.gaussian(sigma), rng.gaussian(sigma));
        src[i] = cv::Point2f(static_cast<float>(tc[i].x), static_cast<float>(tc[i].y));
        dst[i] = cv::Point2f(static_cast<float>(truth[i].x), static_cast<float>(truth[i].y));
      }
      const cv::Matx33d H_true = cv::getPerspectiveTransform(src.data(), dst.data());
      scene = background.clone();
      draw_template(templ, H_true, scene);
      rng.fill(noise, cv::RNG::NORMAL, 0, settings.pixel_noise);
      scene.convertTo(wide, CV_16S);
      wide += noise;
      wide.convertTo(scene, CV_8U);

      planar::HomographyTrackOutcome o;
      double ms = time_ms(*ecc, scene, H0, o);
      a_ecc.add(o, planar::corner_rms(planar::map_corners(o.H, tc), truth), ms, settings.converged_rms_px);
      ms = time_ms(*ic, scene, H0, o);
      a_ic.add(o, planar::corner_rms(planar::map_corners(o.H, tc), truth), ms, settings.converged_rms_px);
    }
    rows.push_back({sigma, a_ecc.stats(), a_ic.stats()});
  }
  return rows;
}

}  // namespace labo::bench
