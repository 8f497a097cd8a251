// Steady-state allocations of the vision front-ends: counted by replacing the global operator new in
// this test executable (test_control), on the calling thread only. The planar localizer's tracking
// allocates nothing, nor do the front-ends that wrap it.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <new>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "control/lab_pipelines_factory.hpp"
#include "control/planar_front_end.hpp"
#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"
#include "localization/planar/synthetic_scene.hpp"

namespace {
thread_local std::size_t g_allocations = 0;

void* counted_alloc(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* counted_aligned_alloc(std::size_t size, std::align_val_t align) {
  ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return counted_alloc(size); }
void* operator new[](std::size_t size) { return counted_alloc(size); }
void* operator new(std::size_t size, std::align_val_t align) { return counted_aligned_alloc(size, align); }
void* operator new[](std::size_t size, std::align_val_t align) { return counted_aligned_alloc(size, align); }
// The nothrow forms too (Catch2 registers its tests with them): every form must come from this
// malloc-based family, or a delete here frees what the runtime's own new allocated (ASan reports it).
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(align);
  return std::aligned_alloc(a, (size + a - 1) / a * a);
}
void* operator new[](std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(align);
  return std::aligned_alloc(a, (size + a - 1) / a * a);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

using namespace labo;

namespace {
template <typename F>
std::size_t allocations_of(F&& f) {
  const std::size_t before = g_allocations;
  f();
  return g_allocations - before;
}
}  // namespace

// Until 2026-12-03 the planar localizer's tracking made 93 heap allocations per frame (109 on frames
// where motion blur is modelled), all inside OpenCV calls (found with a backtrace on the counting
// operator new): cv::solvePnPGeneric (IPPE) 82, the corner clipping's vectors 6, cv::GaussianBlur 16,
// cv::pyrDown 3, cv::remap 2. LaboDrone's own allocation-free code replaced them (ippe.hpp,
// image_ops.hpp, planar_localizer.cpp); the frames below cover both refinement models (the
// footprint model, and the sampled one with its smoothing on the frames the panel moved 2 px or more).

TEST_CASE("vision front-ends: tracking a panel allocates nothing") {
  // OpenCV's thread pool splits work differently from call to call, and with it the allocations
  // made on this thread: counted single-threaded, they repeat exactly.
  const int threads = cv::getNumThreads();
  cv::setNumThreads(0);
  const LabGeometry lab = lab_geometry_from(load_lab_description(default_lab_path()));
  const PlanarTarget& osc = lab.instruments.front();
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const cv::Mat templ = cv::imread(osc.template_path.string(), cv::IMREAD_GRAYSCALE);
  const PlanarViewRenderer renderer(camera, make_clutter_background(cv::Size(1200, 1200), 5), 0.0025);

  // The same drone hover seen by: the bare localizer, the front-end, and LabPipelines::on_video.
  const Eigen::Vector3d body = osc.T_world_object.translation() - Eigen::Vector3d(1.4, 0.0, 0.0);
  std::vector<cv::Mat> frames;
  std::vector<VideoFrame> video;
  for (int i = 0; i < 12; ++i) {
    const Eigen::Vector3d b = body + Eigen::Vector3d(0.004 * i, 0.003 * i, 0.0);
    const Eigen::Isometry3d T = (make_pose(b, 0.0) * T_body_cam_front()).inverse() * osc.T_world_object;
    frames.push_back(renderer.render(templ, osc.width_m, osc.height_m, T));
    VideoFrame f;
    f.t = 0.1 + i / 30.0;
    cv::cvtColor(frames.back(), f.bgr, cv::COLOR_GRAY2BGR);
    video.push_back(f);
  }
  PlanarObjectLocalizer bare(load_target_template(osc, PlanarConfig{}), camera,
                             PlanarObjectThresholds::from(VisionThresholds{}, osc.sift_switch_distance_m, osc.sift_min_inliers),
                             PlanarConfig{});
  PlanarFrontEnd front_end(osc, camera, VisionThresholds{}, PlanarConfig{});
  FlightStackSetup setup;
  setup.lab = lab;
  FrontEndSettings settings;
  settings.with_face = false;
  const auto pipelines = make_lab_pipelines(setup, settings);
  pipelines->reset(make_pose(body, 0.0), 0.0);
  PerceptionFocus focus;
  focus.slam = false;
  focus.instrument_id = osc.id;
  pipelines->set_focus(focus);

  // Detection and the first tracked frames warm every buffer up.
  constexpr int kWarmUp = 4;
  for (int i = 0; i < kWarmUp; ++i) {
    bare.process(frames[static_cast<std::size_t>(i)], video[static_cast<std::size_t>(i)].t, 1.4);
    front_end.process(frames[static_cast<std::size_t>(i)], video[static_cast<std::size_t>(i)].t, 1.4);
    pipelines->on_video(video[static_cast<std::size_t>(i)]);
  }
  int footprint_frames = 0, sampled_frames = 0;
  for (std::size_t i = kWarmUp; i < frames.size(); ++i) {
    PlanarResult r;
    const std::size_t by_localizer = allocations_of([&] { r = bare.process(frames[i], video[i].t, 1.4); });
    REQUIRE(r.state == PlanarState::Tracking);
    REQUIRE(r.pose_refined);
    ++(r.footprint_model ? footprint_frames : sampled_frames);
    const std::size_t by_front_end = allocations_of([&] { front_end.process(frames[i], video[i].t, 1.4); });
    REQUIRE(front_end.last_result().state == PlanarState::Tracking);
    const std::size_t by_pipelines = allocations_of([&] { pipelines->on_video(video[i]); });
    INFO("frame " << i << ": localizer " << by_localizer << ", front-end " << by_front_end << ", LabPipelines "
                  << by_pipelines);
    CHECK(by_localizer == 0);
    CHECK(by_front_end == by_localizer);
    CHECK(by_pipelines == by_localizer);
  }
  // Both refinement models ran (the sampled one smooths the frame; the footprint one reads it raw).
  CHECK(footprint_frames > 0);
  CHECK(sampled_frames > 0);
  CHECK(pipelines->instrument().state == TrackState::Tracking);
  cv::setNumThreads(threads);
}
