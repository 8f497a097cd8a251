#include "bench/slam/lens_error.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "core/cli_args.hpp"

namespace labo::bench {

namespace {
double checked(double value, double limit, const char* what, const std::string& text) {
  if (!std::isfinite(value) || std::abs(value) > limit) {
    std::ostringstream m;
    m << "--lens-error " << text << ": " << what << " " << value << " outside +-" << limit;
    throw UsageError(m.str());
  }
  return value;
}
}  // namespace

LensError parse_lens_error(const std::string& text) {
  std::vector<double> values;
  // getline drops an empty last field: "0,0,0,0," would pass as four.
  if (!text.empty() && text.back() == ',') throw UsageError("--lens-error " + text + ": ends with ',' (expected F,C,K1,K2)");
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) throw UsageError("--lens-error " + text + ": '" + item + "' is not a number (expected F,C,K1,K2)");
    values.push_back(v);
  }
  if (values.size() != 4) {
    throw UsageError("--lens-error " + text + ": " + std::to_string(values.size()) +
                     " values; expected four: focal fraction, principal point px, k1, k2 (e.g. 0.03,0,0,0)");
  }
  return {checked(values[0], 0.2, "focal fraction", text), checked(values[1], 50.0, "principal point shift (px)", text),
          checked(values[2], 0.5, "k1", text), checked(values[3], 0.5, "k2", text)};
}

PinholeCamera with_lens_error(const PinholeCamera& camera, const LensError& error) {
  CameraIntrinsics k = camera.intrinsics();
  k.fx *= 1 + error.focal_fraction;
  k.fy *= 1 + error.focal_fraction;
  k.cx += error.principal_px;
  k.cy += error.principal_px;
  k.k1 += error.k1;
  k.k2 += error.k2;
  return PinholeCamera(k);
}

}  // namespace labo::bench
