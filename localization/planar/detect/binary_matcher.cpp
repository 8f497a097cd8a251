#include "localization/planar/detect/binary_matcher.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace labo::planar {

namespace {

// Hamming distance of two descriptors of `bytes` bytes: 8 bytes at a time, then the rest.
inline int hamming(const unsigned char* a, const unsigned char* b, int bytes) {
  int bits = 0, i = 0;
  for (; i + 8 <= bytes; i += 8) {
    std::uint64_t x = 0, y = 0;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    bits += __builtin_popcountll(x ^ y);
  }
  for (; i < bytes; ++i) bits += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return bits;
}

inline void consider(NearestTwo& n, int d, int t) {
  if (d < n.best_distance) {
    n.second_distance = n.best_distance;
    n.best_distance = d;
    n.best = t;
  } else if (d < n.second_distance) {
    n.second_distance = d;
  }
}

// The searches, each built twice (target_clones): with the POPCNT instruction and without; the loader
// picks the one the CPU runs (one dispatch per call, the distance inlined). ORB's 32 bytes have their
// own, unrolled.
__attribute__((target_clones("popcnt", "default"))) void search_32(const cv::Mat& query, const cv::Mat& train,
                                                                   std::vector<NearestTwo>& out) {
  for (int q = 0; q < query.rows; ++q) {
    std::uint64_t a[4];
    std::memcpy(a, query.ptr<unsigned char>(q), 32);
    NearestTwo& n = out[static_cast<std::size_t>(q)];
    for (int t = 0; t < train.rows; ++t) {
      std::uint64_t b[4];
      std::memcpy(b, train.ptr<unsigned char>(t), 32);
      const int d = __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) + __builtin_popcountll(a[2] ^ b[2]) +
                    __builtin_popcountll(a[3] ^ b[3]);
      consider(n, d, t);
    }
  }
}

__attribute__((target_clones("popcnt", "default"))) void search_any(const cv::Mat& query, const cv::Mat& train,
                                                                    std::vector<NearestTwo>& out) {
  for (int q = 0; q < query.rows; ++q) {
    const unsigned char* a = query.ptr<unsigned char>(q);
    NearestTwo& n = out[static_cast<std::size_t>(q)];
    for (int t = 0; t < train.rows; ++t) consider(n, hamming(a, train.ptr<unsigned char>(t), query.cols), t);
  }
}

}  // namespace

void nearest_two_hamming(const cv::Mat& query, const cv::Mat& train, std::vector<NearestTwo>& out) {
  if ((!query.empty() && query.type() != CV_8UC1) || (!train.empty() && train.type() != CV_8UC1) ||
      (!query.empty() && !train.empty() && query.cols != train.cols)) {
    throw std::invalid_argument("nearest_two_hamming: descriptors must be CV_8UC1 rows of the same width");
  }
  NearestTwo none;
  none.best_distance = 1 << 30;
  out.assign(static_cast<std::size_t>(query.rows), none);
  if (train.empty()) return;
  if (query.cols == 32) {
    search_32(query, train, out);
  } else {
    search_any(query, train, out);
  }
}

}  // namespace labo::planar
