#include "server/video/overlay_geometry.hpp"

#include <cmath>
#include <cstdio>

namespace labo::server {

namespace {

// Appends JSON to a reused string: numbers through snprintf into a stack buffer, strings escaped.
class JsonAppender {
 public:
  explicit JsonAppender(std::string& out) : out_(out) {}
  JsonAppender& raw(const char* text) {
    out_ += text;
    return *this;
  }
  JsonAppender& number(double v, const char* format = "%.1f") {
    if (!std::isfinite(v)) return raw("null");
    char buf[40];
    const int n = std::snprintf(buf, sizeof buf, format, v);
    out_.append(buf, static_cast<std::size_t>(n));
    return *this;
  }
  JsonAppender& integer(long long v) {
    char buf[24];
    const int n = std::snprintf(buf, sizeof buf, "%lld", v);
    out_.append(buf, static_cast<std::size_t>(n));
    return *this;
  }
  JsonAppender& string(const std::string& s) {
    out_ += '"';
    for (const char c : s) {
      if (c == '"' || c == '\\') {
        out_ += '\\';
        out_ += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
        out_ += buf;
      } else {
        out_ += c;
      }
    }
    out_ += '"';
    return *this;
  }
  JsonAppender& point(const cv::Point2f& p) {
    raw("[").number(p.x).raw(",").number(p.y).raw("]");
    return *this;
  }

 private:
  std::string& out_;
};

void write_axes(JsonAppender& j, const std::optional<AxesPx>& axes) {
  if (!axes) {
    j.raw("null");
    return;
  }
  j.raw("{\"o\":").point(axes->origin).raw(",\"x\":").point(axes->x).raw(",\"y\":").point(axes->y);
  j.raw(",\"z\":").point(axes->z).raw("}");
}

void write_points(JsonAppender& j, const std::vector<cv::Point2f>& points) {
  j.raw("[");
  for (std::size_t i = 0; i < points.size(); ++i) j.raw(i ? "," : "").point(points[i]);
  j.raw("]");
}

void write_outline(JsonAppender& j, const OutlineOverlay& o, double clock_to_unix_s) {
  if (o.corners.size() != 4) {
    j.raw("null");
    return;
  }
  j.raw("{\"corners\":");
  write_points(j, o.corners);
  j.raw(",\"axes\":");
  write_axes(j, o.axes);
  j.raw(",\"measured_ms\":").number((o.measured_t + clock_to_unix_s) * 1000.0, "%.3f").raw("}");
}

void write_face(JsonAppender& j, const FaceOverlay& f, double clock_to_unix_s) {
  if (f.points.empty()) {
    j.raw("null");
    return;
  }
  j.raw("{\"points\":");
  write_points(j, f.points);
  j.raw(",\"edges\":[");
  for (std::size_t i = 0; i < f.edges.size(); ++i)
    j.raw(i ? ",[" : "[").integer(f.edges[i].first).raw(",").integer(f.edges[i].second).raw("]");
  j.raw("],\"axes\":");
  write_axes(j, f.axes);
  j.raw(",\"measured_ms\":").number((f.measured_t + clock_to_unix_s) * 1000.0, "%.3f").raw("}");
}

}  // namespace

std::shared_ptr<const std::string> OverlayGeometryWriter::write(const OverlayModel& o, const FlightTelemetry& t,
                                                                const FrameStamp& frame, double clock_to_unix_s) {
  auto buffer = pool_.acquire();
  buffer->clear();
  JsonAppender j(*buffer);
  j.raw("{\"type\":\"overlay\",\"frame\":").integer(frame.frame_number);
  j.raw(",\"capture_ms\":").number(frame.capture_unix_ms, "%.3f");
  j.raw(",\"camera\":").raw(frame.camera == CameraId::Bottom ? "\"bottom\"" : "\"front\"");
  j.raw(",\"width\":").integer(frame.width).raw(",\"height\":").integer(frame.height);
  j.raw(",\"source\":").string(to_string(t.source)).raw(",\"source_colour\":").string(colour_of(t.source));
  j.raw(",\"panel\":");
  write_outline(j, o.panel, clock_to_unix_s);
  j.raw(",\"platform\":");
  write_outline(j, o.platform, clock_to_unix_s);
  j.raw(",\"face\":");
  write_face(j, o.face, clock_to_unix_s);
  j.raw(",\"hud\":{\"battery_percent\":").number(t.battery_percent);
  j.raw(",\"altitude_m\":").number(t.altitude_m, "%.2f");
  j.raw(",\"yaw_deg\":").number(t.pose.yaw_rad * 180.0 / M_PI);
  j.raw(",\"link_quality\":").number(t.link_quality, "%.2f");
  j.raw(",\"mission\":").string(t.mission).raw(",\"stage\":").string(t.stage).raw("}}");
  return buffer;
}

}  // namespace labo::server
