#include "drone/sim/render_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "drone/sim/render_vector_clones.hpp"

namespace labo::sim {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kNear = 1e-3;  // m: closer than this a rectangle is clipped
constexpr std::uint32_t kBackground = 0;
constexpr int kAreaMinLevel = 2;  // area filtering from this mip level's footprint on (> 3 texels per pixel)

// Clips a convex polygon to the half-space d(p) >= 0 (Sutherland-Hodgman); returns the new count.
template <typename Distance>
int clip(const Eigen::Vector3d* in, int n, Eigen::Vector3d* out, Distance d) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = in[i];
    const Eigen::Vector3d& b = in[(i + 1) % n];
    const double da = d(a), db = d(b);
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}

// Bounds of a quad's projection onto z = 1 after clipping it to the camera's field (its rays' extent
// and z >= kNear); false when nothing is left. Clipping to the field, not only to the near plane,
// keeps a face that passes beside the camera from claiming the whole image.
bool projected_bounds(const Eigen::Vector3d (&corners)[4], const CameraRays& rays, float& min_x, float& max_x, float& min_y,
                      float& max_y) {
  Eigen::Vector3d a[12], b[12];
  const double x0 = rays.min_x(), x1 = rays.max_x(), y0 = rays.min_y(), y1 = rays.max_y();
  int n = clip(corners, 4, a, [](const Eigen::Vector3d& p) { return p.z() - kNear; });
  n = clip(a, n, b, [x0](const Eigen::Vector3d& p) { return p.x() - x0 * p.z(); });
  n = clip(b, n, a, [x1](const Eigen::Vector3d& p) { return x1 * p.z() - p.x(); });
  n = clip(a, n, b, [y0](const Eigen::Vector3d& p) { return p.y() - y0 * p.z(); });
  n = clip(b, n, a, [y1](const Eigen::Vector3d& p) { return y1 * p.z() - p.y(); });
  if (n == 0) return false;
  min_x = min_y = kInf;
  max_x = max_y = -kInf;
  for (int i = 0; i < n; ++i) {
    const float x = static_cast<float>(a[i].x() / a[i].z()), y = static_cast<float>(a[i].y() / a[i].z());
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
  maps_.resize(scene.rects.size());
}

void SceneTracer::prepare_views(const Eigen::Isometry3d& T_world_cam) {
  views_.clear();
  const Eigen::Matrix3d R_cw = T_world_cam.linear().transpose();
  const Eigen::Vector3d c = T_world_cam.translation();
  for (std::size_t i = 0; i < scene_.rects.size(); ++i) {
    const SceneRect& r = scene_.rects[i];
    const Eigen::Vector3d oc = c - r.origin;
    if (r.normal.dot(oc) <= 1e-9) continue;  // seen from behind
    const Eigen::Vector3d corners_w[4] = {r.origin, r.origin + r.size_u * r.axis_u,
                                          r.origin + r.size_u * r.axis_u + r.size_v * r.axis_v, r.origin + r.size_v * r.axis_v};
    Eigen::Vector3d corners_c[4];
    for (int k = 0; k < 4; ++k) corners_c[k] = R_cw * (corners_w[k] - c);
    View v{};
    if (!projected_bounds(corners_c, rays_, v.min_x, v.max_x, v.min_y, v.max_y)) continue;
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
SceneTracer::LevelMap SceneTracer::level_for(const View& v, int ti) const {
  constexpr int kPoints = CameraRays::kSpanPoints;
  const RenderTile& tile = rays_.tiles()[static_cast<std::size_t>(ti)];
  const float* spans = rays_.span_rays(ti);
  const int last_row = (tile.y1 - tile.y0 - 1) * kPoints;
  const int corner[4] = {0, kPoints - 1, last_row, last_row + kPoints - 1};
  const TextureMap& tex = scene_.textures[static_cast<std::size_t>(v.texture)];
  int level = tex.level_count() - 1;  // when the plane's horizon crosses the tile
  float ta[4], tb[4];
  float half_u = 0, half_v = 0;
  bool below_horizon = true;
  for (int i = 0; i < 4; ++i) {
    const float x = spans[2 * corner[i]], y = spans[2 * corner[i] + 1];
    const float nd = v.nx * x + v.ny * y + v.nz;
    if (!(nd < 0.f)) {
      below_horizon = false;
      break;
    }
    const float t = v.num / nd;
    ta[i] = (v.a0 + t * (v.ux * x + v.uy * y + v.uz)) * v.tpu;
    tb[i] = (v.b0 + t * (v.vx * x + v.vy * y + v.vz)) * v.tpv;
  }
  if (below_horizon) {
    const float w = static_cast<float>(std::max(1, tile.x1 - tile.x0 - 1));
    const float h = static_cast<float>(std::max(1, tile.y1 - tile.y0 - 1));
    const float across = std::max(std::hypot(ta[1] - ta[0], tb[1] - tb[0]), std::hypot(ta[3] - ta[2], tb[3] - tb[2])) / w;
    const float down = std::max(std::hypot(ta[2] - ta[0], tb[2] - tb[0]), std::hypot(ta[3] - ta[1], tb[3] - tb[1])) / h;
    level = tex.level_for_footprint(std::max(across, down));
    // The pixel square's extent along the texture's axes (level-0 texels): the box with its second
    // moments, for area filtering.
    const float du_dx = 0.5f * ((ta[1] - ta[0]) + (ta[3] - ta[2])) / w, du_dy = 0.5f * ((ta[2] - ta[0]) + (ta[3] - ta[1])) / h;
    const float dv_dx = 0.5f * ((tb[1] - tb[0]) + (tb[3] - tb[2])) / w, dv_dy = 0.5f * ((tb[2] - tb[0]) + (tb[3] - tb[1])) / h;
    half_u = 0.5f * std::hypot(du_dx, du_dy);
    half_v = 0.5f * std::hypot(dv_dx, dv_dy);
  }
  // Minified more than 3 texels per pixel (mip level 2 and up): a panel's pixels average their
  // footprint. Nearer, the mip level's bilinear sample stays: its blur (the level's texel box and the
  // bilinear tent, 0.75-1.5 level texels per pixel) is close to the pixel's box there, and area
  // filtering every pixel of a panel that fills the frame would cost too much (docs/sim_rendering.md).
  if (level >= kAreaMinLevel && tex.has_area_table() && half_u > 0 && half_v > 0) {
    const TextureMap::Level& l0 = tex.level(0);
    return {&l0, v.tpu, v.tpv, &tex, static_cast<std::int32_t>(half_u * 256.f + 0.5f), static_cast<std::int32_t>(half_v * 256.f + 0.5f)};
  }
  const TextureMap::Level& l = tex.level(level);
  return {&l, v.tpu * l.scale_x, v.tpv * l.scale_y};
}

namespace {

// Bilinear samples at n <= kMax points (u[i], w[i]) of a level (16.16 fixed point, inside its border):
// addresses and weights, then the loads, then the blend, each a loop the compiler vectorizes (fully
// unrolled for a whole tile row).
template <int kMax>
inline void sample_points(const TextureMap::Level& level, const std::int32_t* u, const std::int32_t* w, int n,
                          std::uint32_t* out) {
  alignas(32) std::int32_t index[kMax];
  alignas(32) std::uint32_t fx[kMax], fy[kMax], p00[kMax], p01[kMax], p10[kMax], p11[kMax];
  const int stride = level.stride;
  for (int i = 0; i < n; ++i) {
    index[i] = (w[i] >> 16) * stride + (u[i] >> 16);
    fx[i] = static_cast<std::uint32_t>(u[i] >> 8) & 0xFFu;
    fy[i] = static_cast<std::uint32_t>(w[i] >> 8) & 0xFFu;
  }
  const std::uint32_t* base = level.origin();
  for (int i = 0; i < n; ++i) {
    const std::uint32_t* p = base + index[i];
    p00[i] = p[0];
    p01[i] = p[1];
    p10[i] = p[stride];
    p11[i] = p[stride + 1];
  }
  for (int i = 0; i < n; ++i) {
    const std::uint32_t w11 = (fx[i] * fy[i]) >> 8, w01 = fx[i] - w11, w10 = fy[i] - w11, w00 = 256 - w01 - w10 - w11;
    out[i] = blend4(p00[i], p01[i], p10[i], p11[i], w00, w01, w10, w11);
  }
}

// Area-filtered samples: level-0 texel coordinates (16.16, texel centres at integers) to the mean of
// the box of half-sizes (half_u, half_v) about them (1/256 texels, edges at multiples of 256).
void area_points(const TextureMap& tex, std::int32_t half_u, std::int32_t half_v, const std::int32_t* u,
                 const std::int32_t* w, int n, std::uint32_t* out) {
  for (int i = 0; i < n; ++i) {
    const std::int32_t x = (u[i] + 32768) >> 8, y = (w[i] + 32768) >> 8;
    out[i] = tex.box_mean(x - half_u, y - half_v, x + half_u, y + half_v);
  }
}

}  // namespace

// A tile covered by one rectangle. Texel coordinates are exact at the span points of each row
// (CameraRays::kSpanPoints) and interpolated linearly in between (16.16 fixed point): over 8 pixels
// the perspective and the lens bend them by far less than a texel.
LABO_VECTOR_CLONES void SceneTracer::fill_uniform(int ti, const View& v, const LevelMap& m, bool want_depth,
                                                  std::uint32_t* colour, float* depth) const {
  constexpr int kPoints = CameraRays::kSpanPoints;
  const RenderTile& tile = rays_.tiles()[static_cast<std::size_t>(ti)];
  const int width = rays_.width();
  const TextureMap::Level& level = *m.level;
  const float* spans = rays_.span_rays(ti);
  int px[kPoints];
  for (int j = 0; j < kPoints; ++j) px[j] = CameraRays::span_x(tile, j);
  for (int py = tile.y0; py < tile.y1; ++py) {
    const int row = py * width;
    const float* r = spans + (py - tile.y0) * kPoints * 2;
    std::int32_t u[kPoints], w[kPoints];
    for (int j = 0; j < kPoints; ++j) {
      const float x = r[2 * j], y = r[2 * j + 1];
      const float t = v.num / (v.nx * x + v.ny * y + v.nz);
      u[j] = TextureMap::to_fixed((v.a0 + t * (v.ux * x + v.uy * y + v.uz)) * m.ku - 0.5f, level.width);
      w[j] = TextureMap::to_fixed((v.b0 + t * (v.vx * x + v.vy * y + v.vz)) * m.kv - 0.5f, level.height);
    }
    // The row's texel coordinates: linear between consecutive span points.
    constexpr int kRow = CameraRays::kTile;
    alignas(32) std::int32_t us[kRow], ws[kRow];
    const int count = tile.x1 - tile.x0;
    for (int j = 0; j + 1 < kPoints; ++j) {
      const int n = px[j + 1] - px[j];
      if (n <= 0) continue;
      const std::int32_t du = (u[j + 1] - u[j]) / n, dw = (w[j + 1] - w[j]) / n;
      for (int i = 0; i < n; ++i) {
        us[px[j] - tile.x0 + i] = u[j] + i * du;
        ws[px[j] - tile.x0 + i] = w[j] + i * dw;
      }
    }
    us[count - 1] = u[kPoints - 1];
    ws[count - 1] = w[kPoints - 1];
    if (m.area != nullptr) {
      area_points(*m.area, m.half_u, m.half_v, us, ws, count, colour + row + tile.x0);
    } else if (count == kRow) {
      sample_points<kRow>(level, us, ws, kRow, colour + row + tile.x0);
    } else {
      sample_points<kRow>(level, us, ws, count, colour + row + tile.x0);
    }
    if (want_depth) {
      const float* rx = rays_.ray_x() + row;
      const float* ry = rays_.ray_y() + row;
      for (int x = tile.x0; x < tile.x1; ++x) depth[row + x] = v.num / (v.nx * rx[x] + v.ny * ry[x] + v.nz);
    }
  }
}

// A tile with several candidates: each row is tested against one candidate at a time over all its
// pixels (branch-free, so the compiler vectorizes it), keeping the nearest hit; then shaded.
LABO_VECTOR_CLONES void SceneTracer::fill_mixed(int ti, const std::uint16_t* cand, int n, bool want_depth,
                             std::uint32_t* colour, float* depth) {
  constexpr int kRow = CameraRays::kTile;
  const RenderTile& tile = rays_.tiles()[static_cast<std::size_t>(ti)];
  const int width = rays_.width();
  const int count = tile.x1 - tile.x0;
  for (int k = 0; k < n; ++k) maps_[static_cast<std::size_t>(k)] = level_for(views_[cand[k]], ti);
  alignas(32) float best_t[kRow], best_a[kRow], best_b[kRow];
  alignas(32) int best_k[kRow];
  for (int py = tile.y0; py < tile.y1; ++py) {
    const int row = py * width + tile.x0;
    const float* rx = rays_.ray_x() + row;
    const float* ry = rays_.ray_y() + row;
    for (int i = 0; i < count; ++i) {
      best_t[i] = kInf;
      best_a[i] = best_b[i] = 0.f;
      best_k[i] = -1;
    }
    for (int k = 0; k < n; ++k) {
      const View& v = views_[cand[k]];
      const float nx = v.nx, ny = v.ny, nz = v.nz, ux = v.ux, uy = v.uy, uz = v.uz, vx = v.vx, vy = v.vy, vz = v.vz;
      const float num = v.num, a0 = v.a0, b0 = v.b0, su = v.size_u, sv = v.size_v;
      for (int i = 0; i < count; ++i) {
        const float x = rx[i], y = ry[i];
        const float nd = nx * x + ny * y + nz;
        const float t = num / nd;
        const float a = a0 + t * (ux * x + uy * y + uz);
        const float b = b0 + t * (vx * x + vy * y + vz);
        const bool hit = (nd < 0.f) & (t < best_t[i]) & (a >= 0.f) & (a <= su) & (b >= 0.f) & (b <= sv);
        best_t[i] = hit ? t : best_t[i];
        best_a[i] = hit ? a : best_a[i];
        best_b[i] = hit ? b : best_b[i];
        best_k[i] = hit ? k : best_k[i];
      }
    }
    for (int i = 0; i < count; ++i) {
      const int k = best_k[i];
      if (k < 0) {
        colour[row + i] = kBackground;
        continue;
      }
      const LevelMap& m = maps_[static_cast<std::size_t>(k)];
      if (m.area != nullptr) {
        const std::int32_t u = TextureMap::to_fixed(best_a[i] * m.ku - 0.5f, m.level->width);
        const std::int32_t w = TextureMap::to_fixed(best_b[i] * m.kv - 0.5f, m.level->height);
        area_points(*m.area, m.half_u, m.half_v, &u, &w, 1, colour + row + i);
        continue;
      }
      colour[row + i] = TextureMap::sample_fixed(*m.level, TextureMap::to_fixed(best_a[i] * m.ku - 0.5f, m.level->width),
                                                 TextureMap::to_fixed(best_b[i] * m.kv - 0.5f, m.level->height));
    }
    if (want_depth) std::copy(best_t, best_t + count, depth + row);
  }
}

void SceneTracer::trace_tile(int ti, bool want_depth, std::uint32_t* colour, float* depth) {
  const RenderTile& tile = rays_.tiles()[static_cast<std::size_t>(ti)];
  const int width = rays_.width();
  const int n = candidate_count_[static_cast<std::size_t>(ti)];
  const std::uint16_t* cand = candidates_.data() + static_cast<std::size_t>(ti) * scene_.rects.size();

  // Corner rays (from the tile's span rays, contiguous in memory).
  constexpr int kPoints = CameraRays::kSpanPoints;
  const float* spans = rays_.span_rays(ti);
  const int last_row = (tile.y1 - tile.y0 - 1) * kPoints;
  const float* corners[4] = {spans, spans + 2 * (kPoints - 1), spans + 2 * last_row, spans + 2 * (last_row + kPoints - 1)};
  static_assert(kPoints == 3);
  int corner_hit[4];
  float depth_sum = 0;
  int depth_n = 0;
  for (int i = 0; i < 4; ++i) {
    float t, a, b;
    corner_hit[i] = closest(cand, n, corners[i][0], corners[i][1], t, a, b);
    if (corner_hit[i] >= 0) {
      depth_sum += t;
      ++depth_n;
    }
  }
  tile_depth_[static_cast<std::size_t>(ti)] = depth_n > 0 ? depth_sum / static_cast<float>(depth_n) : 0.f;

  if (n == 0) {
    ++stats_.empty_tiles;
    for (int py = tile.y0; py < tile.y1; ++py) {
      std::fill(colour + py * width + tile.x0, colour + py * width + tile.x1, kBackground);
      if (want_depth) std::fill(depth + py * width + tile.x0, depth + py * width + tile.x1, kInf);
    }
    return;
  }
  const int s = corner_hit[0];
  const int objects = object_count_[static_cast<std::size_t>(ti)];
  const bool same = s >= 0 && corner_hit[1] == s && corner_hit[2] == s && corner_hit[3] == s;
  const bool uniform = same && (views_[static_cast<std::size_t>(s)].shell ? objects == 0
                                                                         : objects == 1 && first_object_[static_cast<std::size_t>(ti)] == s);
  if (uniform) {
    ++stats_.uniform_tiles;
    const View& v = views_[static_cast<std::size_t>(s)];
    fill_uniform(ti, v, level_for(v, ti), want_depth, colour, depth);
  } else {
    ++stats_.mixed_tiles;
    fill_mixed(ti, cand, n, want_depth, colour, depth);
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

}  // namespace labo::sim
