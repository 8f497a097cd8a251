#include "localization/estimation/altitude_tracker.hpp"

#include <cmath>

namespace labo {

namespace {
constexpr Seconds kMaxGap = 0.5;             // beyond, increments are not comparable: re-anchor
constexpr Seconds kFloorPullTime = 0.5;      // floor estimate -> surveyed height, time constant
constexpr double kSurfaceTolerance = 0.05;   // the floor estimate "is" a surveyed surface within this
constexpr double kMotionEvidenceShare = 0.5;  // share of a range change the vertical speed must explain
}  // namespace

AltitudeDecision AltitudeTracker::process(double range_m, Seconds t, double z_predicted, double vz_mps,
                                          const Eigen::Vector2d& xy, double xy_sigma, const SurfaceMap* map) {
  const double margin = 2.0 * xy_sigma + 0.05;
  const std::optional<double> surveyed_opt =
      (map != nullptr && !map->empty()) ? map->unambiguous_height(xy, margin) : std::nullopt;
  const bool surveyed = surveyed_opt.has_value();
  const double surveyed_z = surveyed_opt.value_or(0.0);
  AltitudeDecision d;
  if (!initialized_ || t - last_t_ > kMaxGap) {
    floor_z_ = surveyed ? surveyed_z : z_predicted - range_m;
    initialized_ = true;
    d.kind = surveyed ? AltitudeDecision::Kind::Fused : AltitudeDecision::Kind::Anchored;
  } else {
    const double range_change = range_m - last_range_;
    const double z_change = z_predicted - last_z_;
    const double apparent_floor_rise = z_change - range_change;
    if (mode_ == Mode::PaperGammaOnly) {
      if (std::abs(range_change) > gamma_) {
        floor_z_ += apparent_floor_rise;
        ++steps_;
        d.kind = AltitudeDecision::Kind::FloorStep;
      } else {
        d.kind = AltitudeDecision::Kind::Fused;
        d.range_increment = range_change;
      }
    } else if (std::abs(apparent_floor_rise) > gamma_) {
      // Far from any edge, on the surface we believe we are over: the floor cannot have moved.
      const bool no_step_possible = surveyed && std::abs(surveyed_z - floor_z_) < kSurfaceTolerance;
      // The vertical speed measured at either end of the interval, in the range's direction, could
      // account for at least half of the change: the drone moved (floor steps happen at vz ~ 0).
      const double speed_reach = std::max(std::abs(vz_mps), std::abs(last_vz_)) * (t - last_t_);
      const bool same_direction = range_change * (std::abs(vz_mps) > std::abs(last_vz_) ? vz_mps : last_vz_) > 0;
      const bool motion_explains = same_direction && speed_reach > kMotionEvidenceShare * std::abs(range_change);
      if (no_step_possible || motion_explains) {
        d.kind = AltitudeDecision::Kind::FusedAsMotion;
        d.range_increment = range_change;
      } else {
        floor_z_ += apparent_floor_rise;
        ++steps_;
        d.kind = AltitudeDecision::Kind::FloorStep;
      }
    } else {
      if (surveyed) floor_z_ += (1.0 - std::exp(-(t - last_t_) / kFloorPullTime)) * (surveyed_z - floor_z_);
      d.kind = AltitudeDecision::Kind::Fused;
      d.range_increment = range_change;
    }
  }
  d.z_observed = floor_z_ + range_m;
  last_range_ = range_m;
  last_z_ = z_predicted;
  last_vz_ = vz_mps;
  last_t_ = t;
  return d;
}

}  // namespace labo
