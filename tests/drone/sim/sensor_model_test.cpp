// SensorModel: the ultrasound steps at the platform's edge, the bottom camera's velocity fails over
// bare floor and low down, the yaw drifts slowly, flat trim removes the attitude offset, and the
// same seed gives the same readings bit for bit.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "drone/sim/sensor_model.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::sim;

namespace {

QuadrotorState flying_at(const Eigen::Vector3d& p, const Eigen::Vector3d& v = Eigen::Vector3d::Zero(), double yaw = 0) {
  QuadrotorState s;
  s.phase = FirmwarePhase::Flying;
  s.position_m = p;
  s.velocity_mps = v;
  s.yaw_rad = yaw;
  return s;
}

// Samples `seconds` of readings at 200 Hz for a fixed true state.
std::vector<VehicleTelemetry> sample(SensorModel& m, QuadrotorState s, double seconds) {
  std::vector<VehicleTelemetry> out;
  for (int i = 0; i < static_cast<int>(seconds * 200); ++i) {
    s.t += 0.005;
    m.update(s, 0.005);
    out.push_back(m.telemetry());
  }
  return out;
}

double mean_altitude(const std::vector<VehicleTelemetry>& v) {
  double sum = 0;
  for (const auto& t : v) sum += t.nav.altitude_m;
  return sum / static_cast<double>(v.size());
}

}  // namespace

TEST_CASE("sim sensors: the ultrasound steps by the platform's thickness at its edge", "[sim][sensors]") {
  SensorNoise noise;
  noise.ultrasound_outlier_probability = 0;
  SensorModel m(noise, test::shipped_lab(), 3);
  // The platform is 0.6 m wide around the origin, 0.10 m high: flying level at z = 1.0 m across its edge.
  const double over = mean_altitude(sample(m, flying_at({0.25, 0.0, 1.0}), 1.0));
  const double beside = mean_altitude(sample(m, flying_at({0.35, 0.0, 1.0}), 1.0));
  CHECK(over == Approx(0.90).margin(0.005));
  CHECK(beside == Approx(1.00).margin(0.005));
  CHECK(beside - over == Approx(0.10).margin(0.01));
  // Over a bench top (0.9 m) the altitude is to the bench.
  CHECK(mean_altitude(sample(m, flying_at({6.1, -0.5, 1.8}), 1.0)) == Approx(0.90).margin(0.005));
}

TEST_CASE("sim sensors: the ultrasound holds each echo for 40 ms, is noisy and has spurious short echoes", "[sim][sensors]") {
  SensorNoise noise;
  noise.ultrasound_outlier_probability = 0.05;
  SensorModel m(noise, test::shipped_lab(), 4);
  const auto v = sample(m, flying_at({1.0, 1.0, 1.5}), 40.0);
  int changes = 0, outliers = 0, samples = 0;
  double sq = 0;
  for (std::size_t i = 1; i < v.size(); ++i) {
    if (v[i].nav.altitude_m == v[i - 1].nav.altitude_m) continue;
    ++changes;
    const double e = v[i].nav.altitude_m - 1.5;
    if (std::abs(e) > 0.05) {
      ++outliers;
      CHECK(e < 0);  // an early echo is always shorter
    } else {
      sq += e * e;
      ++samples;
    }
  }
  CHECK(changes == Approx(40 * 25).epsilon(0.02));  // 25 Hz, not 200 Hz
  CHECK(static_cast<double>(outliers) / changes == Approx(0.05).margin(0.02));
  CHECK(std::sqrt(sq / samples) == Approx(noise.ultrasound_noise_m).epsilon(0.15));
}

TEST_CASE("sim sensors: the bottom camera's velocity fails over bare floor and below 0.3 m", "[sim][sensors]") {
  SensorModel m(SensorNoise{}, test::shipped_lab(), 5);
  const Eigen::Vector3d v(0.5, 0.0, 0.0);
  // Textured floor, 1 m up, heading +y: 0.5 m/s along world x is to the right (vy < 0) in the heading frame.
  auto ok = sample(m, flying_at({1.0, -1.5, 1.0}, v, std::numbers::pi / 2), 1.0);
  CHECK(m.velocity_valid());
  double vx = 0, vy = 0;
  for (const auto& t : ok) vx += t.nav.vx_mps / ok.size(), vy += t.nav.vy_mps / ok.size();
  CHECK(vx == Approx(0.0).margin(0.01));
  CHECK(vy == Approx(-0.5).margin(0.01));
  // The bare floor area (x 2.4..3.6, y -2.6..-0.9): the estimate decays towards zero.
  REQUIRE(test::shipped_lab().floor_is_bare(3.0, -1.5));
  auto bare = sample(m, flying_at({3.0, -1.5, 1.0}, v, std::numbers::pi / 2), 1.0);
  CHECK_FALSE(m.velocity_valid());
  CHECK(std::abs(bare.back().nav.vy_mps) < 0.15);
  // Textured again, but 0.2 m above the floor.
  sample(m, flying_at({1.0, -1.5, 0.2}, v, std::numbers::pi / 2), 0.1);
  CHECK_FALSE(m.velocity_valid());
  sample(m, flying_at({1.0, -1.5, 0.35}, v, std::numbers::pi / 2), 0.1);
  CHECK(m.velocity_valid());
}

TEST_CASE("sim sensors: a drone's biases scale and offset its velocity, ultrasound, attitude and IMU", "[sim][sensors]") {
  SensorBiases b;
  b.velocity_scale = 1.05;
  b.velocity_mps = {0.02, -0.01};
  b.ultrasound_scale = 0.98;
  b.ultrasound_offset_m = 0.01;
  b.attitude_rad = {0.004, -0.003};
  b.gyro_radps = {0.01, 0.0, -0.01};
  SensorModel biased(SensorNoise{}, test::shipped_lab(), 5, b), plain(SensorNoise{}, test::shipped_lab(), 5);
  const auto mean_of = [](const std::vector<VehicleTelemetry>& v, auto field) {
    double sum = 0;
    for (const auto& t : v) sum += field(t);
    return sum / static_cast<double>(v.size());
  };
  const QuadrotorState s = flying_at({1.0, -1.5, 1.0}, {0.5, 0.0, 0.0});  // heading +x, textured floor
  const auto with = sample(biased, s, 2.0), without = sample(plain, s, 2.0);
  CHECK(mean_of(with, [](const auto& t) { return t.nav.vx_mps; }) == Approx(1.05 * 0.5 + 0.02).margin(0.005));
  CHECK(mean_of(with, [](const auto& t) { return t.nav.vy_mps; }) == Approx(-0.01).margin(0.005));
  CHECK(mean_altitude(with) == Approx(0.98 * mean_altitude(without) + 0.01).margin(0.003));
  CHECK(mean_of(with, [](const auto& t) { return t.nav.roll_rad; }) - mean_of(without, [](const auto& t) { return t.nav.roll_rad; }) ==
        Approx(0.004).margin(1e-9));
  CHECK(with.back().gyro_body_radps.x() - without.back().gyro_body_radps.x() == Approx(0.01).margin(1e-9));
}

TEST_CASE("sim sensors: the yaw drifts slowly, flat trim removes the roll/pitch offset on the ground", "[sim][sensors]") {
  SensorNoise noise;
  noise.attitude_offset_rad = 0.02;
  SensorModel m(noise, test::shipped_lab(), 6);
  auto first = sample(m, flying_at({1.0, 1.0, 1.0}), 1.0);
  auto later = sample(m, flying_at({1.0, 1.0, 1.0}), 60.0);
  auto mean_yaw = [](const std::vector<VehicleTelemetry>& v, std::size_t from) {
    double s = 0;
    for (std::size_t i = from; i < v.size(); ++i) s += v[i].nav.yaw_rad;
    return s / static_cast<double>(v.size() - from);
  };
  const double drift = mean_yaw(later, later.size() - 200) - mean_yaw(first, 0);
  CHECK(std::abs(drift) > 0.002);  // about 1 deg/min
  CHECK(std::abs(drift) < 0.05);

  auto offset = [](const std::vector<VehicleTelemetry>& v) {
    double r = 0;
    for (const auto& t : v) r += std::abs(t.nav.roll_rad) + std::abs(t.nav.pitch_rad);
    return r / static_cast<double>(v.size());
  };
  QuadrotorState ground;
  ground.position_m = Eigen::Vector3d(1.0, 1.0, 0.0);
  const double before = offset(sample(m, ground, 1.0));
  m.flat_trim(ground);
  const double after = offset(sample(m, ground, 1.0));
  CHECK(after < 0.5 * before);
}

TEST_CASE("sim sensors: the same seed gives the same readings bit for bit, another seed others", "[sim][sensors][determinism]") {
  auto run = [](std::uint64_t seed) {
    SensorModel m(SensorNoise{}, test::shipped_lab(), seed);
    return sample(m, flying_at({1.0, 0.5, 1.2}, {0.3, -0.2, 0.1}, 0.4), 2.0);
  };
  const auto a = run(11), b = run(11), c = run(12);
  REQUIRE(a.size() == b.size());
  bool same = true, differ = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double va[] = {a[i].nav.roll_rad, a[i].nav.yaw_rad, a[i].nav.vx_mps, a[i].nav.altitude_m, a[i].accel_body_mps2.x()};
    const double vb[] = {b[i].nav.roll_rad, b[i].nav.yaw_rad, b[i].nav.vx_mps, b[i].nav.altitude_m, b[i].accel_body_mps2.x()};
    const double vc[] = {c[i].nav.roll_rad, c[i].nav.yaw_rad, c[i].nav.vx_mps, c[i].nav.altitude_m, c[i].accel_body_mps2.x()};
    same = same && std::memcmp(va, vb, sizeof va) == 0;
    differ = differ || std::memcmp(va, vc, sizeof va) != 0;
  }
  CHECK(same);
  CHECK(differ);
}
