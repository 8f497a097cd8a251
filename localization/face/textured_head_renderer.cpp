#include "localization/face/textured_head_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "localization/face/portrait.hpp"

namespace labo::face {

namespace {

// The point of the mesh (vertices in the photograph's camera `cam_vertices`, projected to `uv`) under
// photograph pixel `p`: the nearest front triangle containing it, by barycentric interpolation.
// Returns the barycentric combination of `face_vertices`, NaN when no triangle contains `p`.
Eigen::Vector3d mesh_point_under(const Eigen::Vector2d& p, const Eigen::Matrix2Xd& uv,
                                 const std::vector<Eigen::Vector3d>& cam_vertices,
                                 const std::vector<Eigen::Vector3d>& face_vertices,
                                 const std::vector<std::array<int, 3>>& triangles) {
  double best_depth = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  for (const auto& tri : triangles) {
    const Eigen::Vector2d a = uv.col(tri[0]), b = uv.col(tri[1]), c = uv.col(tri[2]);
    const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(det) < 1e-9) continue;
    const double l1 = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / det;
    const double l2 = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / det;
    const double l0 = 1 - l1 - l2;
    if (l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6) continue;
    const auto v = [&](int i) { return static_cast<std::size_t>(tri[static_cast<std::size_t>(i)]); };
    const double depth = l0 * cam_vertices[v(0)].z() + l1 * cam_vertices[v(1)].z() + l2 * cam_vertices[v(2)].z();
    if (depth < best_depth) {
      best_depth = depth;
      best = l0 * face_vertices[v(0)] + l1 * face_vertices[v(1)] + l2 * face_vertices[v(2)];
    }
  }
  return best;
}

}  // namespace

IdealPinhole portrait_lens(const cv::Size& size, double interocular_px, double ipd_m) {
  // The photographer's distance is unknown; a portrait is taken from a metre or more, where the
  // perspective is weak. Placing the face at kPortraitDistanceM whatever the picture's size keeps a
  // tight crop of a group photograph from being textured as if seen from a few centimetres.
  constexpr double kPortraitDistanceM = 1.5;
  const double f = kPortraitDistanceM * interocular_px / ipd_m;
  return {f, f, size.width / 2.0, size.height / 2.0};
}

TexturedHead texture_head_from_photo(FacePoseEstimator& estimator, const Candide3Model& candide,
                                     const cv::Mat& photo_gray, double ipd_m) {
  const PortraitLimits limits = portrait_limits(estimator.config());
  PortraitFace face = find_portrait_face(estimator, photo_gray, limits);
  if (!face.serves()) throw std::runtime_error("head texture refused: " + face.reason);
  const Eigen::Matrix2Xd& lm68 = face.landmarks;
  const IdealPinhole cam = portrait_lens(photo_gray.size(), face.interocular_px, ipd_m);
  const FaceLandmarkModel& model = estimator.model();
  Eigen::Matrix2Xd pixels(2, model.size());
  for (int i = 0; i < model.size(); ++i) pixels.col(i) = lm68.col(model.landmark_ids()[static_cast<std::size_t>(i)]);
  const ShapeFit fit = fit_shape(model, pixels, cam, ipd_m);
  check_portrait_angles(face, head_angles(fit.T_cam_face.linear()), limits);
  if (!face.serves()) throw std::runtime_error("head texture refused: " + face.reason);

  TexturedHead head;
  head.texture = photo_gray.clone();
  head.shape_params = fit.shape_params;
  head.interpupillary_distance_m = ipd_m;
  const std::vector<double> tau(fit.shape_params.data(), fit.shape_params.data() + fit.shape_params.size());
  const auto vertices = candide.deformed(tau);
  const double mpu = model.metres_per_unit(fit.shape_params, ipd_m);
  head.uv.resize(2, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    head.uv.col(static_cast<Eigen::Index>(v)) = cam.project(fit.T_cam_face * (vertices[v] * mpu));
  }
  std::vector<Eigen::Vector3d> face_m(vertices.size()), cam_m(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    face_m[v] = vertices[v] * mpu;
    cam_m[v] = fit.T_cam_face * face_m[v];
  }
  head.landmarks_face_m.resize(3, lm68.cols());
  for (Eigen::Index i = 0; i < lm68.cols(); ++i) {
    head.landmarks_face_m.col(i) = mesh_point_under(lm68.col(i), head.uv, cam_m, face_m, candide.triangles());
  }
  // The head's metric scale: the photograph's eyes, where its landmarks lie on the mesh, `ipd_m` apart.
  // The fit places the mesh's eye vertices, not the eyes themselves, at that distance; on a small or
  // unusual face they miss the photograph's eyes by a few pixels, and the drawn eyes then stood up to
  // 6 % closer or farther than the person's interpupillary distance, a scale no registration can see
  // (every distance off by as much).
  const Eigen::Vector3d right = head.landmarks_face_m.middleCols(36, 6).rowwise().mean();
  const Eigen::Vector3d left = head.landmarks_face_m.middleCols(42, 6).rowwise().mean();
  if (right.allFinite() && left.allFinite() && (left - right).norm() > 0) {
    head.scale = ipd_m / (left - right).norm();
    head.landmarks_face_m *= head.scale;
  }
  return head;
}

std::vector<Eigen::Vector3d> head_vertices_m(const Candide3Model& candide, const TexturedHead& head) {
  const std::vector<double> tau(head.shape_params.data(), head.shape_params.data() + head.shape_params.size());
  std::vector<Eigen::Vector3d> vertices = candide.deformed(tau);
  // The same metric scale as the estimator's landmark model: eye centres `ipd` apart.
  const FaceLandmarkModel lm = make_face_landmark_model(candide, load_ibug68_mapping(default_ibug68_mapping_path()));
  const double mpu = lm.metres_per_unit(head.shape_params, head.interpupillary_distance_m);
  for (auto& v : vertices) v *= mpu * head.scale;
  return vertices;
}

TexturedHeadRenderer::TexturedHeadRenderer(const Candide3Model& candide, TexturedHead head, const PinholeCamera& camera)
    : triangles_(candide.triangles()), head_(std::move(head)), camera_(camera) {
  if (head_.texture.empty() || head_.texture.type() != CV_8UC1) throw std::invalid_argument("head renderer: texture must be 8-bit grey");
  vertices_m_ = head_vertices_m(candide, head_);
  // Distortion maps: for every distorted (real) pixel, the ideal pixel it shows.
  const auto& k = camera_.intrinsics();
  map_x_.create(k.height, k.width, CV_32FC1);
  map_y_.create(k.height, k.width, CV_32FC1);
  for (int y = 0; y < k.height; ++y) {
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector2d n = camera_.undistort({(x - k.cx) / k.fx, (y - k.cy) / k.fy});
      map_x_.at<float>(y, x) = static_cast<float>(k.fx * n.x() + k.cx);
      map_y_.at<float>(y, x) = static_cast<float>(k.fy * n.y() + k.cy);
    }
  }
}

void TexturedHeadRenderer::render(const Eigen::Isometry3d& T_cam_face, cv::Mat& image) {
  const auto& k = camera_.intrinsics();
  if (image.type() != CV_8UC1 || image.cols != k.width || image.rows != k.height) {
    throw std::invalid_argument("head renderer: image must be 8-bit grey of the camera's size");
  }
  // Draw in ideal (undistorted) pixels over an undistorted copy of the background, then distort.
  // The ideal canvas is larger than the image so that wide-angle corners are covered.
  const int pad_x = k.width / 2, pad_y = k.height / 2;
  ideal_.create(k.height + 2 * pad_y, k.width + 2 * pad_x, CV_8UC1);
  ideal_.setTo(0);
  mask_.create(ideal_.size(), CV_8UC1);
  mask_.setTo(0);
  std::vector<Eigen::Vector3d> cam(vertices_m_.size());
  std::vector<cv::Point2f> px(vertices_m_.size());
  for (std::size_t v = 0; v < vertices_m_.size(); ++v) {
    cam[v] = T_cam_face * vertices_m_[v];
    if (cam[v].z() < 0.05) return;  // head (partly) behind the camera: draw nothing
    px[v] = cv::Point2f(static_cast<float>(k.fx * cam[v].x() / cam[v].z() + k.cx + pad_x),
                        static_cast<float>(k.fy * cam[v].y() / cam[v].z() + k.cy + pad_y));
  }
  // Painter's algorithm: far triangles first.
  std::vector<std::size_t> order(triangles_.size());
  std::iota(order.begin(), order.end(), 0);
  const auto depth = [&](std::size_t t) {
    const auto& tri = triangles_[t];
    return cam[static_cast<std::size_t>(tri[0])].z() + cam[static_cast<std::size_t>(tri[1])].z() + cam[static_cast<std::size_t>(tri[2])].z();
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depth(a) > depth(b); });
  const cv::Rect canvas(0, 0, ideal_.cols, ideal_.rows);
  for (std::size_t t : order) {
    const auto& tri = triangles_[t];
    cv::Point2f dst[3], src[3];
    for (int i = 0; i < 3; ++i) {
      const auto v = static_cast<std::size_t>(tri[static_cast<std::size_t>(i)]);
      dst[i] = px[v];
      src[i] = cv::Point2f(static_cast<float>(head_.uv(0, static_cast<Eigen::Index>(v))),
                           static_cast<float>(head_.uv(1, static_cast<Eigen::Index>(v))));
    }
    // Back faces of the closed front surface: skip triangles seen edge-on or from behind.
    const cv::Point2f e1 = dst[1] - dst[0], e2 = dst[2] - dst[0];
    const cv::Point2f s1 = src[1] - src[0], s2 = src[2] - src[0];
    const float area = e1.x * e2.y - e1.y * e2.x, src_area = s1.x * s2.y - s1.y * s2.x;
    if (area * src_area <= 0) continue;
    const cv::Rect box = cv::boundingRect(std::vector<cv::Point2f>(dst, dst + 3)) & canvas;
    if (box.area() <= 0) continue;
    cv::Point2f local[3];
    cv::Point ipts[3];
    for (int i = 0; i < 3; ++i) {
      local[i] = dst[i] - cv::Point2f(static_cast<float>(box.x), static_cast<float>(box.y));
      ipts[i] = cv::Point(cvRound(local[i].x * 16), cvRound(local[i].y * 16));
    }
    const cv::Mat A = cv::getAffineTransform(src, local);
    cv::warpAffine(head_.texture, warped_, A, box.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    cv::Mat tri_mask = cv::Mat::zeros(box.size(), CV_8UC1);
    cv::fillConvexPoly(tri_mask, ipts, 3, cv::Scalar(255), cv::LINE_AA, 4);
    // Grow the mask by a pixel so neighbouring triangles leave no seams.
    cv::dilate(tri_mask, tri_mask, cv::Mat());
    warped_.copyTo(ideal_(box), tri_mask);
    mask_(box).setTo(255, tri_mask);
  }
  // Distort the head into the image; where no triangle was drawn the background stays.
  cv::Mat head_img, head_mask;
  cv::Mat mx = map_x_ + static_cast<float>(pad_x), my = map_y_ + static_cast<float>(pad_y);
  cv::remap(ideal_, head_img, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  cv::remap(mask_, head_mask, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  // Soft edge: blend by the interpolated mask.
  cv::Mat out_f, img_f, head_f, alpha;
  image.convertTo(img_f, CV_32F);
  head_img.convertTo(head_f, CV_32F);
  head_mask.convertTo(alpha, CV_32F, 1.0 / 255.0);
  out_f = img_f.mul(1.0 - alpha) + head_f.mul(alpha);
  out_f.convertTo(image, CV_8U);
}

}  // namespace labo::face
