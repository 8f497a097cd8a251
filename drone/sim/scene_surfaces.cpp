#include "drone/sim/scene_surfaces.hpp"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "drone/sim/texture_procedural.hpp"

namespace labo::sim {

using lab::Box3;
using lab::InstrumentSpec;
using lab::LabDescription;


namespace {

// A face given its centre, outward normal and in-plane axes.
SceneRect face(std::string name, const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, const Eigen::Vector3d& u,
               const Eigen::Vector3d& v, double size_u, double size_v) {
  SceneRect r;
  r.name = std::move(name);
  r.normal = normal;
  r.axis_u = u;
  r.axis_v = v;
  r.size_u = size_u;
  r.size_v = size_v;
  r.origin = centre - 0.5 * size_u * u - 0.5 * size_v * v;
  return r;
}

// Texture axes of an axis-aligned face: vertical faces read left to right for a viewer facing them,
// top to bottom; horizontal faces have u along +x.
void axes_for_normal(const Eigen::Vector3d& n, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  if (std::abs(n.z()) > 0.5) {
    u = Eigen::Vector3d::UnitX();
    v = n.z() > 0 ? Eigen::Vector3d(-Eigen::Vector3d::UnitY()) : Eigen::Vector3d(Eigen::Vector3d::UnitY());
  } else {
    u = (-n).cross(Eigen::Vector3d::UnitZ()).normalized();
    v = -Eigen::Vector3d::UnitZ();
  }
}

// The faces of an axis-aligned box; `inward` for the room (normals into the box).
std::vector<SceneRect> box_faces(const std::string& prefix, const Box3& box, bool inward, bool with_bottom) {
  static const char* kNames[6] = {"xmin", "xmax", "ymin", "ymax", "bottom", "top"};
  std::vector<SceneRect> out;
  const Eigen::Vector3d c = box.centre(), s = box.size();
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      if (axis == 2 && side == 0 && !with_bottom) continue;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = side == 0 ? -1.0 : 1.0;
      Eigen::Vector3d centre = c;
      centre[axis] = side == 0 ? box.min[axis] : box.max[axis];
      if (inward) n = -n;
      Eigen::Vector3d u, v;
      axes_for_normal(n, u, v);
      out.push_back(face(prefix + kNames[axis * 2 + side], centre, n, u, v, std::abs(s.dot(u)), std::abs(s.dot(v))));
    }
  }
  return out;
}

// The panel and housing of a planar object (object x right, y down, z into the panel, depth along z).
std::vector<SceneRect> housing_faces(const InstrumentSpec& s) {
  const Eigen::Matrix3d R = s.T_world_object.linear();
  const Eigen::Vector3d x = R.col(0), y = R.col(1), z = R.col(2);
  const Eigen::Vector3d c = s.T_world_object.translation() + 0.5 * s.depth_m * z;  // the box's centre
  const double w = s.width_m, h = s.height_m, d = s.depth_m;
  return {face(s.id + ".back", c + 0.5 * d * z, z, -x, y, w, h),
          face(s.id + ".top", c - 0.5 * h * y, -y, x, z, w, d),
          face(s.id + ".bottom", c + 0.5 * h * y, y, x, -z, w, d),
          face(s.id + ".left", c - 0.5 * w * x, -x, z, y, d, h),
          face(s.id + ".right", c + 0.5 * w * x, x, -z, y, d, h)};
}

SceneRect panel_face(const InstrumentSpec& s) {
  const Eigen::Matrix3d R = s.T_world_object.linear();
  SceneRect r = face(s.id + ".panel", s.T_world_object.translation(), -R.col(2), R.col(0), R.col(1), s.width_m, s.height_m);
  return r;
}

// Surface texture of a procedural material; `bare` in metres from the rect's origin along u, v.
void add_procedural(LabScene& scene, SceneRect r, SurfaceMaterial material, unsigned seed, std::vector<cv::Rect2d> bare = {}) {
  SurfaceTextureRequest q;
  q.material = material;
  q.width_m = r.size_u;
  q.height_m = r.size_v;
  q.metres_per_texel = metres_per_texel(material);
  q.seed = seed;
  q.bare_m = std::move(bare);
  scene.textures.emplace_back(draw_surface_texture(q));
  r.texture = static_cast<int>(scene.textures.size()) - 1;
  r.texels_per_m_u = r.texels_per_m_v = 1.0 / q.metres_per_texel;
  scene.rects.push_back(std::move(r));
}

void add_template(LabScene& scene, SceneRect r, const std::filesystem::path& file) {
  const cv::Mat img = cv::imread(file.string(), cv::IMREAD_COLOR);
  if (img.empty()) {
    throw std::runtime_error("lab renderer: " + r.name + ": cannot read the template image " + file.string() +
                             (std::filesystem::exists(file) ? " (not a decodable image)" : " (no such file)"));
  }
  scene.textures.emplace_back(img);
  // Panels seen from afar are area filtered (docs/sim_rendering.md): the planar localizer measures
  // their pose to a tenth of a pixel, and a mip level's phase-dependent blur would bias it.
  scene.textures.back().build_area_table();
  r.texture = static_cast<int>(scene.textures.size()) - 1;
  r.texels_per_m_u = img.cols / r.size_u;
  r.texels_per_m_v = img.rows / r.size_v;
  scene.rects.push_back(std::move(r));
}

// The bare areas of one room face, in the face's texture metres.
std::vector<cv::Rect2d> bare_rects(const LabDescription& lab, const SceneRect& r, const std::string& surface) {
  std::vector<cv::Rect2d> out;
  for (const auto& area : lab.bare_areas) {
    if (area.surface != surface) continue;
    // Floor: (x, y); walls: (along, z) with `along` the wall's horizontal world axis.
    Eigen::Vector3d lo, hi;
    if (surface == "floor") {
      lo = {area.min.x(), area.min.y(), r.origin.z()};
      hi = {area.max.x(), area.max.y(), r.origin.z()};
    } else if (surface == "wall_xmin" || surface == "wall_xmax") {
      lo = {r.origin.x(), area.min.x(), area.min.y()};
      hi = {r.origin.x(), area.max.x(), area.max.y()};
    } else {
      lo = {area.min.x(), r.origin.y(), area.min.y()};
      hi = {area.max.x(), r.origin.y(), area.max.y()};
    }
    const double a0 = (lo - r.origin).dot(r.axis_u), a1 = (hi - r.origin).dot(r.axis_u);
    const double b0 = (lo - r.origin).dot(r.axis_v), b1 = (hi - r.origin).dot(r.axis_v);
    out.emplace_back(std::min(a0, a1), std::min(b0, b1), std::abs(a1 - a0), std::abs(b1 - b0));
  }
  return out;
}

}  // namespace

int LabScene::find(const std::string& name) const {
  for (std::size_t i = 0; i < rects.size(); ++i) {
    if (rects[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

LabScene build_lab_scene(const LabDescription& lab) {
  LabScene scene;
  unsigned seed = lab.texture_seed * 7919u + 17u;
  auto next_seed = [&seed] { return seed = seed * 1103515245u + 12345u; };

  // The room's shell, named as the lab file's bare areas name them.
  for (SceneRect r : box_faces("", lab.room, /*inward=*/true, /*with_bottom=*/true)) {
    r.room_shell = true;
    std::string surface;
    SurfaceMaterial material = SurfaceMaterial::Wall;
    if (r.name == "bottom") {
      surface = "floor";
      material = SurfaceMaterial::Floor;
    } else if (r.name == "top") {
      surface = "ceiling";
      material = SurfaceMaterial::Ceiling;
    } else {
      surface = "wall_" + r.name;
    }
    r.name = surface;
    const auto bare = bare_rects(lab, r, surface);
    add_procedural(scene, r, material, next_seed(), bare);
  }
  for (const auto& bench : lab.benches) {
    for (SceneRect r : box_faces(bench.id + ".", bench.box, /*inward=*/false, /*with_bottom=*/false)) {
      const bool top = r.name == bench.id + ".top";
      add_procedural(scene, r, top ? SurfaceMaterial::BenchTop : SurfaceMaterial::BenchSide, next_seed());
    }
  }
  for (const auto& instrument : lab.instruments) {
    add_template(scene, panel_face(instrument), instrument.template_path);
    for (SceneRect r : housing_faces(instrument)) add_procedural(scene, r, SurfaceMaterial::Housing, next_seed());
  }
  add_template(scene, panel_face(lab.platform), lab.platform.template_path);
  for (SceneRect r : housing_faces(lab.platform)) {
    if (r.name == lab.platform.id + ".back") continue;  // on the floor, never seen
    add_procedural(scene, r, SurfaceMaterial::PlatformSide, next_seed());
  }
  return scene;
}

void append_instrument(LabScene& scene, const InstrumentSpec& instrument, unsigned seed) {
  add_template(scene, panel_face(instrument), instrument.template_path);
  for (SceneRect r : housing_faces(instrument)) add_procedural(scene, r, SurfaceMaterial::Housing, seed = seed * 1103515245u + 12345u);
}

}  // namespace labo::sim
