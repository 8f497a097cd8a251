#include "drone/lab/lab_description.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "core/config_reader.hpp"
#include "core/source_tree.hpp"

namespace labo::lab {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

std::string fmt(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(3);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

std::string fmt2(const Eigen::Vector2d& v) {
  std::ostringstream s;
  s.precision(3);
  s << "(" << v.x() << ", " << v.y() << ")";
  return s.str();
}

Eigen::Vector3d read_vec3(const ConfigReader& r, std::string_view key) {
  const auto v = r.numbers(key, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector2d read_vec2(const ConfigReader& r, std::string_view key) {
  const auto v = r.numbers(key, 2);
  return {v[0], v[1]};
}

Box3 read_box(const ConfigReader& r) {
  Box3 b{read_vec3(r, "min"), read_vec3(r, "max")};
  for (int i = 0; i < 3; ++i) {
    if (!(b.max[i] > b.min[i])) {
      r.fail("max", "non-positive size " + fmt(b.size()) + ": every max coordinate must exceed min");
    }
  }
  return b;
}

}  // namespace

Eigen::Isometry3d panel_pose(const Eigen::Vector3d& centre, double facing_rad, double tilt_rad) {
  const Eigen::Vector3d n(std::cos(facing_rad), std::sin(facing_rad), 0.0);
  const Eigen::Vector3d view = -n;                                   // the viewer looks along -n
  const Eigen::Vector3d right(view.y(), -view.x(), 0.0);             // the viewer's right
  // Tilt leans the panel back (top away from the viewer), about the panel's x axis.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(-tilt_rad, right).toRotationMatrix();
  Eigen::Matrix3d R;
  R.col(0) = right;
  R.col(1) = tilt * Eigen::Vector3d(0, 0, -1);
  R.col(2) = tilt * view;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = centre;
  return T;
}

namespace {

// Loads the template to check it exists, decodes, and has the panel's aspect ratio.
void check_template(const ConfigReader& r, const InstrumentSpec& s) {
  if (!std::filesystem::exists(s.template_path)) {
    r.fail("template", "missing texture: file " + s.template_path.string() +
                           " does not exist (regenerate with `labodrone sim textures`)");
  }
  const cv::Mat img = cv::imread(s.template_path.string(), cv::IMREAD_UNCHANGED);
  if (img.empty()) r.fail("template", "cannot decode image " + s.template_path.string());
  const double image_aspect = static_cast<double>(img.cols) / img.rows;
  const double panel_aspect = s.width_m / s.height_m;
  if (std::abs(image_aspect / panel_aspect - 1.0) > 0.03) {
    std::ostringstream m;
    m << "image " << img.cols << "x" << img.rows << " (aspect " << image_aspect << ") does not match width_m/height_m = "
      << panel_aspect << " within 3%";
    r.fail("template", m.str());
  }
}

void read_planar_common(const ConfigReader& r, const std::filesystem::path& base_dir, InstrumentSpec& s) {
  s.id = r.string("id");
  if (s.id.empty()) r.fail("id", "must not be empty");
  s.name = r.string_or("name", s.id);
  s.template_path = (base_dir / r.string("template")).lexically_normal();
  s.width_m = r.number("width_m", Range::positive());
  s.height_m = r.number("height_m", Range::positive());
  s.sift_switch_distance_m = r.number_or("sift_switch_distance_m", 2.0, Range::positive());
  s.sift_min_inliers = r.integer_or("sift_min_inliers", 20, 4, 10000);
  check_template(r, s);
}

InstrumentSpec read_instrument(const ConfigReader& r, const std::filesystem::path& base_dir) {
  InstrumentSpec s;
  read_planar_common(r, base_dir, s);
  s.depth_m = r.number("depth_m", Range::positive());
  s.T_world_object = panel_pose(read_vec3(r, "centre"), r.number("facing_deg", Range::closed(-360, 360)) * kDegToRad,
                                r.number_or("tilt_deg", 0.0, Range::closed(-60, 60)) * kDegToRad);
  r.finish();
  return s;
}

PlatformSpec read_platform(const ConfigReader& r, const std::filesystem::path& base_dir) {
  PlatformSpec p;
  read_planar_common(r, base_dir, p);
  p.thickness_m = r.number("thickness_m", Range::positive());
  const Eigen::Vector2d c = read_vec2(r, "centre");
  const double yaw = r.number_or("yaw_deg", 0.0, Range::closed(-360, 360)) * kDegToRad;
  // Object axes: x = world -y, y = world -x, z = world -z (rotated by yaw about world z).
  Eigen::Matrix3d R0;
  R0.col(0) = -Eigen::Vector3d::UnitY();
  R0.col(1) = -Eigen::Vector3d::UnitX();
  R0.col(2) = -Eigen::Vector3d::UnitZ();
  p.T_world_object.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R0;
  p.T_world_object.translation() = Eigen::Vector3d(c.x(), c.y(), p.thickness_m);
  p.depth_m = p.thickness_m;
  r.finish();
  return p;
}

ObserverCameraSpec read_camera(const ConfigReader& r) {
  ObserverCameraSpec c;
  c.id = r.string("id");
  c.position = read_vec3(r, "position");
  c.look_at = read_vec3(r, "look_at");
  c.horizontal_fov_deg = r.number_or("horizontal_fov_deg", 70.0, Range::closed(10, 170));
  if ((c.look_at - c.position).norm() < 1e-3) r.fail("look_at", "must differ from position");
  r.finish();
  return c;
}

TeacherSpec read_teacher(const ConfigReader& r) {
  TeacherSpec t;
  for (const ConfigReader& w : r.objects("waypoints")) {
    t.waypoints.emplace_back(w.number("x"), w.number("y"));
    w.finish();
  }
  if (t.waypoints.size() < 2) r.fail("waypoints", "needs at least 2 waypoints");
  t.speed_mps = r.number("speed_mps", Range{0.0, 3.0, true});
  t.pause_s = r.number_or("pause_s", t.pause_s, Range::non_negative());
  t.interpupillary_distance_m = r.number("interpupillary_distance_m", Range::closed(0.04, 0.09));
  t.eye_height_m = r.number_or("eye_height_m", t.eye_height_m, Range::closed(0.5, 2.5));
  t.body_radius_m = r.number_or("body_radius_m", t.body_radius_m, Range::positive());
  t.face_image = r.string_or("face_image", "../assets/astronaut.png");
  if (r.has("head_motion")) {
    const ConfigReader h = r.object("head_motion");
    auto& m = t.head;
    m.yaw_amplitude_deg = h.number_or("yaw_amplitude_deg", m.yaw_amplitude_deg, Range::closed(0, 90));
    m.yaw_period_s = h.number_or("yaw_period_s", m.yaw_period_s, Range::positive());
    m.pitch_amplitude_deg = h.number_or("pitch_amplitude_deg", m.pitch_amplitude_deg, Range::closed(0, 60));
    m.pitch_period_s = h.number_or("pitch_period_s", m.pitch_period_s, Range::positive());
    m.roll_amplitude_deg = h.number_or("roll_amplitude_deg", m.roll_amplitude_deg, Range::closed(0, 60));
    m.roll_period_s = h.number_or("roll_period_s", m.roll_period_s, Range::positive());
    h.finish();
  }
  r.finish();
  return t;
}

// Parameter s in [0, 1] where the segment a-b first enters the 2D box [lo, hi] (slab method), or -1.
double segment_hits_rect(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& lo,
                         const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int i = 0; i < 2; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (a[i] < lo[i] || a[i] > hi[i]) return -1.0;
      continue;
    }
    double ta = (lo[i] - a[i]) / d[i], tb = (hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return -1.0;
  }
  return t0;
}

void check_unique_ids(const LabDescription& lab, const ConfigReader& root) {
  std::set<std::string> ids;
  auto add = [&](const std::string& id, const std::string& key) {
    if (!ids.insert(id).second) root.fail(key, "duplicate id '" + id + "'");
  };
  for (std::size_t i = 0; i < lab.benches.size(); ++i) add(lab.benches[i].id, "benches[" + std::to_string(i) + "].id");
  for (std::size_t i = 0; i < lab.instruments.size(); ++i) {
    add(lab.instruments[i].id, "instruments[" + std::to_string(i) + "].id");
  }
  add(lab.platform.id, "platform.id");
}

struct NamedBox {
  std::string key;
  std::string id;
  Box3 box;
};

std::vector<NamedBox> solid_objects(const LabDescription& lab) {
  std::vector<NamedBox> out;
  for (std::size_t i = 0; i < lab.benches.size(); ++i) {
    out.push_back({"benches[" + std::to_string(i) + "]", lab.benches[i].id, lab.benches[i].box});
  }
  for (std::size_t i = 0; i < lab.instruments.size(); ++i) {
    out.push_back({"instruments[" + std::to_string(i) + "]", lab.instruments[i].id, lab.instruments[i].bounds()});
  }
  out.push_back({"platform", lab.platform.id, lab.platform.box()});
  return out;
}

void check_geometry(const LabDescription& lab, const ConfigReader& root) {
  const auto solids = solid_objects(lab);
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const auto& a = solids[i];
    if (!lab.room.contains(a.box.min, 1e-6) || !lab.room.contains(a.box.max, 1e-6)) {
      root.fail(a.key, "'" + a.id + "' spans " + fmt(a.box.min) + "-" + fmt(a.box.max) + ", outside the room " +
                           fmt(lab.room.min) + "-" + fmt(lab.room.max));
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (a.box.overlaps(solids[j].box)) {
        root.fail(a.key, "'" + a.id + "' overlaps '" + solids[j].id + "' (" + solids[j].key + ")");
      }
    }
  }
  for (std::size_t i = 0; i < lab.cameras.size(); ++i) {
    const std::string key = "cameras[" + std::to_string(i) + "].position";
    if (!lab.room.contains(lab.cameras[i].position, -0.01)) {
      root.fail(key, "camera '" + lab.cameras[i].id + "' at " + fmt(lab.cameras[i].position) + " is outside the room " +
                         fmt(lab.room.min) + "-" + fmt(lab.room.max));
    }
    for (const auto& s : solids) {
      if (s.box.contains(lab.cameras[i].position)) {
        root.fail(key, "camera '" + lab.cameras[i].id + "' is inside '" + s.id + "'");
      }
    }
  }
}

void check_teacher_path(const LabDescription& lab, const ConfigReader& root) {
  const auto& t = lab.teacher;
  const double r = t.body_radius_m;
  const Eigen::Vector2d room_lo = lab.room.min.head<2>() + Eigen::Vector2d::Constant(r);
  const Eigen::Vector2d room_hi = lab.room.max.head<2>() - Eigen::Vector2d::Constant(r);
  if (t.eye_height_m + 0.15 > lab.room.max.z()) root.fail("teacher.eye_height_m", "the head does not fit under the ceiling");
  const std::size_t n = t.waypoints.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = t.waypoints[i], b = t.waypoints[(i + 1) % n];
    const std::string key = "teacher.waypoints[" + std::to_string(i) + "]";
    const std::string seg = "path segment " + fmt2(a) + " -> " + fmt2(b);
    // The room is convex: a segment stays inside iff both ends do.
    for (const auto& p : {a, b}) {
      if ((p.array() < room_lo.array()).any() || (p.array() > room_hi.array()).any()) {
        root.fail(key, seg + " passes through a wall: " + fmt2(p) + " is not inside the room shrunk by the body radius " +
                           std::to_string(r) + " m");
      }
    }
    for (const auto& s : solid_objects(lab)) {
      const Eigen::Vector2d lo = s.box.min.head<2>() - Eigen::Vector2d::Constant(r);
      const Eigen::Vector2d hi = s.box.max.head<2>() + Eigen::Vector2d::Constant(r);
      if (segment_hits_rect(a, b, lo, hi) >= 0.0) root.fail(key, seg + " walks through '" + s.id + "'");
    }
  }
}

}  // namespace

bool Box3::contains(const Eigen::Vector3d& p, double margin) const {
  return (p.array() >= min.array() - margin).all() && (p.array() <= max.array() + margin).all();
}

bool Box3::overlaps(const Box3& o, double tol) const {
  for (int i = 0; i < 3; ++i) {
    if (std::min(max[i], o.max[i]) - std::max(min[i], o.min[i]) <= tol) return false;
  }
  return true;
}

std::array<Eigen::Vector3d, 4> InstrumentSpec::corners_world() const {
  const double w = 0.5 * width_m, h = 0.5 * height_m;
  return {{T_world_object * Eigen::Vector3d(-w, -h, 0), T_world_object * Eigen::Vector3d(w, -h, 0),
          T_world_object * Eigen::Vector3d(w, h, 0), T_world_object * Eigen::Vector3d(-w, h, 0)}};
}

Box3 InstrumentSpec::bounds() const {
  Box3 b{Eigen::Vector3d::Constant(1e9), Eigen::Vector3d::Constant(-1e9)};
  for (const auto& c : corners_world()) {
    for (double d : {0.0, depth_m}) {
      const Eigen::Vector3d p = c + d * T_world_object.linear().col(2);
      b.min = b.min.cwiseMin(p);
      b.max = b.max.cwiseMax(p);
    }
  }
  return b;
}

Box3 PlatformSpec::box() const { return bounds(); }

Eigen::Isometry3d ObserverCameraSpec::T_world_cam() const {
  const Eigen::Vector3d z = (look_at - position).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitY();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = position;
  return T;
}

const InstrumentSpec* LabDescription::find_instrument(const std::string& id) const {
  for (const auto& i : instruments) {
    if (i.id == id) return &i;
  }
  return platform.id == id ? &platform : nullptr;
}

double LabDescription::surface_height(double x, double y) const {
  double h = room.min.z();
  auto consider = [&](const Box3& b) {
    if (x >= b.min.x() && x <= b.max.x() && y >= b.min.y() && y <= b.max.y()) h = std::max(h, b.max.z());
  };
  for (const auto& b : benches) consider(b.box);
  for (const auto& i : instruments) consider(i.bounds());
  consider(platform.box());
  return h;
}

bool LabDescription::floor_is_bare(double x, double y) const {
  for (const auto& a : bare_areas) {
    if (a.surface == "floor" && x >= a.min.x() && x <= a.max.x() && y >= a.min.y() && y <= a.max.y()) return true;
  }
  return false;
}

LabDescription read_lab_description(const ConfigReader& root, const std::filesystem::path& base_dir) {
  LabDescription lab;
  lab.source = root.source();
  {
    const ConfigReader room = root.object("room");
    lab.room = read_box(room);
    room.finish();
  }
  if (lab.room.size().z() < 2.0 || lab.room.size().x() < 2.0 || lab.room.size().y() < 2.0) {
    root.fail("room", "the room " + fmt(lab.room.size()) + " m must be at least 2 m along each axis");
  }
  if (!lab.room.contains(Eigen::Vector3d::Zero())) root.fail("room", "must contain the origin (the base)");
  lab.texture_seed = static_cast<unsigned>(root.integer_or("texture_seed", 1, 0, 1 << 30));
  for (const ConfigReader& b : root.objects("benches")) {
    lab.benches.push_back({b.string("id"), read_box(b)});
    b.finish();
  }
  for (const ConfigReader& i : root.objects("instruments")) lab.instruments.push_back(read_instrument(i, base_dir));
  if (lab.instruments.size() < 1) root.fail("instruments", "needs at least one instrument");
  lab.platform = read_platform(root.object("platform"), base_dir);
  {
    const ConfigReader base = root.object("base");
    const double yaw = base.number_or("yaw_deg", 0.0, Range::closed(-360, 360)) * kDegToRad;
    base.finish();
    const Eigen::Vector3d top = lab.platform.T_world_object.translation();
    lab.T_world_base = Eigen::Isometry3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    lab.T_world_base.translation() = top;
  }
  if (root.has("cameras")) {
    for (const ConfigReader& c : root.objects("cameras")) lab.cameras.push_back(read_camera(c));
  }
  if (root.has("bare_areas")) {
    for (const ConfigReader& a : root.objects("bare_areas")) {
      BareArea area;
      area.surface = a.choice("surface", {"floor", "wall_xmin", "wall_xmax", "wall_ymin", "wall_ymax"});
      area.min = read_vec2(a, "min");
      area.max = read_vec2(a, "max");
      if ((area.max.array() <= area.min.array()).any()) a.fail("max", "non-positive size: max must exceed min");
      a.finish();
      lab.bare_areas.push_back(area);
    }
  }
  lab.teacher = read_teacher(root.object("teacher"));
  root.finish();

  check_unique_ids(lab, root);
  check_geometry(lab, root);
  check_teacher_path(lab, root);
  return lab;
}

LabDescription load_lab_description(const std::filesystem::path& file) {
  const ConfigDocument doc = ConfigDocument::load(file);
  LabDescription lab = read_lab_description(doc.root(), file.parent_path());
  lab.source = file;
  return lab;
}

std::filesystem::path default_lab_path() { return labo::source_root() / "config" / "lab.json"; }

}  // namespace labo::lab
