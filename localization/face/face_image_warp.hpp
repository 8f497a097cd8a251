#pragma once
// The face front end's per-frame resampling without allocating: the landmark crop (cv::warpAffine)
// and the frontal view (cv::remap), both bilinear with the border replicated, pixel for pixel as
// OpenCV 4.6 computes them for 8-bit grey images (each of those OpenCV calls allocates its scratch
// blocks and thread-pool work on every call; test "face front end: a tracked frame allocates nothing,
// a detector frame only the detector's").
// OpenCV places each output pixel's source position on a 1/32 px grid (fixed point) and blends the
// four neighbours with integer weights (32 - fx or fx) (32 - fy or fy) over 2^10, rounded half up;
// neighbours beyond the image take its nearest border pixel. tests/localization/face/face_image_warp_test.cpp
// compares both with OpenCV on random images, transforms and maps.
#include <opencv2/core.hpp>

namespace labo::face {

// cv::warpAffine(src, dst, M, size, cv::INTER_LINEAR, cv::BORDER_REPLICATE) for CV_8UC1: M maps source
// pixels to output pixels (OpenCV inverts it as it does). dst becomes `size`; see sized_view for
// keeping its buffer when the size changes from frame to frame.
void warp_affine_8u(const cv::Mat& src, const cv::Matx23d& M, cv::Size size, cv::Mat& dst);

// cv::remap(src, dst, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE) for CV_8UC1 and CV_32FC1
// maps of one size, computed on every call (the maps change every frame). dst must not be src.
void remap_8u(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& dst);

// `view` becomes the top-left `size` of `storage` (a region of it, same type), `storage` grown (by a
// quarter more than needed) only when too small: images whose size changes every frame by a few
// pixels then reuse one buffer. Returns `view`.
cv::Mat& sized_view(cv::Mat& storage, cv::Size size, int type, cv::Mat& view);

}  // namespace labo::face
