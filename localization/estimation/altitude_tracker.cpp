#include "localization/estimation/altitude_tracker.hpp"

#include <array>
#include <cmath>

namespace labo::estimation {

namespace {
constexpr Seconds kMaxGap = 0.5;             // beyond, increments are not comparable: re-anchor
constexpr Seconds kFloorPullTime = 0.5;      // floor estimate -> surveyed height, time constant
constexpr double kSurfaceTolerance = 0.05;   // the floor estimate "is" a surveyed surface within this
constexpr double kMotionEvidenceShare = 0.5;  // share of a range change the vertical speed must explain
// A surveyed surface near the drone whose height differs from the current floor by the apparent rise
// (within kEdgeMatch), when that rise is large enough to tell from noise.
std::optional<double> known_edge_step_impl(const SurfaceMap* map, const Eigen::Vector2d& xy, double margin,
                                           double floor_z, double rise) {
  constexpr double kEdgeMatch = 0.02, kMinRise = 0.025;
  if (map == nullptr || map->empty() || std::abs(rise) < kMinRise) return std::nullopt;
  std::array<double, 8> heights{};
  const int n = map->heights_near(xy, margin, heights.data(), static_cast<int>(heights.size()));
  if (n < 2) return std::nullopt;
  for (int i = 0; i < n; ++i) {
    if (std::abs(heights[i] - floor_z - rise) < kEdgeMatch) return heights[i];
  }
  return std::nullopt;
}
}  // namespace

std::optional<double> AltitudeTracker::known_edge_step(const SurfaceMap* map, const Eigen::Vector2d& xy, double margin,
                                                       double rise) const {
  return known_edge_step_impl(map, xy, margin, floor_z_, rise);
}

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
    } else if (const std::optional<double> edge = known_edge_step(map, xy, margin, apparent_floor_rise);
               edge && std::abs(apparent_floor_rise) <= gamma_) {
      // A small step (under gamma) that matches a surveyed edge next to the drone: the floor changed.
      floor_z_ = *edge;
      ++steps_;
      d.kind = AltitudeDecision::Kind::FloorStep;
    } else if (std::abs(apparent_floor_rise) > gamma_) {
      // Far from any edge, on the surface we believe we are over: the floor cannot have moved.
      const bool no_step_possible = surveyed && std::abs(surveyed_z - floor_z_) < kSurfaceTolerance;
      // The vertical speed measured at either end of the interval, in the range's direction, could
      // account for at least half of the change: the drone moved (floor steps happen at vz ~ 0).
      const double speed_reach = std::max(std::abs(vz_mps), std::abs(last_vz_)) * (t - last_t_);
      const bool same_direction = range_change * (std::abs(vz_mps) > std::abs(last_vz_) ? vz_mps : last_vz_) > 0;
      const bool motion_explains = same_direction && speed_reach > kMotionEvidenceShare * std::abs(range_change);
      // A shorter range nothing explains where the floor cannot have risen: the sonar's short echo.
      const bool short_echo = no_step_possible && !motion_explains && range_change < 0 &&
                              (!echo_since_ || t - *echo_since_ < kEchoPersist);
      if (short_echo) {
        if (!echo_since_) echo_since_ = t;
        d.kind = AltitudeDecision::Kind::ShortEcho;
        d.z_observed = floor_z_ + range_m;
        return d;  // the increment is measured from the last good range when the echo ends
      }
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
  echo_since_.reset();
  d.z_observed = floor_z_ + range_m;
  last_range_ = range_m;
  last_z_ = z_predicted;
  last_vz_ = vz_mps;
  last_t_ = t;
  return d;
}

}  // namespace labo::estimation
