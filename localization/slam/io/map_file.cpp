#include "localization/slam/io/map_file.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace labo::slam {
namespace {

constexpr char kMagic[8] = {'L', 'A', 'B', 'O', 'S', 'L', 'A', 'M'};
constexpr char kEnd[8] = {'E', 'N', 'D', 'S', 'L', 'A', 'M', '!'};
// Version 2 added the loop edges (after the points); version 3 the gravity directions (each
// keyframe's IMU "down" in its camera, and the map's). Version 2 files still load, without gravity:
// a lab mapped before stays usable, and the map's gravity is then re-estimated by the adjustments
// from the attitudes of the keyframes added after loading.
constexpr std::uint32_t kVersion = 3;
constexpr std::uint32_t kOldestReadable = 2;

std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= 1099511628211ull;
  }
  return h;
}

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put_bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + n);
  }
  std::vector<std::uint8_t> bytes;
};

class Reader {
 public:
  Reader(const std::vector<std::uint8_t>& bytes, std::size_t end, std::string file) : bytes_(bytes), end_(end), file_(std::move(file)) {}
  template <typename T>
  T get(const char* what) {
    T v;
    need(sizeof(T), what);
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  double finite(const char* what) {
    const double v = get<double>(what);
    if (!std::isfinite(v)) fail(std::string("non-finite ") + what);
    return v;
  }
  void get_bytes(void* out, std::size_t n, const char* what) {
    need(n, what);
    std::memcpy(out, bytes_.data() + pos_, n);
    pos_ += n;
  }
  std::uint32_t count(const char* what, std::uint32_t max) {
    const auto n = get<std::uint32_t>(what);
    if (n > max) fail(std::string(what) + " count " + std::to_string(n) + " exceeds " + std::to_string(max));
    return n;
  }
  [[noreturn]] void fail(const std::string& reason) const {
    throw std::runtime_error("map file " + file_ + ": " + reason + " (at byte " + std::to_string(pos_) + ")");
  }
  std::size_t position() const { return pos_; }

 private:
  void need(std::size_t n, const char* what) const {
    if (pos_ + n > end_) fail(std::string("truncated while reading ") + what);
  }
  const std::vector<std::uint8_t>& bytes_;
  std::size_t pos_ = 0, end_;
  std::string file_;
};

std::vector<double> camera_numbers(const CameraIntrinsics& c) {
  return {static_cast<double>(c.width), static_cast<double>(c.height), c.fx, c.fy, c.cx, c.cy, c.k1, c.k2, c.p1, c.p2, c.k3};
}

void put_pose(Writer& w, const Eigen::Isometry3d& T) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) w.put(T.matrix()(r, c));
  }
}

// An optional unit vector: u8 present (0 or 1), then 3 f64 when present.
void put_direction(Writer& w, const std::optional<Eigen::Vector3d>& d) {
  w.put(static_cast<std::uint8_t>(d ? 1 : 0));
  if (d) {
    for (int i = 0; i < 3; ++i) w.put((*d)[i]);
  }
}

std::optional<Eigen::Vector3d> get_direction(Reader& r, const char* what) {
  const auto present = r.get<std::uint8_t>(what);
  if (present > 1) r.fail(std::string(what) + " flag " + std::to_string(present) + ", expected 0 or 1");
  if (present == 0) return std::nullopt;
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) d[i] = r.finite(what);
  // Saved normalized: anything far from unit length is damage, not rounding.
  if (std::abs(d.norm() - 1.0) > 1e-6) r.fail(std::string(what) + " is not a unit vector (norm " + std::to_string(d.norm()) + ")");
  return d.normalized();
}

Eigen::Isometry3d get_pose(Reader& r) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int c = 0; c < 4; ++c) T.matrix()(i, c) = r.finite("keyframe pose");
  }
  const Eigen::Matrix3d R = T.linear();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6) r.fail("keyframe pose is not a rotation");
  return T;
}

}  // namespace

void write_map_file(const std::filesystem::path& file, const CameraIntrinsics& camera, const SlamMap& map) {
  Writer w;
  w.put_bytes(kMagic, 8);
  w.put(kVersion);
  for (double v : camera_numbers(camera)) w.put(v);
  w.put(static_cast<std::uint32_t>(map.keyframes().size()));
  for (const Keyframe& kf : map.keyframes()) {
    w.put(kf.t);
    put_pose(w, kf.T_cam_map);
    w.put(static_cast<std::uint32_t>(kf.frame.size()));
    for (std::size_t i = 0; i < kf.frame.size(); ++i) {
      const Feature& f = kf.frame.features[i];
      w.put(f.px.x());
      w.put(f.px.y());
      w.put(f.image_px.x());
      w.put(f.image_px.y());
      w.put(static_cast<std::int32_t>(f.level));
      w.put(f.response);
      w.put_bytes(kf.frame.descriptors[i].data(), 32);
      w.put(kf.point_of_feature[i]);
    }
    const cv::Mat small = kf.small_image.isContinuous() ? kf.small_image : kf.small_image.clone();
    w.put(static_cast<std::int32_t>(small.rows));
    w.put(static_cast<std::int32_t>(small.cols));
    if (!small.empty()) w.put_bytes(small.ptr<float>(0), small.total() * sizeof(float));
    put_direction(w, kf.down_cam);
  }
  w.put(static_cast<std::uint32_t>(map.points().size()));
  w.put(map.next_point_id());
  for (const auto& [id, p] : map.points()) {
    w.put(id);
    for (int i = 0; i < 3; ++i) w.put(p.p_map[i]);
    w.put_bytes(p.descriptor.data(), 32);
    w.put(static_cast<std::int32_t>(p.reference_keyframe));
    w.put(static_cast<std::int32_t>(p.reference_level));
    w.put(p.reference_distance);
    w.put(static_cast<std::uint32_t>(p.observations.size()));
    for (const Observation& o : p.observations) {
      w.put(static_cast<std::int32_t>(o.keyframe));
      w.put(static_cast<std::int32_t>(o.feature));
    }
  }
  w.put(static_cast<std::uint32_t>(map.loop_edges().size()));
  for (const LoopEdge& e : map.loop_edges()) {
    w.put(static_cast<std::int32_t>(e.current));
    w.put(static_cast<std::int32_t>(e.loop));
    w.put(e.measured.scale);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) w.put(e.measured.R(r, c));
    }
    for (int i = 0; i < 3; ++i) w.put(e.measured.t[i]);
  }
  put_direction(w, map.down_map());
  w.put(fnv1a(w.bytes.data(), w.bytes.size()));
  w.put_bytes(kEnd, 8);
  // Write to a temporary file and rename: a crash while saving never leaves half a map in place.
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("map file " + file.string() + ": cannot open for writing");
    out.write(reinterpret_cast<const char*>(w.bytes.data()), static_cast<std::streamsize>(w.bytes.size()));
    if (!out) throw std::runtime_error("map file " + file.string() + ": write failed");
  }
  std::filesystem::rename(tmp, file);
}

void read_map_file(const std::filesystem::path& file, const CameraIntrinsics& camera, SlamMap& out) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("map file " + file.string() + ": cannot open");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string name = file.string();
  if (bytes.size() < 8 + 4 + 16 || std::memcmp(bytes.data(), kMagic, 8) != 0) {
    throw std::runtime_error("map file " + name + ": not a LaboDrone map (bad magic or too short)");
  }
  if (std::memcmp(bytes.data() + bytes.size() - 8, kEnd, 8) != 0) {
    throw std::runtime_error("map file " + name + ": truncated (end marker missing, " + std::to_string(bytes.size()) + " bytes)");
  }
  const std::size_t body = bytes.size() - 16;
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body, 8);
  if (stored != fnv1a(bytes.data(), body)) throw std::runtime_error("map file " + name + ": corrupted (checksum mismatch)");

  Reader r(bytes, body, name);
  std::uint8_t magic[8];
  r.get_bytes(magic, 8, "magic");
  const auto version = r.get<std::uint32_t>("version");
  if (version < kOldestReadable || version > kVersion) {
    r.fail("version " + std::to_string(version) + ", expected " + std::to_string(kOldestReadable) + " to " + std::to_string(kVersion));
  }
  const bool with_gravity = version >= 3;
  const std::vector<double> expected = camera_numbers(camera);
  static constexpr const char* kCameraFields[] = {"width", "height", "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double v = r.get<double>("camera");
    if (!(std::abs(v - expected[i]) <= 1e-9 * std::max(1.0, std::abs(expected[i])))) {
      r.fail(std::string("built with another camera: ") + kCameraFields[i] + " = " + std::to_string(v) + ", this camera has " +
             std::to_string(expected[i]));
    }
  }
  out.clear();
  const std::uint32_t n_kf = r.count("keyframe", 100000);
  std::vector<std::size_t> features_of(n_kf);
  for (std::uint32_t k = 0; k < n_kf; ++k) {
    Keyframe kf;
    kf.t = r.finite("keyframe time");
    kf.T_cam_map = get_pose(r);
    const std::uint32_t n_f = r.count("feature", 100000);
    kf.frame.features.resize(n_f);
    kf.frame.descriptors.resize(n_f);
    std::vector<PointId> links(n_f);
    for (std::uint32_t i = 0; i < n_f; ++i) {
      Feature& f = kf.frame.features[i];
      f.px.x() = r.finite("feature");
      f.px.y() = r.finite("feature");
      f.image_px.x() = r.get<float>("feature");
      f.image_px.y() = r.get<float>("feature");
      f.level = r.get<std::int32_t>("feature level");
      if (f.level < 0 || f.level > 7) r.fail("feature level " + std::to_string(f.level) + " out of range");
      f.response = r.get<float>("feature");
      r.get_bytes(kf.frame.descriptors[i].data(), 32, "descriptor");
      links[i] = r.get<PointId>("feature point");
    }
    const auto rows = r.get<std::int32_t>("small image"), cols = r.get<std::int32_t>("small image");
    if (rows < 0 || cols < 0 || rows > 256 || cols > 256) r.fail("small image size out of range");
    if (rows > 0 && cols > 0) {
      kf.small_image.create(rows, cols, CV_32F);
      r.get_bytes(kf.small_image.ptr<float>(0), static_cast<std::size_t>(rows * cols) * sizeof(float), "small image");
    }
    if (with_gravity) kf.down_cam = get_direction(r, "keyframe gravity direction");
    features_of[k] = n_f;
    const int id = out.add_keyframe(std::move(kf));
    out.keyframes_mutable()[static_cast<std::size_t>(id)].point_of_feature = std::move(links);
  }
  const std::uint32_t n_p = r.count("point", 10000000);
  const auto next_id = r.get<PointId>("next point id");
  for (std::uint32_t i = 0; i < n_p; ++i) {
    MapPoint p;
    p.id = r.get<PointId>("point id");
    if (p.id < 0 || p.id >= next_id) r.fail("point id " + std::to_string(p.id) + " out of range");
    for (int c = 0; c < 3; ++c) p.p_map[c] = r.finite("point position");
    r.get_bytes(p.descriptor.data(), 32, "point descriptor");
    p.reference_keyframe = r.get<std::int32_t>("point");
    p.reference_level = r.get<std::int32_t>("point");
    p.reference_distance = r.finite("point");
    const std::uint32_t n_o = r.count("observation", n_kf);
    for (std::uint32_t o = 0; o < n_o; ++o) {
      const auto kf = r.get<std::int32_t>("observation"), f = r.get<std::int32_t>("observation");
      if (kf < 0 || static_cast<std::uint32_t>(kf) >= n_kf || f < 0 || static_cast<std::size_t>(f) >= features_of[static_cast<std::size_t>(kf)]) {
        r.fail("observation of a keyframe feature that does not exist");
      }
      p.observations.push_back({kf, f});
    }
    out.points_mutable().emplace(p.id, std::move(p));
  }
  const std::uint32_t n_loops = r.count("loop edge", 100000);
  for (std::uint32_t i = 0; i < n_loops; ++i) {
    LoopEdge e;
    e.current = r.get<std::int32_t>("loop edge");
    e.loop = r.get<std::int32_t>("loop edge");
    if (e.current < 0 || e.loop < 0 || static_cast<std::uint32_t>(e.current) >= n_kf || static_cast<std::uint32_t>(e.loop) >= n_kf) {
      r.fail("loop edge between keyframes that do not exist");
    }
    e.measured.scale = r.finite("loop edge scale");
    if (!(e.measured.scale > 0)) r.fail("loop edge scale must be positive");
    for (int row = 0; row < 3; ++row) {
      for (int c = 0; c < 3; ++c) e.measured.R(row, c) = r.finite("loop edge rotation");
    }
    if ((e.measured.R * e.measured.R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6) r.fail("loop edge rotation is not a rotation");
    for (int c = 0; c < 3; ++c) e.measured.t[c] = r.finite("loop edge translation");
    out.add_loop_edge(e);
  }
  if (with_gravity) {
    if (const auto down = get_direction(r, "map gravity direction")) out.set_down_map(*down);
  }
  if (r.position() != body) r.fail("unexpected bytes after the last section");
  // Keyframe links must point at points that exist.
  for (Keyframe& kf : out.keyframes_mutable()) {
    for (PointId& id : kf.point_of_feature) {
      if (id != kNoPoint && !out.point(id)) r.fail("keyframe feature linked to a missing point");
    }
  }
  out.set_next_point_id(next_id);
}

}  // namespace labo::slam
