#include <catch2/catch.hpp>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/planar/sequence_bench.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

// The refinement of the template samples in the undistorted, smoothed frame (the sampled model: not
// the default, still used when a motion blur is modelled).
planar::PlanarConfig sampled_model() {
  planar::PlanarConfig c;
  c.se3_footprint_model = false;
  return c;
}

// One bench sequence through the IC tracker with the default configuration.
SequenceStats run_ic(const std::string& sequence) {
  const SequenceBenchResult result =
      run_sequence_bench(planar::PlanarConfig{}, VisionThresholds{}, sequence, {planar::TrackerKind::InverseCompositional});
  REQUIRE(result.sequences.size() == 1);
  return result.sequences.front();
}

}  // namespace

// The simulated lab's oscilloscope approached from 3 m to 0.6 m, rendered by the lab's own renderer
// (the `bench planar` sequence). At 2.3-2.4 m the panel (~97 px wide) is tracked on the 80 px
// template level, coarser than the frame, where full Gauss-Newton steps of IC would cycle across the
// minimum until the iteration limit: losses for no convergence, each restarting the pose filter.
TEST_CASE("planar: the lab's oscilloscope is tracked from 3 m to 0.6 m without a loss") {
  const SequenceStats s = run_ic("lab_renderer_oscilloscope");
  CHECK(s.losses == 0);
  CHECK(s.detections == 1);
  CHECK(s.frames_with_pose == s.frames_in_view);
}

// The motion-blur sequence (a panel swept sideways at 1.2 m, up to 9 px of blur): the pose refinement
// searches the exposure (a fraction of the frame's motion). Starting at the previous frame's exposure,
// from the best pose so far, it needs about half the Gauss-Newton iterations of a search from "no
// blur" upward from the IPPE pose every time, for the same poses.
TEST_CASE("planar: the motion-blur search starts at the last exposure: half the refinement work, same accuracy") {
  const SequenceStats s = run_ic("motion_blur");
  CHECK(s.losses == 0);
  CHECK(s.gross_errors == 0);
  CHECK(s.median_error_deg < 0.35);
  CHECK(s.p95_error_deg < 0.7);
  CHECK(s.mean_refinement_iterations > 0);
  CHECK(s.mean_refinement_iterations < 18);
}

// The lab's oscilloscope (0.40 x 0.20 m, ~75-110 px wide) at 2-3 m: seen nearly face-on, the two IPPE
// branches refine to two mirror minima of the photometric fit, 5-11 deg apart with residuals within a
// few %, on either side of the truth; the lower residual would pick one of them at random. The pose
// midway between them is nearer the truth. A rule of the sampled model.
TEST_CASE("planar: two refined IPPE branches the fit cannot tell apart give the pose midway between them") {
  const SequenceBenchResult result = run_sequence_bench(sampled_model(), VisionThresholds{}, "lab_renderer_oscilloscope",
                                                        {planar::TrackerKind::InverseCompositional});
  std::vector<double> far;
  for (const FrameRecord& f : result.frames) {
    if (f.has_pose && f.range_m >= 2.6) far.push_back(f.rotation_error_deg.norm());
  }
  REQUIRE(far.size() >= 20);
  std::nth_element(far.begin(), far.begin() + static_cast<std::ptrdiff_t>(far.size() / 2), far.end());
  CHECK(far[far.size() / 2] < 2.2);
  bool binned = false;
  for (const RangeBinStats& bin : result.range_bins) {
    if (bin.min_m != 2.0) continue;
    binned = true;
    CHECK(bin.median_error_deg < 1.6);
    CHECK(bin.rotation_within_2sigma_percent >= 85);  // the sigma covers both branches
  }
  CHECK(binned);
}

// On other frames of that approach both IPPE branches refine into the same one of the two mirror
// minima (3-4 deg off); the refined pose mirrored about the line of sight is refined as well and
// the midway rule applies to it. A rule of the sampled model (the footprint model's cost has no split
// minimum).
TEST_CASE("planar: the mirror of the refined pose finds the other minimum both IPPE branches missed") {
  const SequenceBenchResult result = run_sequence_bench(sampled_model(), VisionThresholds{}, "lab_renderer_oscilloscope",
                                                        {planar::TrackerKind::InverseCompositional});
  bool binned = false;
  for (const RangeBinStats& bin : result.range_bins) {
    if (bin.min_m != 2.0) continue;
    binned = true;
    CHECK(bin.p95_error_deg < 3.4);
    CHECK(bin.median_filtered_error_deg < 1.3);
  }
  CHECK(binned);
}

// The SE(3) refinement estimates the frame's blur relative to the template level (`se3_estimate_blur`,
// the default): with the blur fixed at the level's the fit bends the panel's shape, a tilt at 2-3 m.
// With the blur estimated `se3_template_resolution: frame` does worse than the pyramid level, which
// stays the default (docs/planar.md). The sampled model's test; target <= 1 deg median.
TEST_CASE("planar: the lab's oscilloscope at 2-3 m is within 1 degree with the frame's blur estimated") {
  planar::PlanarConfig config = sampled_model();
  REQUIRE(config.se3.estimate_blur);
  REQUIRE_FALSE(config.se3.resample_to_frame);
  const SequenceBenchResult result =
      run_sequence_bench(config, VisionThresholds{}, "lab_renderer_oscilloscope", {planar::TrackerKind::InverseCompositional});
  bool binned = false;
  for (const RangeBinStats& bin : result.range_bins) {
    if (bin.min_m != 2.0) continue;
    binned = true;
    CHECK(bin.median_error_deg < 1.0);
    CHECK(bin.p95_error_deg < 3.1);
  }
  CHECK(binned);
}

// The pixel's footprint modelled (`se3_pixel_model: footprint`, the default): each raw frame pixel
// predicted as the template's mean over its footprint. On the lab's oscilloscope, rendered as a camera
// integrates each pixel (area-filtered panels), at 2-3 m it does better than the sampled model on the
// same frames; target <= 1 deg at the 95th percentile.
TEST_CASE("planar: the lab's oscilloscope at 2-3 m is within 1 degree at the 95th percentile with the pixel's footprint modelled") {
  const planar::PlanarConfig config;
  REQUIRE(config.se3_footprint_model);
  for (const bool footprint : {true, false}) {
    const SequenceBenchResult result = run_sequence_bench(footprint ? config : sampled_model(), VisionThresholds{},
                                                          "lab_renderer_oscilloscope", {planar::TrackerKind::InverseCompositional});
    REQUIRE(result.sequences.size() == 1);
    CHECK(result.sequences.front().losses == 0);
    bool binned = false;
    for (const RangeBinStats& bin : result.range_bins) {
      if (bin.min_m != 2.0) continue;
      binned = true;
      INFO((footprint ? "footprint" : "sampled") << ": 2-3 m " << bin.median_error_deg << " / " << bin.p95_error_deg << " deg");
      if (footprint) {
        CHECK(bin.median_error_deg < 0.3);
        CHECK(bin.p95_error_deg < 1.0);
        CHECK(bin.rotation_within_2sigma_percent >= 90);
      } else {
        CHECK(bin.p95_error_deg > 1.5);  // what the footprint model fixes
      }
    }
    CHECK(binned);
  }
}

TEST_CASE("planar: the H.264 approach runs over several noise seeds, each reported and pooled apart from the other sequences") {
  const SequenceBenchResult result = run_sequence_bench(planar::PlanarConfig{}, VisionThresholds{}, "h264",
                                                        {planar::TrackerKind::InverseCompositional}, kDefaultH264Kbps, 2);
  REQUIRE(result.sequences.size() == 2);
  CHECK(result.h264_seeds == 2);
  CHECK(result.sequences[0].sequence == h264_sequence_name(0));
  CHECK(result.sequences[1].sequence == "h264_approach_2.5m_to_0.7m_seed1");
  // The same path with another noise: the poses differ.
  std::vector<double> errors[2];
  for (const FrameRecord& f : result.frames) errors[f.sequence == h264_sequence_name(0) ? 0 : 1].push_back(f.rotation_error_deg.norm());
  REQUIRE(errors[0].size() == 150);
  REQUIRE(errors[1].size() == 150);
  CHECK(errors[0] != errors[1]);
  // The panel-frame error is the camera-frame one turned into the panel's axes: the same length; the
  // approach looks at the panel nearly face-on, so nearly the same vector, but not exactly.
  int turned = 0;
  for (const FrameRecord& f : result.frames) {
    REQUIRE(f.has_pose);
    CHECK(f.panel_rotation_error_deg.norm() == Approx(f.rotation_error_deg.norm()).margin(1e-12));
    CHECK(f.panel_rotation_error_deg.dot(f.rotation_error_deg) >= 0.9 * f.rotation_error_deg.squaredNorm());
    turned += (f.panel_rotation_error_deg - f.rotation_error_deg).norm() > 1e-6 ? 1 : 0;
  }
  CHECK(turned > 0);
  REQUIRE(result.range_bins.size() == 3);
  REQUIRE(result.h264_seed_bins.size() == 3);
  for (std::size_t b = 0; b < 3; ++b) {
    const int seed0 = result.sequences[0].range_bins.at(b).poses, seed1 = result.sequences[1].range_bins.at(b).poses;
    CHECK(result.range_bins[b].poses == seed0);  // the all-sequence bins keep seed 0 only
    CHECK(result.h264_seed_bins[b].poses == seed0 + seed1);
  }
  CHECK(result.h264_seed_bins[2].poses > 0);  // 2-3.1 m
  CHECK_THROWS_AS(run_sequence_bench(planar::PlanarConfig{}, VisionThresholds{}, "h264", {planar::TrackerKind::InverseCompositional},
                                     kDefaultH264Kbps, 0),
                  std::invalid_argument);
}
