#pragma once
// Shared by the simulated lab's tests: the shipped lab, the stock cameras, a renderer that draws
// nothing worth looking at (for tests about physics and sensors).
#include <opencv2/core.hpp>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo::test {
using namespace labo::sim;

inline const lab::LabDescription& shipped_lab() {
  static const lab::LabDescription lab = lab::load_lab_description(lab::default_lab_path());
  return lab;
}

inline CamerasConfig stock_cameras() {
  return ardrone2_cameras();
}

class GreyRenderer final : public SceneRenderer {
 public:
  void render(CameraId, const SceneState&, cv::Mat& bgr) override {
    bgr.create(360, 640, CV_8UC3);
    bgr.setTo(cv::Scalar(128, 128, 128));
  }
};

}  // namespace labo::test
