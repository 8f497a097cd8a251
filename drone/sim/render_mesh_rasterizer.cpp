#include "drone/sim/render_mesh_rasterizer.hpp"

#include <algorithm>
#include <cmath>

namespace labo::sim {

namespace {

constexpr float kNear = 0.02f;  // m

inline float edge(const Eigen::Vector2f& a, const Eigen::Vector2f& b, float x, float y) {
  return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
}

struct TriangleSetup {
  Eigen::Vector2f p[3];
  float inv_z[3];
  float area;
  int x0, y0, x1, y1;
};

bool setup(const ProjectedMesh& pm, const std::array<int, 3>& tri, int width, int height, TriangleSetup& s) {
  for (int i = 0; i < 3; ++i) {
    const auto v = static_cast<std::size_t>(tri[static_cast<std::size_t>(i)]);
    if (!pm.valid[v]) return false;
    s.p[i] = pm.px[v];
    s.inv_z[i] = 1.f / pm.z[v];
  }
  s.area = edge(s.p[0], s.p[1], s.p[2].x(), s.p[2].y());
  if (std::abs(s.area) < 1e-6f) return false;
  const float min_x = std::min({s.p[0].x(), s.p[1].x(), s.p[2].x()}), max_x = std::max({s.p[0].x(), s.p[1].x(), s.p[2].x()});
  const float min_y = std::min({s.p[0].y(), s.p[1].y(), s.p[2].y()}), max_y = std::max({s.p[0].y(), s.p[1].y(), s.p[2].y()});
  s.x0 = std::max(0, static_cast<int>(std::ceil(min_x)));
  s.y0 = std::max(0, static_cast<int>(std::ceil(min_y)));
  s.x1 = std::min(width - 1, static_cast<int>(std::floor(max_x)));
  s.y1 = std::min(height - 1, static_cast<int>(std::floor(max_y)));
  return s.x0 <= s.x1 && s.y0 <= s.y1;
}

// Calls fn(pixel index, w0, w1, w2, z) for every pixel centre inside the triangle that is nearer than
// the depth buffer (which it updates to z + bias); w_i are the perspective-correct weights (sum 1/z).
template <typename Fn>
void for_each_fragment(const TriangleSetup& s, float bias, FrameTarget& target, Fn&& fn) {
  const float inv_area = 1.f / s.area;
  for (int y = s.y0; y <= s.y1; ++y) {
    const auto fy = static_cast<float>(y);
    for (int x = s.x0; x <= s.x1; ++x) {
      const auto fx = static_cast<float>(x);
      const float l0 = edge(s.p[1], s.p[2], fx, fy) * inv_area;
      const float l1 = edge(s.p[2], s.p[0], fx, fy) * inv_area;
      const float l2 = 1.f - l0 - l1;
      if (l0 < 0.f || l1 < 0.f || l2 < 0.f) continue;
      const float w0 = l0 * s.inv_z[0], w1 = l1 * s.inv_z[1], w2 = l2 * s.inv_z[2];
      const float z = 1.f / (w0 + w1 + w2);
      const int i = y * target.width + x;
      if (!(z + bias < target.depth[i])) continue;
      target.depth[i] = z + bias;
      fn(i, w0, w1, w2, z);
    }
  }
}

}  // namespace

void PixelBounds::include(float x, float y) {
  const int fx = static_cast<int>(std::floor(x)), fy = static_cast<int>(std::floor(y));
  if (empty()) {
    x0 = fx;
    y0 = fy;
    x1 = fx + 2;
    y1 = fy + 2;
    return;
  }
  x0 = std::min(x0, fx);
  y0 = std::min(y0, fy);
  x1 = std::max(x1, fx + 2);
  y1 = std::max(y1, fy + 2);
}

void project_mesh(const RenderMesh& mesh, const Eigen::Isometry3d& T_cam_mesh, const PinholeCamera& camera, float max_radius,
                  ProjectedMesh& out, PixelBounds& box) {
  const std::size_t n = mesh.vertices.size();
  out.px.resize(n);
  out.z.resize(n);
  out.valid.resize(n);
  out.front.resize(mesh.triangles.size());
  const Eigen::Matrix3f R = T_cam_mesh.linear().cast<float>();
  const Eigen::Vector3f t = T_cam_mesh.translation().cast<float>();
  const float limit = 1.3f * max_radius;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f p = R * mesh.vertices[i] + t;
    out.z[i] = p.z();
    out.valid[i] = 0;
    if (p.z() < kNear) continue;
    if (std::hypot(p.x() / p.z(), p.y() / p.z()) > limit) continue;
    const auto px = camera.project(p.cast<double>());
    if (!px) continue;
    out.px[i] = px->cast<float>();
    out.valid[i] = 1;
  }
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& tri = mesh.triangles[k];
    const auto a = static_cast<std::size_t>(tri[0]), b = static_cast<std::size_t>(tri[1]), c = static_cast<std::size_t>(tri[2]);
    out.front[k] = 0;
    if (!out.valid[a] || !out.valid[b] || !out.valid[c]) continue;
    if (mesh.culling == RenderMesh::Culling::Outward) {
      // Facing the camera when the outward normal points back at the optical centre.
      const Eigen::Vector3f pa = R * mesh.vertices[a] + t, pb = R * mesh.vertices[b] + t, pc = R * mesh.vertices[c] + t;
      if ((pb - pa).cross(pc - pa).dot(pa) >= 0.f) continue;
    } else {
      const Eigen::Vector2f e1 = out.px[b] - out.px[a], e2 = out.px[c] - out.px[a];
      const Eigen::Vector2f s1 = mesh.texture_px[b] - mesh.texture_px[a], s2 = mesh.texture_px[c] - mesh.texture_px[a];
      const float image_area = e1.x() * e2.y() - e1.y() * e2.x();
      const float texture_area = s1.x() * s2.y() - s1.y() * s2.x();
      if (!(image_area * texture_area > 0.f)) continue;
    }
    out.front[k] = 1;
    for (std::size_t v : {a, b, c}) box.include(out.px[v].x(), out.px[v].y());
  }
}

void rasterize_mesh(const RenderMesh& mesh, const ProjectedMesh& pm, FrameTarget target) {
  const float bias = mesh.depth_bias_m;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    if (!pm.front[k]) continue;
    const auto& tri = mesh.triangles[k];
    TriangleSetup s;
    if (!setup(pm, tri, target.width, target.height, s)) continue;
    const auto a = static_cast<std::size_t>(tri[0]), b = static_cast<std::size_t>(tri[1]), c = static_cast<std::size_t>(tri[2]);
    if (mesh.textured) {
      const Eigen::Vector2f uv[3] = {mesh.texture_px[a], mesh.texture_px[b], mesh.texture_px[c]};
      const Eigen::Vector2f s1 = uv[1] - uv[0], s2 = uv[2] - uv[0];
      const float texture_area = std::abs(s1.x() * s2.y() - s1.y() * s2.x());
      const int level = mesh.texture.level_for_footprint(std::sqrt(texture_area / std::abs(s.area)));
      for_each_fragment(s, bias, target, [&](int i, float w0, float w1, float w2, float z) {
        const float u = (w0 * uv[0].x() + w1 * uv[1].x() + w2 * uv[2].x()) * z;
        const float v = (w0 * uv[0].y() + w1 * uv[1].y() + w2 * uv[2].y()) * z;
        target.colour[i] = mesh.texture.sample(level, u, v);
      });
    } else {
      const std::uint32_t col[3] = {mesh.colours[a], mesh.colours[b], mesh.colours[c]};
      for_each_fragment(s, bias, target, [&](int i, float, float w1, float w2, float z) {
        // Gouraud colours: affine weights are enough for a colour gradient.
        const std::uint32_t q1 = static_cast<std::uint32_t>(w1 * z * 256.f), q2 = static_cast<std::uint32_t>(w2 * z * 256.f);
        const std::uint32_t q0 = 256 - std::min(256u, q1 + q2);
        target.colour[i] = blend4(col[0], col[1], col[2], 0, q0, q1, q2, 0);
      });
    }
  }
}

}  // namespace labo::sim
