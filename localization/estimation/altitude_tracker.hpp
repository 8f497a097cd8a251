#pragma once
// AltitudeTracker: turns ultrasound ranges (to the surface below) into observations of the drone's
// height z in the world, telling a floor step (the drone passes over a bench edge: the range jumps, z
// does not) from a true vertical motion (a push: the range and z change together).
//
// The paper (§6.1, Fig. 8) threw away every range increment above gamma, so a push of more than gamma
// per navdata packet was taken for a floor step and the drone stayed displaced. Here the increment is
// compared with the change of z the filter predicts over the same interval, which already contains
// the commanded gaz and the navdata's vertical velocity: only the part the motion does not explain can
// be a floor step. A mismatch is not a floor step either when the navdata's vertical speed over the
// interval could have produced it (a push too short for the filter to integrate at 15 Hz), or when
// the lab's surface map says no edge lies near the drone: then the range is fused as true motion. Over a known surface the floor
// estimate is pulled to its surveyed height, so an earlier misclassification does not persist.
// A sudden shorter range that no motion explains over a surface where no step is possible is a
// spurious short echo (the sonar hears something nearer than the floor for a ping): it is dropped, and
// only accepted as motion if it persists for kEchoPersist: fused as motion, such echoes (the simulated
// lab's sonar has them) put 0.1-0.5 m spikes into z and the scale's metric odometry. Test
// "estimation: a short sonar echo over a surveyed floor is dropped, a lasting lower range is motion".
#include <Eigen/Core>
#include <optional>

#include "core/time.hpp"
#include "localization/estimation/surface_map.hpp"

namespace labo::estimation {

struct AltitudeDecision {
  // FusedAsMotion: an increment above gamma explained by vertical speed or a flat surface map.
  // ShortEcho: a spurious shorter range, not fused.
  enum class Kind { Anchored, Fused, FusedAsMotion, FloorStep, ShortEcho };
  Kind kind = Kind::Anchored;
  double z_observed = 0;  // world z to fuse (Fused, FusedAsMotion)
  double range_increment = 0;  // the range change accepted as motion (0 for a floor step)
  bool fuse() const { return kind == Kind::Fused || kind == Kind::FusedAsMotion; }
};

class AltitudeTracker {
 public:
  // PaperGammaOnly reproduces the paper's rule for comparison: every range increment above gamma is a
  // floor step, whatever the motion.
  enum class Mode { Discriminating, PaperGammaOnly };
  explicit AltitudeTracker(double gamma_m = 0.10, Mode mode = Mode::Discriminating) : gamma_(gamma_m), mode_(mode) {}

  static constexpr Seconds kEchoPersist = 0.25;  // a shorter range lasting this long is real

  void reset() { initialized_ = false; steps_ = 0; echo_since_.reset(); }
  // range_m: ultrasound corrected for tilt; z_predicted: the filter's z at the range's time;
  // xy_sigma: the position uncertainty (sets how near an edge counts as ambiguous).
  // vz_mps: the navdata's vertical speed in this packet (the evidence of a true vertical motion).
  AltitudeDecision process(double range_m, Seconds t, double z_predicted, double vz_mps, const Eigen::Vector2d& xy,
                           double xy_sigma, const SurfaceMap* map);
  // The filter's z after fusing (the reference for the next increment; kept across a short echo).
  void set_reference_z(double z) {
    if (!echo_since_) last_z_ = z;
  }

  double floor_z() const { return floor_z_; }
  int floor_steps() const { return steps_; }

 private:
  std::optional<double> known_edge_step(const SurfaceMap* map, const Eigen::Vector2d& xy, double margin,
                                        double rise) const;

  double gamma_;
  Mode mode_;
  bool initialized_ = false;
  double last_range_ = 0;
  double last_z_ = 0;
  double last_vz_ = 0;
  Seconds last_t_ = 0;
  double floor_z_ = 0;
  int steps_ = 0;
  std::optional<Seconds> echo_since_;  // a short echo is being dropped since then
};

}  // namespace labo::estimation
