#pragma once
// Brute-force nearest two neighbours of binary descriptors (ORB, BRISK, AKAZE) by Hamming distance.
// cv::BFMatcher(NORM_HAMMING) counts bits through a table in the distribution's OpenCV build (no
// POPCNT in its baseline): 8.6 ns per 32-byte pair on this machine, 8 ms for 1000 x 1000
// descriptors. Here the count is the CPU's POPCNT instruction when it has one (chosen at load time,
// the portable count otherwise), and the results go into a vector kept by the caller: no allocation
// once it has its size.
#include <vector>

#include <opencv2/core.hpp>

namespace labo::planar {

struct NearestTwo {
  int best = -1;                // row of the nearest train descriptor, -1 when train is empty
  int best_distance = 1 << 30;  // bits
  int second_distance = 1 << 30;  // bits; huge when train has a single row
};

// For each row of `query` (CV_8UC1, one descriptor per row) the nearest two rows of `train` (same
// width). Throws std::invalid_argument when the types or widths differ.
void nearest_two_hamming(const cv::Mat& query, const cv::Mat& train, std::vector<NearestTwo>& out);

}  // namespace labo::planar
