#include "drone/sim/flat_scene_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "core/frames.hpp"

namespace labo {

namespace {

constexpr double kNear_m = 0.02;
constexpr int kShift = 4;  // sub-pixel bits of the polygon fill
constexpr double kSubpixel = 1 << kShift;
constexpr int kMaxTextureLevels = 5;

double shading(const Eigen::Vector3d& normal) {
  static const Eigen::Vector3d light = Eigen::Vector3d(0.3, 0.2, 1.0).normalized();
  return 0.6 + 0.4 * std::abs(normal.dot(light));
}

cv::Scalar bgr(int b, int g, int r) { return cv::Scalar(b, g, r); }

// The four corners of a box face, counter-clockwise seen from outside; the box spans lo..hi in the
// frame T (world from box).
std::array<Eigen::Vector3d, 4> box_face(const Eigen::Isometry3d& T, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                        int axis, bool positive) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  std::array<Eigen::Vector3d, 4> c;
  const double fixed = positive ? hi[axis] : lo[axis];
  const double us[4] = {lo[a], hi[a], hi[a], lo[a]}, vs[4] = {lo[b], lo[b], hi[b], hi[b]};
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d p;
    p[axis] = fixed;
    p[a] = us[i];
    p[b] = vs[i];
    c[static_cast<std::size_t>(i)] = T * p;
  }
  return c;
}

bool in_area(const BareArea& area, double u, double v, double margin = 0.0) {
  return u >= area.min.x() - margin && u <= area.max.x() + margin && v >= area.min.y() - margin &&
         v <= area.max.y() + margin;
}

}  // namespace

FlatSceneRenderer::FlatSceneRenderer(const LabDescription& lab, const CamerasConfig& cameras) : lab_(lab) {
  teacher_eye_height_m_ = lab.teacher.eye_height_m;
  teacher_body_radius_m_ = lab.teacher.body_radius_m;
  build_room(lab);
  build_objects(lab);
  build_view(views_[0], cameras.front, T_body_cam_front());
  build_view(views_[1], cameras.bottom, T_body_cam_bottom());
}

// ---- scene construction ------------------------------------------------------------------------

void FlatSceneRenderer::build_room(const LabDescription& lab) {
  const Box3& r = lab.room;
  std::mt19937 rng(lab.texture_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto random_colour = [&] {
    return bgr(static_cast<int>(40 + 200 * unit(rng)), static_cast<int>(40 + 200 * unit(rng)),
               static_cast<int>(40 + 200 * unit(rng)));
  };
  auto floor_bare = [&](double x, double y, double margin) {
    for (const auto& a : lab.bare_areas)
      if (a.surface == "floor" && in_area(a, x, y, margin)) return true;
    return false;
  };
  auto floor_quad = [&](double x0, double y0, double x1, double y1, cv::Scalar colour) {
    room_.push_back({{Eigen::Vector3d(x0, y0, r.min.z()), Eigen::Vector3d(x1, y0, r.min.z()),
                      Eigen::Vector3d(x1, y1, r.min.z()), Eigen::Vector3d(x0, y1, r.min.z())},
                     Eigen::Vector3d::Zero(), colour * shading(Eigen::Vector3d::UnitZ())});
  };
  // Floor: 0.5 m tiles, scattered marks (corners for SLAM and texture for the bottom camera's flow),
  // bare areas plain on top.
  const double tile = 0.5;
  for (double x = r.min.x(); x < r.max.x() - 1e-9; x += tile) {
    for (double y = r.min.y(); y < r.max.y() - 1e-9; y += tile) {
      const bool dark = (static_cast<int>(std::floor((x - r.min.x()) / tile)) + static_cast<int>(std::floor((y - r.min.y()) / tile))) % 2;
      floor_quad(x, y, std::min(x + tile, r.max.x()), std::min(y + tile, r.max.y()), dark ? bgr(118, 124, 130) : bgr(150, 155, 158));
    }
  }
  for (int i = 0; i < 600; ++i) {
    const double s = 0.04 + 0.12 * unit(rng);
    const double x = r.min.x() + s + (r.size().x() - 2 * s) * unit(rng), y = r.min.y() + s + (r.size().y() - 2 * s) * unit(rng);
    const cv::Scalar colour = random_colour();
    if (!floor_bare(x, y, s)) floor_quad(x - 0.5 * s, y - 0.3 * s, x + 0.5 * s, y + 0.3 * s, colour);
  }
  for (const auto& a : lab.bare_areas)
    if (a.surface == "floor") floor_quad(a.min.x(), a.min.y(), a.max.x(), a.max.y(), bgr(138, 140, 142));

  // Walls, each with posters outside its bare areas. A wall point is (along, z): along is y for the
  // x walls, x for the y walls.
  struct Wall {
    const char* name;
    int along_axis;  // 0: x, 1: y
    double fixed;    // the wall's coordinate on the other horizontal axis
    Eigen::Vector3d inward;
    cv::Scalar colour;
  };
  const Wall walls[4] = {{"wall_xmin", 1, r.min.x(), Eigen::Vector3d::UnitX(), bgr(170, 190, 205)},
                         {"wall_xmax", 1, r.max.x(), -Eigen::Vector3d::UnitX(), bgr(185, 185, 170)},
                         {"wall_ymin", 0, r.min.y(), Eigen::Vector3d::UnitY(), bgr(165, 180, 190)},
                         {"wall_ymax", 0, r.max.y(), -Eigen::Vector3d::UnitY(), bgr(190, 175, 175)}};
  for (const Wall& w : walls) {
    auto point = [&](double along, double z) {
      return w.along_axis == 1 ? Eigen::Vector3d(w.fixed, along, z) : Eigen::Vector3d(along, w.fixed, z);
    };
    auto wall_quad = [&](double a0, double z0, double a1, double z1, cv::Scalar colour) {
      room_.push_back({{point(a0, z1), point(a1, z1), point(a1, z0), point(a0, z0)}, Eigen::Vector3d::Zero(),
                       colour * shading(w.inward)});
    };
    const double lo = w.along_axis == 1 ? r.min.y() : r.min.x(), hi = w.along_axis == 1 ? r.max.y() : r.max.x();
    wall_quad(lo, r.min.z(), hi, r.max.z(), w.colour);
    const int posters = static_cast<int>(3 * (hi - lo));
    for (int i = 0; i < posters; ++i) {
      const double pw = 0.2 + 0.6 * unit(rng), ph = 0.2 + 0.6 * unit(rng);
      const double a = lo + pw + (hi - lo - 2 * pw) * unit(rng), z = 0.3 + ph + (r.size().z() - 0.6 - 2 * ph) * unit(rng);
      const cv::Scalar colour = random_colour();
      bool bare = false;
      for (const auto& area : lab.bare_areas) bare = bare || (area.surface == w.name && in_area(area, a, z, std::max(pw, ph)));
      if (!bare) wall_quad(a - 0.5 * pw, z - 0.5 * ph, a + 0.5 * pw, z + 0.5 * ph, colour);
    }
  }
  // Ceiling with light panels.
  auto ceiling_quad = [&](double x0, double y0, double x1, double y1, cv::Scalar colour) {
    room_.push_back({{Eigen::Vector3d(x0, y0, r.max.z()), Eigen::Vector3d(x0, y1, r.max.z()),
                      Eigen::Vector3d(x1, y1, r.max.z()), Eigen::Vector3d(x1, y0, r.max.z())},
                     Eigen::Vector3d::Zero(), colour});
  };
  ceiling_quad(r.min.x(), r.min.y(), r.max.x(), r.max.y(), bgr(200, 200, 200));
  for (double x = r.min.x() + 1.0; x < r.max.x() - 0.8; x += 2.0)
    for (double y = r.min.y() + 1.0; y < r.max.y() - 0.8; y += 2.0) ceiling_quad(x, y, x + 1.2, y + 0.3, bgr(250, 250, 250));
}

void FlatSceneRenderer::build_objects(const LabDescription& lab) {
  auto add_box = [](Solid& solid, const Eigen::Isometry3d& T, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                    cv::Scalar colour, bool skip_front) {
    for (int axis = 0; axis < 3; ++axis) {
      for (bool positive : {false, true}) {
        if (skip_front && axis == 2 && !positive) continue;  // the planar object's textured face
        Eigen::Vector3d n = Eigen::Vector3d::Zero();
        n[axis] = positive ? 1.0 : -1.0;
        n = T.linear() * n;
        solid.faces.push_back({box_face(T, lo, hi, axis, positive), n, colour * shading(n)});
      }
    }
  };
  for (const auto& b : lab.benches) {
    Solid s;
    s.layer = 0;
    s.centre = b.box.centre();
    add_box(s, Eigen::Isometry3d::Identity(), b.box.min, b.box.max, bgr(70, 115, 160), false);
    solids_.push_back(std::move(s));
  }
  auto add_planar = [&](const InstrumentSpec& spec, int layer, cv::Scalar housing) {
    cv::Mat image = cv::imread(spec.template_path.string(), cv::IMREAD_COLOR);
    if (image.empty()) throw std::runtime_error("cannot read the template " + spec.template_path.string());
    Texture t;
    t.width_m = spec.width_m;
    t.height_m = spec.height_m;
    t.levels.push_back(image);
    while (static_cast<int>(t.levels.size()) < kMaxTextureLevels && t.levels.back().cols > 32 && t.levels.back().rows > 32) {
      cv::Mat down;
      cv::pyrDown(t.levels.back(), down);
      t.levels.push_back(down);
    }
    textures_.push_back(std::move(t));
    Solid s;
    s.layer = layer;
    s.centre = spec.bounds().centre();
    const Eigen::Vector3d lo(-0.5 * spec.width_m, -0.5 * spec.height_m, 0.0), hi(0.5 * spec.width_m, 0.5 * spec.height_m, spec.depth_m);
    add_box(s, spec.T_world_object, lo, hi, housing, true);
    const auto c = spec.corners_world();
    s.faces.push_back({{c[0], c[1], c[2], c[3]}, -spec.T_world_object.linear().col(2), cv::Scalar(), static_cast<int>(textures_.size()) - 1});
    solids_.push_back(std::move(s));
  };
  add_planar(lab.platform, 1, bgr(45, 45, 50));
  for (const auto& i : lab.instruments) add_planar(i, 2, bgr(75, 75, 80));
  fixed_solids_ = solids_.size();
  // The teacher: a body and a head, rebuilt in place per frame.
  for (int i = 0; i < 2; ++i) {
    Solid s;
    s.layer = 3;
    add_box(s, Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cv::Scalar(), false);
    solids_.push_back(std::move(s));
  }
}

void FlatSceneRenderer::build_view(View& view, const CameraIntrinsics& k, const Eigen::Isometry3d& T_body_cam) {
  view.camera = PinholeCamera(k);
  view.T_body_cam = T_body_cam;
  view.distorted = view.camera.has_distortion();
  // The undistorted extent the lens sees: the undistorted image border.
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  auto extend = [&](double u, double v) {
    const Eigen::Vector2d n = view.camera.undistort({(u - k.cx) / k.fx, (v - k.cy) / k.fy});
    x0 = std::min(x0, n.x()), x1 = std::max(x1, n.x()), y0 = std::min(y0, n.y()), y1 = std::max(y1, n.y());
  };
  for (int u = 0; u <= k.width; u += 4) extend(u - 0.5, -0.5), extend(u - 0.5, k.height - 0.5);
  for (int v = 0; v <= k.height; v += 4) extend(-0.5, v - 0.5), extend(k.width - 0.5, v - 0.5);
  const double margin_x = 2.0 / k.fx, margin_y = 2.0 / k.fy;
  view.frustum = Eigen::Vector4d(x0 - margin_x, x1 + margin_x, y0 - margin_y, y1 + margin_y);
  if (!view.distorted) {
    view.K_canvas = cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    view.canvas_size = cv::Size(k.width, k.height);
  } else {
    const double ox = -view.frustum[0] * k.fx, oy = -view.frustum[2] * k.fy;
    view.K_canvas = cv::Matx33d(k.fx, 0, ox, 0, k.fy, oy, 0, 0, 1);
    view.canvas_size = cv::Size(static_cast<int>(std::ceil(ox + view.frustum[1] * k.fx)) + 1,
                                static_cast<int>(std::ceil(oy + view.frustum[3] * k.fy)) + 1);
    cv::Mat map_x(k.height, k.width, CV_32FC1), map_y(k.height, k.width, CV_32FC1);
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const Eigen::Vector2d n = view.camera.undistort({(u - k.cx) / k.fx, (v - k.cy) / k.fy});
        map_x.at<float>(v, u) = static_cast<float>(k.fx * n.x() + ox);
        map_y.at<float>(v, u) = static_cast<float>(k.fy * n.y() + oy);
      }
    }
    cv::convertMaps(map_x, map_y, view.map1, view.map2, CV_16SC2);
  }
  view.canvas.create(view.canvas_size, CV_8UC3);
  view.warp.create(view.canvas_size, CV_8UC3);
  view.mask.create(view.canvas_size, CV_8UC1);
}

// ---- per frame ---------------------------------------------------------------------------------

void FlatSceneRenderer::add_teacher(const SceneState& scene) {
  if (!scene.teacher_present) return;
  const Eigen::Matrix3d R_head = scene.T_world_head.linear();
  // The body turns with the head's heading (the face frame's +z is out of the face).
  const Eigen::Vector3d facing = R_head.col(2);
  const double yaw = std::atan2(facing.y(), facing.x());
  Eigen::Isometry3d T_body = Eigen::Isometry3d::Identity();
  T_body.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_body.translation() << scene.teacher_floor_xy.x(), scene.teacher_floor_xy.y(), 0.0;
  const double r = teacher_body_radius_m_, top = std::max(0.3, teacher_eye_height_m_ - 0.25);
  const Eigen::Vector3d body_lo(-0.6 * r, -r, 0.0), body_hi(0.6 * r, r, top);
  // Head in the face frame: x ±7.5 cm, y (up) from the chin to the crown, z (out) from the back to the nose.
  const Eigen::Vector3d head_lo(-0.075, -0.14, -0.20), head_hi(0.075, 0.08, 0.02);
  const struct {
    const Eigen::Isometry3d* T;
    Eigen::Vector3d lo, hi;
    cv::Scalar colour, front;
  } parts[2] = {{&T_body, body_lo, body_hi, bgr(150, 80, 60), bgr(150, 80, 60)},
                {&scene.T_world_head, head_lo, head_hi, bgr(40, 45, 55), bgr(120, 150, 200)}};
  for (std::size_t p = 0; p < 2; ++p) {
    Solid& s = solids_[fixed_solids_ + p];
    s.centre = *parts[p].T * (0.5 * (parts[p].lo + parts[p].hi));
    std::size_t f = 0;
    for (int axis = 0; axis < 3; ++axis) {
      for (bool positive : {false, true}) {
        Eigen::Vector3d n = Eigen::Vector3d::Zero();
        n[axis] = positive ? 1.0 : -1.0;
        n = parts[p].T->linear() * n;
        const cv::Scalar colour = (p == 1 && axis == 2 && positive) ? parts[p].front : parts[p].colour;
        s.faces[f++] = {box_face(*parts[p].T, parts[p].lo, parts[p].hi, axis, positive), n, colour * shading(n)};
      }
    }
  }
}

void FlatSceneRenderer::render(CameraId camera, const SceneState& scene, cv::Mat& out) {
  View& view = views_[camera == CameraId::Front ? 0 : 1];
  Eigen::Isometry3d T_world_cam = scene.T_world_body * view.T_body_cam;
  // The bottom camera sits below the hull's underside: on the ground, keep it just above the surface.
  Eigen::Vector3d c = T_world_cam.translation();
  c.z() = std::max(c.z(), lab_.surface_height(c.x(), c.y()) + 0.01);
  T_world_cam.translation() = c;
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();

  cv::Mat& target = view.distorted ? view.canvas : out;
  target.create(view.canvas_size, CV_8UC3);
  target.setTo(cv::Scalar(90, 90, 90));
  for (const Quad& q : room_) draw_quad(target, view, T_cam_world, q);

  add_teacher(scene);
  order_.clear();
  const std::size_t solids = scene.teacher_present ? solids_.size() : fixed_solids_;
  for (std::size_t i = 0; i < solids; ++i) {
    const double distance = (solids_[i].centre - c).norm();
    order_.emplace_back(solids_[i].layer * 1e6 - distance, i);  // layers first, far to near within one
  }
  std::sort(order_.begin(), order_.end());
  for (const auto& [key, i] : order_) {
    for (const Quad& q : solids_[i].faces) {
      const Eigen::Vector3d centroid = 0.25 * (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]);
      if ((c - centroid).dot(q.normal) <= 0) continue;  // back face
      if (q.texture >= 0) {
        draw_textured(target, view, T_cam_world, q);
      } else {
        draw_quad(target, view, T_cam_world, q);
      }
    }
  }
  if (view.distorted) cv::remap(view.canvas, out, view.map1, view.map2, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  if (scene.exposure_gain != 1.0) out.convertTo(out, -1, scene.exposure_gain);
}

int FlatSceneRenderer::clip_to_frustum(const View& view, int n) {
  // Planes a·p >= 0 in camera coordinates: near, left, right, top, bottom.
  const Eigen::Vector4d& f = view.frustum;
  const Eigen::Vector3d planes[5] = {{0, 0, 1}, {1, 0, -f[0]}, {-1, 0, f[1]}, {0, 1, -f[2]}, {0, -1, f[3]}};
  const double offsets[5] = {-kNear_m, 0, 0, 0, 0};
  auto* in = &clip_a_;
  auto* out = &clip_b_;
  for (int p = 0; p < 5 && n > 0; ++p) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d& a = (*in)[static_cast<std::size_t>(i)];
      const Eigen::Vector3d& b = (*in)[static_cast<std::size_t>((i + 1) % n)];
      const double da = planes[p].dot(a) + offsets[p], db = planes[p].dot(b) + offsets[p];
      if (da >= 0) (*out)[static_cast<std::size_t>(m++)] = a;
      if ((da >= 0) != (db >= 0)) (*out)[static_cast<std::size_t>(m++)] = a + (b - a) * (da / (da - db));
    }
    n = m;
    std::swap(in, out);
  }
  if (in != &clip_a_) std::copy_n(in->begin(), n, clip_a_.begin());
  return n;
}

// Clips the quad to the frustum and projects it onto the canvas into polygon_ (sub-pixel points);
// false when nothing is visible.
bool FlatSceneRenderer::project_quad(const View& view, const Eigen::Isometry3d& T_cam_world, const Quad& q) {
  for (std::size_t i = 0; i < 4; ++i) clip_a_[i] = T_cam_world * q.corners[i];
  const int n = clip_to_frustum(view, 4);
  if (n < 3) return false;
  polygon_.clear();
  const cv::Matx33d& K = view.K_canvas;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = clip_a_[static_cast<std::size_t>(i)];
    polygon_.emplace_back(static_cast<int>(std::lround((K(0, 0) * p.x() / p.z() + K(0, 2)) * kSubpixel)),
                          static_cast<int>(std::lround((K(1, 1) * p.y() / p.z() + K(1, 2)) * kSubpixel)));
  }
  return true;
}

void FlatSceneRenderer::draw_quad(cv::Mat& target, const View& view, const Eigen::Isometry3d& T_cam_world, const Quad& q) {
  if (!project_quad(view, T_cam_world, q)) return;
  cv::fillConvexPoly(target, polygon_.data(), static_cast<int>(polygon_.size()), q.colour, cv::LINE_8, kShift);
}

void FlatSceneRenderer::draw_textured(cv::Mat& target, View& view, const Eigen::Isometry3d& T_cam_world, const Quad& q) {
  if (!project_quad(view, T_cam_world, q)) return;
  const Texture& tex = textures_[static_cast<std::size_t>(q.texture)];
  const cv::Mat& full = tex.levels.front();
  // Texture pixel (i, j) (centre at integer coordinates, as OpenCV warps) lies on the panel at
  // O + i·A + j·B: the plane-to-canvas homography is K·[R·A, R·B, R·O + t].
  const Eigen::Vector3d A = (q.corners[1] - q.corners[0]) / full.cols, B = (q.corners[3] - q.corners[0]) / full.rows;
  const Eigen::Vector3d O = q.corners[0] + 0.5 * A + 0.5 * B;
  const Eigen::Matrix3d R = T_cam_world.linear();
  Eigen::Matrix3d M;
  M.col(0) = R * A;
  M.col(1) = R * B;
  M.col(2) = T_cam_world * O;
  // The mip level whose texels are about one canvas pixel at the panel's depth.
  const double depth = std::max(kNear_m, (T_cam_world * (0.5 * (q.corners[0] + q.corners[2]))).z());
  const double texels_per_pixel = (full.cols / tex.width_m) / (view.K_canvas(0, 0) / depth);
  const int level = std::clamp(static_cast<int>(std::floor(std::log2(std::max(1.0, texels_per_pixel)))), 0,
                               static_cast<int>(tex.levels.size()) - 1);
  const double scale = std::ldexp(1.0, level);
  // Level pixel i sits at level-0 coordinate scale·i + (scale − 1)/2.
  const cv::Matx33d S(scale, 0, 0.5 * (scale - 1), 0, scale, 0.5 * (scale - 1), 0, 0, 1);
  cv::Matx33d H;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) H(r, c) = M(r, c);
  H = view.K_canvas * H * S;

  const cv::Rect bounds = cv::boundingRect(polygon_);
  const cv::Rect roi = cv::Rect(bounds.x >> kShift, bounds.y >> kShift, (bounds.width >> kShift) + 2, (bounds.height >> kShift) + 2) &
                       cv::Rect(0, 0, target.cols, target.rows);
  if (roi.empty()) return;
  const cv::Matx33d shift(1, 0, -roi.x, 0, 1, -roi.y, 0, 0, 1);
  cv::Mat warp = view.warp(roi), mask = view.mask(roi);
  cv::warpPerspective(tex.levels[static_cast<std::size_t>(level)], warp, shift * H, roi.size(), cv::INTER_LINEAR,
                      cv::BORDER_REPLICATE);
  mask.setTo(0);
  for (auto& p : polygon_) p -= cv::Point(roi.x << kShift, roi.y << kShift);
  cv::fillConvexPoly(mask, polygon_.data(), static_cast<int>(polygon_.size()), cv::Scalar(255), cv::LINE_8, kShift);
  warp.copyTo(target(roi), mask);
}

}  // namespace labo
