#include "bench/face/face_gallery_bench.hpp"

#include <algorithm>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/candide3.hpp"
#include "localization/face/group_photo.hpp"

namespace labo::bench {

using face::FaceConfig;
using face::FacePoseEstimator;
using face::GroupPortrait;
using face::interocular_px;
using face::portraits_in_group_photo;

namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

FaceErrors summarise(const std::vector<std::array<double, 6>>& errors, bool use_median) {
  FaceErrors out;
  out.frames = static_cast<int>(errors.size());
  double* fields[6] = {&out.tx_mm, &out.ty_mm, &out.tz_mm, &out.roll_deg, &out.yaw_deg, &out.pitch_deg};
  for (std::size_t k = 0; k < 6; ++k) {
    std::vector<double> column;
    column.reserve(errors.size());
    for (const auto& e : errors) column.push_back(e[k]);
    if (use_median) {
      *fields[k] = median_of(std::move(column));
    } else {
      double sum = 0;
      for (double x : column) sum += x;
      *fields[k] = column.empty() ? 0 : sum / static_cast<double>(column.size());
    }
  }
  return out;
}

struct GalleryFace {
  std::string name;
  bool held_out = false;
  cv::Mat photo_bgr;
  std::string refused;
  double interocular_px = 0;
};

std::vector<GalleryFace> gallery(FacePoseEstimator& estimator, const FaceGalleryOptions& o) {
  std::vector<GalleryFace> faces;
  if (!o.astronaut.empty()) {
    const cv::Mat photo = cv::imread(o.astronaut.string(), cv::IMREAD_COLOR);
    if (photo.empty()) throw std::runtime_error(o.astronaut.string() + ": cannot read the photograph (run scripts/setup.sh)");
    faces.push_back({"astronaut", false, photo, "", 0});
  }
  if (!o.group_photo.empty()) {
    const cv::Mat group = cv::imread(o.group_photo.string(), cv::IMREAD_COLOR);
    if (group.empty()) throw std::runtime_error(o.group_photo.string() + ": cannot read the photograph (run scripts/setup.sh)");
    const auto portraits = portraits_in_group_photo(estimator, group, {.side_interocular = 4.0, .prefix = "solvay"});
    for (std::size_t i = 0; i < portraits.size(); ++i) {
      const GroupPortrait& p = portraits[i];
      faces.push_back({p.name, held_out_of_tuning(static_cast<int>(i) + 1), p.crop_bgr, p.face.reason,
                       p.face.interocular_px});
    }
  }
  if (!o.crops_dir.empty()) {
    std::filesystem::create_directories(o.crops_dir);
    for (const GalleryFace& f : faces) cv::imwrite((o.crops_dir / (f.name + ".png")).string(), f.photo_bgr);
  }
  return faces;
}

}  // namespace

bool held_out_of_tuning(int gallery_rank) { return gallery_rank % 3 == 0; }

FaceGalleryReport run_face_gallery_bench(const FaceConfig& config, const PinholeCamera& camera,
                                         const FaceGalleryOptions& options,
                                         const std::function<void(const std::string&)>& progress) {
  const auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  FaceConfig detect_config = config;
  detect_config.teacher.clear();
  FacePoseEstimator estimator(detect_config, camera);
  FaceGalleryReport report;
  std::vector<std::array<double, 6>> pooled;
  std::vector<double> frame_ms;
  for (GalleryFace& face : gallery(estimator, options)) {
    if (!options.only_face.empty() && face.name != options.only_face) continue;
    if (options.tuning_faces_only && face.held_out) continue;
    if (report.faces_measured >= options.max_faces) break;
    PersonFigures person;
    person.name = face.name;
    person.held_out = face.held_out;
    person.refused = face.refused;
    person.portrait_interocular_px = face.interocular_px;
    if (person.refused.empty()) {
      FaceBenchOptions bench = options.bench;
      bench.texture = face.name;
      bench.texture_bgr = face.photo_bgr;
      try {
        person.report = run_face_bench(config, camera, bench);
      } catch (const std::runtime_error& e) {
        person.refused = e.what();
      }
    }
    if (!person.refused.empty()) {
      say(face.name + ": refused: " + person.refused);
      report.people.push_back(std::move(person));
      continue;
    }
    const FaceBenchReport& r = person.report;
    person.mean = summarise(r.lm_frame_errors, false);
    person.median = summarise(r.lm_frame_errors, true);
    person.detection_rate = r.frames_total ? static_cast<double>(r.frames_tracked) / r.frames_total : 0;
    const auto most = std::max_element(r.lost_reasons.begin(), r.lost_reasons.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    if (most != r.lost_reasons.end()) person.main_lost_reason = most->first;
    pooled.insert(pooled.end(), r.lm_frame_errors.begin(), r.lm_frame_errors.end());
    frame_ms.insert(frame_ms.end(), r.frame_ms.begin(), r.frame_ms.end());
    ++report.faces_measured;
    say(face.name + ": " + std::to_string(r.frames_tracked) + "/" + std::to_string(r.frames_total) +
        " frames posed, LM tz " + std::to_string(person.mean.tz_mm) + " mm, yaw " + std::to_string(person.mean.yaw_deg) +
        " deg, pitch " + std::to_string(person.mean.pitch_deg) + " deg");
    report.people.push_back(std::move(person));
  }
  report.pooled_mean = summarise(pooled, false);
  report.pooled_median = summarise(pooled, true);
  report.frame_ms_median = median_of(std::move(frame_ms));
  return report;
}

}  // namespace labo::bench
