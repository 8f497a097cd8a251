#pragma once
// What is drawn on a video frame, in image pixels of the frame it belongs to: the tracked panel's
// and the landing platform's outlines and axes, the face mesh and its axes. The HUD and the source
// border come from FlightTelemetry. Drawn into the JPEG by overlay_renderer, sent as data to the
// H.264 viewers by overlay_geometry.
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "core/time.hpp"

namespace labo::server {

struct AxesPx {
  cv::Point2f origin, x, y, z;  // projections of the origin and of the three unit-axis tips
};

// A tracked planar target (an instrument panel, the landing platform).
struct OutlineOverlay {
  std::vector<cv::Point2f> corners;  // 4 corners, template order (tl, tr, br, bl); empty: not tracked
  std::optional<AxesPx> axes;
  Seconds measured_t = 0;            // time of the frame the tracker measured this on
  cv::Size template_px;              // the target's template resolution (0 x 0: unknown)
};

struct FaceOverlay {
  std::vector<cv::Point2f> points;         // landmarks or projected mesh vertices; empty: no face
  std::vector<std::pair<int, int>> edges;  // indices into points
  std::optional<AxesPx> axes;
  Seconds measured_t = 0;
};

struct OverlayModel {
  OutlineOverlay panel;
  OutlineOverlay platform;
  FaceOverlay face;
};

}  // namespace labo::server
