#include "drone/sim/scene_teacher.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace labo::sim {

using lab::TeacherSpec;


namespace {

constexpr double kShoulderBelowEyes_m = 0.25;
constexpr double kWaist_m = 0.95;

std::uint32_t shaded(std::uint32_t colour, const Eigen::Vector3f& normal) {
  const Eigen::Vector3f light = Eigen::Vector3f(0.4f, 0.3f, 0.85f).normalized();
  const float k = 0.6f + 0.4f * std::max(0.f, normal.dot(light));
  return pack_bgr(static_cast<int>(texel_b(colour) * k), static_cast<int>(texel_g(colour) * k), static_cast<int>(texel_r(colour) * k));
}

// A cylinder about z with rings at `heights` (ascending) and a top cap (outward winding), coloured by
// height and angle; two close rings make a sharp colour edge (the waist).
template <typename ColourAt>
RenderMesh cylinder(double radius, const std::vector<double>& heights, int segments, ColourAt colour_at) {
  RenderMesh m;
  const int rings = static_cast<int>(heights.size()) - 1;
  const double z1 = heights.back();
  for (double z : heights) {
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      const Eigen::Vector3f n(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.f);
      m.vertices.emplace_back(static_cast<float>(radius) * n.x(), static_cast<float>(radius) * n.y(), static_cast<float>(z));
      m.colours.push_back(shaded(colour_at(z, a), n));
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  }
  // Top cap.
  const int centre = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0.f, 0.f, static_cast<float>(z1));
  m.colours.push_back(shaded(colour_at(z1, 0.0), Eigen::Vector3f::UnitZ()));
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({centre, rings * segments + s, rings * segments + (s + 1) % segments});
  }
  return m;
}

// An ellipsoid (outward winding) in the face frame, hair on the top and back, skin elsewhere.
RenderMesh head_ellipsoid(const Eigen::Vector3f& centre, const Eigen::Vector3f& radii, std::uint32_t skin, std::uint32_t hair) {
  RenderMesh m;
  const int lat = 10, lon = 18;
  for (int i = 0; i <= lat; ++i) {
    const double theta = std::numbers::pi * i / lat;  // from +y (top) to -y
    for (int j = 0; j < lon; ++j) {
      const double phi = 2 * std::numbers::pi * j / lon;
      const Eigen::Vector3f n(static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta)),
                              static_cast<float>(std::sin(theta) * std::cos(phi)));
      const Eigen::Vector3f p = centre + radii.cwiseProduct(n);
      m.vertices.push_back(p);
      const bool is_hair = n.y() > 0.35f || n.z() < -0.2f;
      m.colours.push_back(shaded(is_hair ? hair : skin, Eigen::Vector3f(n.x(), n.z(), n.y())));
    }
  }
  for (int i = 0; i < lat; ++i) {
    for (int j = 0; j < lon; ++j) {
      const int a = i * lon + j, b = i * lon + (j + 1) % lon, c = a + lon, d = b + lon;
      m.triangles.push_back({a, d, b});
      m.triangles.push_back({a, c, d});
    }
  }
  return m;
}

// Mean colour of the photograph under the face's vertices: the skin tone for the rest of the head.
std::uint32_t skin_tone(const RenderMesh& face) {
  long b = 0, g = 0, r = 0;
  for (const auto& uv : face.texture_px) {
    const std::uint32_t c = face.texture.sample(0, uv.x(), uv.y());
    b += texel_b(c);
    g += texel_g(c);
    r += texel_r(c);
  }
  const long n = std::max<long>(1, static_cast<long>(face.texture_px.size()));
  return pack_bgr(static_cast<int>(b / n), static_cast<int>(g / n), static_cast<int>(r / n));
}

}  // namespace

TeacherFigure::TeacherFigure(const TeacherSpec& spec, std::optional<TexturedHeadModel> head) {
  const std::uint32_t shirt = pack_bgr(150, 95, 55), trousers = pack_bgr(55, 50, 48);
  const double shoulder = spec.eye_height_m - kShoulderBelowEyes_m;
  std::vector<double> rings{0.0};
  for (double z : {0.5, kWaist_m - 0.01, kWaist_m + 0.01, 1.2}) {
    if (z < shoulder - 0.02) rings.push_back(z);
  }
  rings.push_back(shoulder);
  body_ = cylinder(spec.body_radius_m, rings, 20, [&](double z, double a) {
    if (z < kWaist_m) return trousers;
    // A darker stripe down the front shows which way the body faces.
    return std::abs(std::remainder(a, 2 * std::numbers::pi)) < 0.25 ? pack_bgr(90, 60, 40) : shirt;
  });
  std::uint32_t skin = pack_bgr(120, 150, 200);
  if (head) {
    validate(*head);
    RenderMesh face;
    for (const auto& v : head->vertices_face_m) face.vertices.push_back(v.cast<float>());
    face.triangles = head->triangles;
    face.texture_px = head->texture_px;
    face.texture = TextureMap(head->texture_bgr);
    face.textured = true;
    face.culling = RenderMesh::Culling::TextureSide;
    skin = skin_tone(face);
    face_ = std::move(face);
  }
  head_back_ = head_ellipsoid({0.f, 0.01f, -0.085f}, {0.078f, 0.115f, 0.1f}, skin, pack_bgr(35, 45, 60));
  head_back_.depth_bias_m = 0.08f;  // the face is drawn over it wherever both are seen
  // The neck hangs below the head, in the face frame: a cylinder along face -y.
  neck_ = cylinder(0.06, {0.05, 0.24}, 10, [&](double, double) { return skin; });
  Eigen::Matrix3f to_face;  // cylinder z -> face -y; cylinder x -> face x
  to_face << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  for (auto& v : neck_.vertices) v = to_face * v + Eigen::Vector3f(0.f, 0.f, -0.07f);
  neck_.depth_bias_m = 0.04f;
}

Eigen::Isometry3d TeacherFigure::body_pose(const SceneState& scene) {
  const Eigen::Vector3d forward = scene.T_world_head.linear().col(2);  // the face's +z
  const double yaw = std::atan2(forward.y(), forward.x());
  Eigen::Isometry3d T(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  T.translation() = Eigen::Vector3d(scene.teacher_floor_xy.x(), scene.teacher_floor_xy.y(), 0.0);
  return T;
}

void TeacherFigure::project(const SceneState& scene, const Eigen::Isometry3d& T_world_cam, const PinholeCamera& camera,
                            float max_radius, TeacherProjection& out) const {
  out.box = PixelBounds{};
  out.has_face = false;
  if (!scene.teacher_present) return;
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  const Eigen::Isometry3d T_cam_head = T_cam_world * scene.T_world_head;
  project_mesh(body_, T_cam_world * body_pose(scene), camera, max_radius, out.body, out.box);
  project_mesh(neck_, T_cam_head, camera, max_radius, out.neck, out.box);
  project_mesh(head_back_, T_cam_head, camera, max_radius, out.head_back, out.box);
  if (face_) {
    project_mesh(*face_, T_cam_head, camera, max_radius, out.face, out.box);
    out.has_face = true;
  }
  out.box.x0 = std::max(out.box.x0, 0);
  out.box.y0 = std::max(out.box.y0, 0);
  out.box.x1 = std::min(out.box.x1, camera.width());
  out.box.y1 = std::min(out.box.y1, camera.height());
}

void TeacherFigure::draw(const TeacherProjection& p, FrameTarget target) const {
  if (p.box.empty()) return;
  rasterize_mesh(body_, p.body, target);
  rasterize_mesh(neck_, p.neck, target);
  rasterize_mesh(head_back_, p.head_back, target);
  if (face_ && p.has_face) rasterize_mesh(*face_, p.face, target);
}

}  // namespace labo::sim
