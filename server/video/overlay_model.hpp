#pragma once
// What is drawn on a video frame, in image pixels of the frame it belongs to: the tracked panel's
// outline and axes, the face mesh and its axes. The HUD comes from FlightTelemetry.
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

namespace labo {

struct AxesPx {
  cv::Point2f origin, x, y, z;  // projections of the origin and of the three unit-axis tips
};

struct OverlayModel {
  std::vector<cv::Point2f> panel_corners;  // 4 corners, template order (tl, tr, br, bl)
  std::optional<AxesPx> panel_axes;
  std::vector<cv::Point2f> face_points;    // landmarks or projected mesh vertices
  std::vector<std::pair<int, int>> face_edges;  // indices into face_points
  std::optional<AxesPx> face_axes;
};

}  // namespace labo
