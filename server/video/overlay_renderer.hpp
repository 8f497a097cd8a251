#pragma once
// Draws the overlays on a video frame in place: the panel outline and axes, the face mesh and axes,
// a HUD line (battery, altitude, yaw, link quality, mission stage) and a border in the localization
// source's colour (paper: green SLAM, blue homography, black/red vision lost). No allocation per
// frame beyond OpenCV's text rendering.
#include <opencv2/core.hpp>

#include "server/lab/flight_service.hpp"
#include "server/video/overlay_model.hpp"

namespace labo::server {

void draw_overlays(cv::Mat& bgr, const OverlayModel& overlay, const FlightTelemetry& telemetry);

// "#1060ff" -> BGR scalar; black for anything malformed.
cv::Scalar bgr_of(const std::string& hex_colour);

}  // namespace labo::server
