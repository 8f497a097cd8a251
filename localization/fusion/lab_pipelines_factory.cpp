#include "localization/fusion/lab_pipelines_factory.hpp"

#include "localization/fusion/face_front_end.hpp"
#include "localization/fusion/planar_front_end.hpp"
#include "localization/fusion/slam_front_end.hpp"

namespace labo::fusion {

std::unique_ptr<LabPipelines> make_lab_pipelines(const LabGeometry& lab, const CamerasConfig& cameras, const VisionThresholds& vision,
                                                 const estimation::EstimatorConfig& estimation, const FrontEndSettings& settings) {
  auto pipelines = std::make_unique<LabPipelines>(lab, estimation, vision);
  const PinholeCamera front(cameras.front), bottom(cameras.bottom);
  for (const PlanarTarget& instrument : lab.instruments) {
    if (instrument.template_path.empty()) continue;  // cannot be seen, only modelled
    pipelines->set_instrument_front_end(instrument.id,
                                        std::make_unique<PlanarFrontEnd>(instrument, front, vision, settings.planar));
  }
  // Instruments placed while flying get the same front-end (the settings are copied: the caller's may go).
  pipelines->set_instrument_front_end_factory([front, vision, planar = settings.planar](const PlanarTarget& instrument) {
    return std::make_unique<PlanarFrontEnd>(instrument, front, vision, planar);
  });
  if (!lab.platform.template_path.empty())
    pipelines->set_platform_front_end(std::make_unique<PlanarFrontEnd>(lab.platform, bottom, vision, settings.planar));
  pipelines->set_slam_front_end(std::make_unique<SlamSystemFrontEnd>(std::make_unique<slam::SlamSystem>(front, settings.slam)));
  if (settings.with_face)
    pipelines->set_face_front_end(std::make_unique<FaceFrontEnd>(std::make_unique<face::FacePoseEstimator>(settings.face, front)));
  return pipelines;
}

}  // namespace labo::fusion
