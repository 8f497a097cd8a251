#include "control/lab_pipelines_factory.hpp"

#include "control/face_front_end.hpp"
#include "control/planar_front_end.hpp"
#include "control/slam_front_end.hpp"

namespace labo {

std::unique_ptr<LabPipelines> make_lab_pipelines(const FlightStackSetup& setup, const FrontEndSettings& settings) {
  auto pipelines = std::make_unique<LabPipelines>(setup.lab, setup.estimation, setup.vision);
  const PinholeCamera front(setup.cameras.front), bottom(setup.cameras.bottom);
  for (const PlanarTarget& instrument : setup.lab.instruments) {
    if (instrument.template_path.empty()) continue;  // cannot be seen, only modelled
    pipelines->set_instrument_front_end(instrument.id,
                                        std::make_unique<PlanarFrontEnd>(instrument, front, setup.vision, settings.planar));
  }
  if (!setup.lab.platform.template_path.empty())
    pipelines->set_platform_front_end(std::make_unique<PlanarFrontEnd>(setup.lab.platform, bottom, setup.vision, settings.planar));
  pipelines->set_slam_front_end(std::make_unique<SlamSystemFrontEnd>(std::make_unique<slam::SlamSystem>(front, settings.slam)));
  if (settings.with_face)
    pipelines->set_face_front_end(std::make_unique<FaceFrontEnd>(std::make_unique<face::FacePoseEstimator>(settings.face, front)));
  return pipelines;
}

}  // namespace labo
