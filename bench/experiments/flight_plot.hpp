#pragma once
// CSV and SVG output of a lockstep flight, like the paper's Figs 5-9: x, y, z and yaw over time, the
// estimate coloured by localization source (green SLAM, blue homography, red dead reckoning, purple
// face), the true pose in grey, the desired pose in cyan.
#include <filesystem>
#include <vector>

#include "bench/experiments/lockstep_flight.hpp"

namespace labo::bench {

void write_flight_csv(const std::filesystem::path& file, const std::vector<FlightSample>& samples);
void write_flight_svg(const std::filesystem::path& file, const std::vector<FlightSample>& samples, const std::string& title);

}  // namespace labo::bench
