#include "drone/sim/render_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace labo {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kNear = 1e-3;  // m: closer than this a rectangle is clipped
constexpr std::uint32_t kBackground = 0;

// Bounds of a quad's projection onto z = 1 after clipping it to z >= kNear; false when nothing is left.
bool projected_bounds(const Eigen::Vector3d (&corners)[4], float& min_x, float& max_x, float& min_y, float& max_y) {
  Eigen::Vector3d clipped[8];
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& a = corners[i];
    const Eigen::Vector3d& b = corners[(i + 1) % 4];
    const bool a_in = a.z() >= kNear, b_in = b.z() >= kNear;
    if (a_in) clipped[n++] = a;
    if (a_in != b_in) clipped[n++] = a + (b - a) * ((kNear - a.z()) / (b.z() - a.z()));
  }
  if (n == 0) return false;
  min_x = min_y = kInf;
  max_x = max_y = -kInf;
  for (int i = 0; i < n; ++i) {
    const float x = static_cast<float>(clipped[i].x() / clipped[i].z()), y = static_cast<float>(clipped[i].y() / clipped[i].z());
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
    min_y = std::min(min_y, y);
    max_y = std::max(max_y, y);
  }
  return true;
}

}  // namespace

SceneTracer::SceneTracer(const CameraRays& rays, const LabScene& scene) : rays_(rays), scene_(scene) {
  views_.reserve(scene.rects.size());
  const std::size_t tiles = rays.tiles().size();
  candidates_.resize(tiles * scene.rects.size());
  candidate_count_.resize(tiles);
  object_count_.resize(tiles);
  first_object_.resize(tiles);
  tile_depth_.resize(tiles);
  levels_.resize(scene.rects.size());
}

void SceneTracer::prepare_views(const Eigen::Isometry3d& T_world_cam) {
  views_.clear();
  const Eigen::Matrix3d R_cw = T_world_cam.linear().transpose();
  const Eigen::Vector3d c = T_world_cam.translation();
  const float r_max = rays_.max_radius();
  for (std::size_t i = 0; i < scene_.rects.size(); ++i) {
    const SceneRect& r = scene_.rects[i];
    const Eigen::Vector3d oc = c - r.origin;
    if (r.normal.dot(oc) <= 1e-9) continue;  // seen from behind
    const Eigen::Vector3d corners_w[4] = {r.origin, r.origin + r.size_u * r.axis_u,
                                          r.origin + r.size_u * r.axis_u + r.size_v * r.axis_v, r.origin + r.size_v * r.axis_v};
    Eigen::Vector3d corners_c[4];
    for (int k = 0; k < 4; ++k) corners_c[k] = R_cw * (corners_w[k] - c);
    View v{};
    if (!projected_bounds(corners_c, v.min_x, v.max_x, v.min_y, v.max_y)) continue;
    if (v.max_x < -r_max || v.min_x > r_max || v.max_y < -r_max || v.min_y > r_max) continue;
    const Eigen::Vector3d n = R_cw * r.normal, u = R_cw * r.axis_u, w = R_cw * r.axis_v;
    v.nx = static_cast<float>(n.x());
    v.ny = static_cast<float>(n.y());
    v.nz = static_cast<float>(n.z());
    v.ux = static_cast<float>(u.x());
    v.uy = static_cast<float>(u.y());
    v.uz = static_cast<float>(u.z());
    v.vx = static_cast<float>(w.x());
    v.vy = static_cast<float>(w.y());
    v.vz = static_cast<float>(w.z());
    v.num = static_cast<float>(-r.normal.dot(oc));
    v.a0 = static_cast<float>(r.axis_u.dot(oc));
    v.b0 = static_cast<float>(r.axis_v.dot(oc));
    v.size_u = static_cast<float>(r.size_u);
    v.size_v = static_cast<float>(r.size_v);
    v.tpu = static_cast<float>(r.texels_per_m_u);
    v.tpv = static_cast<float>(r.texels_per_m_v);
    v.rect = static_cast<int>(i);
    v.texture = r.texture;
    v.shell = r.room_shell;
    views_.push_back(v);
  }
}

void SceneTracer::bin_views() {
  const auto& tiles = rays_.tiles();
  const std::size_t stride = scene_.rects.size();
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const RenderTile& tile = tiles[t];
    std::uint16_t* out = candidates_.data() + t * stride;
    int n = 0, objects = 0, first = -1;
    for (std::size_t k = 0; k < views_.size(); ++k) {
      const View& v = views_[k];
      if (v.max_x < tile.min_x || v.min_x > tile.max_x || v.max_y < tile.min_y || v.min_y > tile.max_y) continue;
      out[n++] = static_cast<std::uint16_t>(k);
      if (!v.shell) {
        if (objects++ == 0) first = static_cast<int>(k);
      }
    }
    candidate_count_[t] = n;
    object_count_[t] = objects;
    first_object_[t] = first;
  }
}

// The candidate hit first along the ray (x, y, 1), -1 for none; t is the depth, (a, b) the point on it.
int SceneTracer::closest(const std::uint16_t* cand, int n, float x, float y, float& t, float& a, float& b) const {
  int best = -1;
  t = kInf;
  for (int k = 0; k < n; ++k) {
    const View& v = views_[cand[k]];
    const float nd = v.nx * x + v.ny * y + v.nz;
    if (!(nd < 0.f)) continue;
    const float tt = v.num / nd;
    if (!(tt < t)) continue;
    const float aa = v.a0 + tt * (v.ux * x + v.uy * y + v.uz);
    if (aa < 0.f || aa > v.size_u) continue;
    const float bb = v.b0 + tt * (v.vx * x + v.vy * y + v.vz);
    if (bb < 0.f || bb > v.size_v) continue;
    t = tt;
    a = aa;
    b = bb;
    best = cand[k];
  }
  return best;
}

// Mip level from how many texels the tile's corners span per pixel on the rectangle's plane.
int SceneTracer::level_for(const View& v, const RenderTile& tile) const {
  const TextureMap& tex = scene_.textures[static_cast<std::size_t>(v.texture)];
  float ta[4], tb[4];
  for (int i = 0; i < 4; ++i) {
    const float x = rays_.ray_x()[tile.corner[i]], y = rays_.ray_y()[tile.corner[i]];
    const float nd = v.nx * x + v.ny * y + v.nz;
    if (!(nd < 0.f)) return tex.level_count() - 1;  // the plane's horizon crosses the tile
    const float t = v.num / nd;
    ta[i] = (v.a0 + t * (v.ux * x + v.uy * y + v.uz)) * v.tpu;
    tb[i] = (v.b0 + t * (v.vx * x + v.vy * y + v.vz)) * v.tpv;
  }
  const float w = static_cast<float>(std::max(1, tile.x1 - tile.x0 - 1));
  const float h = static_cast<float>(std::max(1, tile.y1 - tile.y0 - 1));
  const float across = std::max(std::hypot(ta[1] - ta[0], tb[1] - tb[0]), std::hypot(ta[3] - ta[2], tb[3] - tb[2])) / w;
  const float down = std::max(std::hypot(ta[2] - ta[0], tb[2] - tb[0]), std::hypot(ta[3] - ta[1], tb[3] - tb[1])) / h;
  return tex.level_for_footprint(std::max(across, down));
}

void SceneTracer::trace_tile(int ti, bool want_depth, std::uint32_t* colour, float* depth) {
  const RenderTile& tile = rays_.tiles()[static_cast<std::size_t>(ti)];
  const int width = rays_.width();
  const float* rx = rays_.ray_x();
  const float* ry = rays_.ray_y();
  const int n = candidate_count_[static_cast<std::size_t>(ti)];
  const std::uint16_t* cand = candidates_.data() + static_cast<std::size_t>(ti) * scene_.rects.size();

  // Corner rays.
  int corner_hit[4];
  float depth_sum = 0;
  int depth_n = 0;
  for (int i = 0; i < 4; ++i) {
    float t, a, b;
    corner_hit[i] = closest(cand, n, rx[tile.corner[i]], ry[tile.corner[i]], t, a, b);
    if (corner_hit[i] >= 0) {
      depth_sum += t;
      ++depth_n;
    }
  }
  tile_depth_[static_cast<std::size_t>(ti)] = depth_n > 0 ? depth_sum / static_cast<float>(depth_n) : 0.f;

  const int s = corner_hit[0];
  const int objects = object_count_[static_cast<std::size_t>(ti)];
  const bool same = s >= 0 && corner_hit[1] == s && corner_hit[2] == s && corner_hit[3] == s;
  const bool uniform = same && (views_[static_cast<std::size_t>(s)].shell ? objects == 0
                                                                         : objects == 1 && first_object_[static_cast<std::size_t>(ti)] == s);
  if (n == 0) {
    ++stats_.empty_tiles;
    for (int py = tile.y0; py < tile.y1; ++py) {
      for (int px = tile.x0; px < tile.x1; ++px) {
        colour[py * width + px] = kBackground;
        if (want_depth) depth[py * width + px] = kInf;
      }
    }
    return;
  }
  if (uniform) {
    ++stats_.uniform_tiles;
    const View& v = views_[static_cast<std::size_t>(s)];
    const TextureMap& tex = scene_.textures[static_cast<std::size_t>(v.texture)];
    const int level = level_for(v, tile);
    for (int py = tile.y0; py < tile.y1; ++py) {
      const int row = py * width;
      for (int px = tile.x0; px < tile.x1; ++px) {
        const float x = rx[row + px], y = ry[row + px];
        const float t = v.num / (v.nx * x + v.ny * y + v.nz);
        const float a = v.a0 + t * (v.ux * x + v.uy * y + v.uz);
        const float b = v.b0 + t * (v.vx * x + v.vy * y + v.vz);
        colour[row + px] = tex.sample(level, a * v.tpu - 0.5f, b * v.tpv - 0.5f);
        if (want_depth) depth[row + px] = t;
      }
    }
    return;
  }
  ++stats_.mixed_tiles;
  for (int k = 0; k < n; ++k) levels_[static_cast<std::size_t>(k)] = level_for(views_[cand[k]], tile);
  for (int py = tile.y0; py < tile.y1; ++py) {
    const int row = py * width;
    for (int px = tile.x0; px < tile.x1; ++px) {
      const float x = rx[row + px], y = ry[row + px];
      int best = -1, best_k = -1;
      float best_t = kInf, best_a = 0, best_b = 0;
      for (int k = 0; k < n; ++k) {
        const View& v = views_[cand[k]];
        const float nd = v.nx * x + v.ny * y + v.nz;
        if (!(nd < 0.f)) continue;
        const float t = v.num / nd;
        if (!(t < best_t)) continue;
        const float a = v.a0 + t * (v.ux * x + v.uy * y + v.uz);
        if (a < 0.f || a > v.size_u) continue;
        const float b = v.b0 + t * (v.vx * x + v.vy * y + v.vz);
        if (b < 0.f || b > v.size_v) continue;
        best = cand[k];
        best_k = k;
        best_t = t;
        best_a = a;
        best_b = b;
      }
      if (best < 0) {
        colour[row + px] = kBackground;
      } else {
        const View& v = views_[static_cast<std::size_t>(best)];
        colour[row + px] = scene_.textures[static_cast<std::size_t>(v.texture)].sample(
            levels_[static_cast<std::size_t>(best_k)], best_a * v.tpu - 0.5f, best_b * v.tpv - 0.5f);
      }
      if (want_depth) depth[row + px] = best_t;
    }
  }
}

void SceneTracer::trace(const Eigen::Isometry3d& T_world_cam, int dx0, int dy0, int dx1, int dy1, std::uint32_t* colour,
                        float* depth) {
  stats_ = {};
  prepare_views(T_world_cam);
  bin_views();
  const auto& tiles = rays_.tiles();
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const RenderTile& tile = tiles[t];
    const bool want_depth = depth != nullptr && tile.x0 < dx1 && tile.x1 > dx0 && tile.y0 < dy1 && tile.y1 > dy0;
    trace_tile(static_cast<int>(t), want_depth, colour, depth);
  }
}

int SceneTracer::rect_at(const Eigen::Isometry3d& T_world_cam, int px, int py) {
  prepare_views(T_world_cam);
  std::vector<std::uint16_t> all(views_.size());
  for (std::size_t k = 0; k < views_.size(); ++k) all[k] = static_cast<std::uint16_t>(k);
  const std::size_t i = static_cast<std::size_t>(py) * static_cast<std::size_t>(rays_.width()) + static_cast<std::size_t>(px);
  float t, a, b;
  const int k = closest(all.data(), static_cast<int>(all.size()), rays_.ray_x()[i], rays_.ray_y()[i], t, a, b);
  return k < 0 ? -1 : views_[static_cast<std::size_t>(k)].rect;
}

}  // namespace labo
