#include "core/candide3.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include "core/source_tree.hpp"

namespace labo {

namespace {

// Walks the .wfm file line by line, keeping '#' lines (they carry section and unit names) and
// skipping blank ones.
class WfmReader {
 public:
  explicit WfmReader(const std::filesystem::path& file) : file_(file), in_(file) {
    if (!in_) throw std::runtime_error(file.string() + ": cannot read the CANDIDE-3 model file");
  }

  // Next non-blank line; false at the end of the file.
  bool next(std::string& line) {
    while (std::getline(in_, line)) {
      ++line_number_;
      if (line.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  }

  // Advances to the "# <section>" line.
  void seek_section(const std::string& section) {
    std::string line;
    while (next(line)) {
      if (line.rfind("# " + section, 0) == 0) return;
    }
    fail("section '# " + section + "' not found");
  }

  // The next line as a count (skipping comments).
  int count(int max) {
    std::string line;
    while (next(line)) {
      if (line[0] == '#') continue;
      std::istringstream s(line);
      int n = -1;
      if (!(s >> n) || n < 0 || n > max) fail("expected a count in [0, " + std::to_string(max) + "], found '" + line + "'");
      return n;
    }
    fail("expected a count, found the end of the file");
  }

  template <typename... T>
  void values(T&... out) {
    std::string line;
    if (!next(line)) fail("unexpected end of file");
    std::istringstream s(line);
    if (!(s >> ... >> out)) fail("expected " + std::to_string(sizeof...(T)) + " numbers, found '" + line + "'");
  }

  // A unit: "# name" comment lines, then a count and that many "vertex dx dy dz" lines.
  Candide3Model::Unit unit(int vertex_count) {
    Candide3Model::Unit u;
    std::string line;
    while (next(line)) {
      if (line[0] == '#') {
        u.name = line.substr(line.find_first_not_of("# \t"));
        continue;
      }
      std::istringstream s(line);
      int n = -1;
      if (!(s >> n) || n < 0 || n > vertex_count) fail("expected a displacement count, found '" + line + "'");
      for (int i = 0; i < n; ++i) {
        Candide3Model::Displacement d;
        values(d.vertex, d.delta.x(), d.delta.y(), d.delta.z());
        if (d.vertex < 0 || d.vertex >= vertex_count) fail("vertex index " + std::to_string(d.vertex) + " out of range");
        u.displacements.push_back(d);
      }
      return u;
    }
    fail("unexpected end of file inside a unit");
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(file_.string() + ":" + std::to_string(line_number_) + ": " + what);
  }

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  int line_number_ = 0;
};

}  // namespace

std::filesystem::path Candide3Model::default_path() {
  return labo::source_root() / "config" / "face" / "candide3.wfm";
}

Candide3Model Candide3Model::load(const std::filesystem::path& file) {
  WfmReader r(file);
  Candide3Model m;
  r.seek_section("VERTEX LIST");
  const int nv = r.count(100000);
  m.vertices_.resize(nv);
  for (auto& v : m.vertices_) r.values(v.x(), v.y(), v.z());
  r.seek_section("FACE LIST");
  const int nf = r.count(1000000);
  m.triangles_.resize(nf);
  for (auto& t : m.triangles_) {
    r.values(t[0], t[1], t[2]);
    for (int i : t) {
      if (i < 0 || i >= nv) r.fail("triangle vertex " + std::to_string(i) + " out of range");
    }
  }
  r.seek_section("ANIMATION UNITS LIST");
  const int na = r.count(1000);
  for (int i = 0; i < na; ++i) m.animation_units_.push_back(r.unit(nv));
  r.seek_section("SHAPE UNITS LIST");
  const int ns = r.count(1000);
  for (int i = 0; i < ns; ++i) m.shape_units_.push_back(r.unit(nv));
  return m;
}

void Candide3Model::deform_into(std::span<const double> shape, std::span<const double> animation,
                                std::vector<Eigen::Vector3d>& out) const {
  if (shape.size() > shape_units_.size() || animation.size() > animation_units_.size()) {
    throw std::invalid_argument("CANDIDE-3: " + std::to_string(shape.size()) + " shape / " +
                                std::to_string(animation.size()) + " animation parameters given, the model has " +
                                std::to_string(shape_units_.size()) + " / " + std::to_string(animation_units_.size()));
  }
  out = vertices_;
  auto apply = [&](const std::vector<Unit>& units, std::span<const double> params) {
    for (std::size_t i = 0; i < params.size(); ++i) {
      if (params[i] == 0.0) continue;
      for (const auto& d : units[i].displacements) out[d.vertex] += params[i] * d.delta;
    }
  };
  apply(shape_units_, shape);
  apply(animation_units_, animation);
}

std::vector<Eigen::Vector3d> Candide3Model::deformed(std::span<const double> shape,
                                                     std::span<const double> animation) const {
  std::vector<Eigen::Vector3d> out;
  deform_into(shape, animation, out);
  return out;
}

std::filesystem::path default_ibug68_mapping_path() {
  return labo::source_root() / "config" / "face" / "ibug68_to_candide3.csv";
}

namespace {
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}
}  // namespace

Ibug68Mapping load_ibug68_mapping(const std::filesystem::path& file, int vertex_count) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the landmark mapping");
  Ibug68Mapping mapping;
  std::array<bool, 68> seen{};
  std::string line;
  int line_number = 0;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(file.string() + ":" + std::to_string(line_number) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#' || line.rfind("dlib_idx", 0) == 0) continue;
    const auto fields = split(line, ',');
    if (fields.size() < 4) fail("expected dlib_idx,vertices,weights,kind");
    int index = -1;
    try {
      index = std::stoi(fields[0]);
    } catch (const std::exception&) {
      fail("landmark index '" + fields[0] + "' is not a number");
    }
    if (index < 0 || index >= 68) fail("landmark index " + fields[0] + " outside [0, 67]");
    LandmarkVertexMap& m = mapping[index];
    seen[index] = true;
    if (fields[3] == "none") continue;
    if (fields[3] != "direct" && fields[3] != "interp") fail("kind '" + fields[3] + "' is not direct, interp or none");
    m.kind = fields[3] == "direct" ? LandmarkVertexMap::Kind::Direct : LandmarkVertexMap::Kind::Interpolated;
    const auto vs = split(fields[1], '|');
    const auto ws = split(fields[2], '|');
    if (vs.empty() || vs.size() != ws.size()) fail("vertices and weights differ in count");
    for (std::size_t i = 0; i < vs.size(); ++i) {
      try {
        m.vertices.push_back(std::stoi(vs[i]));
        m.weights.push_back(std::stod(ws[i]));
      } catch (const std::exception&) {
        fail("vertex '" + vs[i] + "' or weight '" + ws[i] + "' is not a number");
      }
      if (m.vertices.back() < 0 || m.vertices.back() >= vertex_count) fail("vertex " + vs[i] + " out of range");
    }
  }
  for (int i = 0; i < 68; ++i) {
    if (!seen[i]) throw std::runtime_error(file.string() + ": landmark " + std::to_string(i) + " is missing");
  }
  return mapping;
}

Eigen::Vector3d landmark_point(const LandmarkVertexMap& map, std::span<const Eigen::Vector3d> vertices) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < map.vertices.size(); ++i) p += map.weights[i] * vertices[map.vertices[i]];
  return p;
}

}  // namespace labo
