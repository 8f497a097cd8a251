#include <catch2/catch.hpp>

#include "core/source_tree.hpp"
#include "drone/sim/sim_setup.hpp"
#include "bench/estimation/estimation_experiment.hpp"
#include "bench/estimation/lab_plant.hpp"
#include "bench/estimation/model_fit.hpp"
#include "bench/estimation/surrogate_plant.hpp"
#include "bench/estimation/truth_vision_pipeline.hpp"

using namespace labo;
using namespace labo::sim;
using namespace labo::bench;

namespace {
PlantFactory surrogate() {
  return [](const PlantRequest& request) -> std::unique_ptr<EstimationPlant> {
    SurrogatePlantOptions o;
    o.navdata_period = request.navdata_period;
    return std::make_unique<SurrogatePlant>(request.seed, o);
  };
}

PipelineKind truth_vision() {
  return {"truth", false, [](const estimation::EstimatorConfig& c, const EstimationPlant& plant, unsigned seed) -> std::unique_ptr<EstimationPipeline> {
            return std::make_unique<TruthVisionPipeline>(c, VisionThresholds{}, plant, seed);
          }};
}
}  // namespace

TEST_CASE("estimation: lockstep experiments on the surrogate plant meet the estimation targets (seed 3)") {
  const EstimationResults r = run_estimation_experiments(surrogate(), truth_vision(), 3, estimation::EstimatorConfig{});
  INFO("scale " << r.scale_error_percent << " %, hover " << r.hover_slam.position_rmse_m << " m, servo "
                << r.servo.position_rmse_m << " m, impulse return " << r.impulse_servo.return_time_s << " s");
  CHECK(r.scale_estimated);
  CHECK(r.scale_error_percent < 3.0);
  CHECK(r.hover_slam.position_rmse_m < 0.05);
  CHECK(r.servo.position_rmse_m < 0.08);
  CHECK(r.impulse_servo.returned);
  CHECK(r.impulse_servo.return_time_s <= 5.0);
  CHECK(r.impulse_dead_reckoning.returned);
  CHECK_FALSE(r.impulse_paper_rule.returned);  // the paper's Fig. 8, reproduced
  CHECK(r.controller_input_error_compensated_m < r.controller_input_error_uncompensated_m);
}

TEST_CASE("estimation: the model fit recovers the surrogate's yaw-rate and tilt limits") {
  SurrogatePlant plant(5);
  const ModelFitReport fit = fit_motion_model(plant, estimation::MotionModelConstants{}, 60.0, 2);
  CHECK(fit.fitted.tilt_max_rad == Approx(0.21).epsilon(0.1));        // the plant's 12 deg
  CHECK(fit.fitted.yaw_rate_max_radps == Approx(1.7).epsilon(0.1));   // the plant's 1.7 rad/s
  for (const ModelFitLaw& law : fit.laws) CHECK(law.residual_rms_after <= law.residual_rms_before * 1.01);
}

namespace {
PlantFactory lab_plant() {
  auto inputs = std::make_shared<LabPlantInputs>();
  SimInputs sim = load_sim_inputs(source_root() / "config" / "default.json");
  inputs->lab = std::move(sim.lab);
  inputs->cameras = sim.cameras;
  inputs->sim = sim.sim;
  return [inputs](const PlantRequest& request) -> std::unique_ptr<EstimationPlant> {
    return std::make_unique<LabPlant>(*inputs, request);
  };
}
}  // namespace

TEST_CASE("estimation: the lab plant takes off, then delivers navdata at the link's rate and frames only on request") {
  const PlantFactory make = lab_plant();
  for (const bool video : {false, true}) {
    auto plant = make(PlantRequest{4, 1.0 / 200.0, video});
    const GroundTruth start = plant->truth();
    CHECK(start.T_world_body.translation().z() > 0.9);  // hovering about 1 m above the platform
    std::vector<NavdataSample> navdata;
    int frames = 0;
    for (int i = 0; i < 30; ++i) {
      plant->step(1.0 / 30.0, navdata);
      frames += static_cast<int>(plant->frames_of_last_step().size());
      for (const VideoFrame& f : plant->frames_of_last_step()) CHECK(f.bgr.cols == 640);
    }
    CHECK(navdata.size() >= 190);  // 200 Hz full navdata
    CHECK(navdata.size() <= 210);
    CHECK(frames == (video ? Approx(30).margin(2) : Approx(0)));
  }
  auto demo = make(PlantRequest{4, 1.0 / 15.0, false});
  std::vector<NavdataSample> navdata;
  for (int i = 0; i < 30; ++i) demo->step(1.0 / 30.0, navdata);
  CHECK(navdata.size() == Approx(15).margin(1));
  CHECK_THROWS_AS(LabPlant(LabPlantInputs{}, PlantRequest{}), std::invalid_argument);  // no such instrument
}

TEST_CASE("estimation: lockstep experiments on the simulated lab meet the estimation targets (seed 3, truth-derived vision)") {
  const EstimationResults r = run_estimation_experiments(lab_plant(), truth_vision(), 3, estimation::EstimatorConfig{});
  INFO("scale " << r.scale_error_percent << " %, hover " << r.hover_slam.position_rmse_m << " m, servo "
                << r.servo.position_rmse_m << " m, impulse return " << r.impulse_servo.return_time_s << " s");
  CHECK(r.plant == "lab");
  CHECK(r.scale_estimated);
  CHECK(r.scale_error_percent < 5.0);
  CHECK(r.hover_slam.position_rmse_m < 0.05);
  CHECK(r.impulse_servo.returned);
  CHECK(r.impulse_servo.return_time_s <= 5.0);
  CHECK(r.impulse_dead_reckoning.returned);
  CHECK(r.rejections.at("rejected_out_of_order") == 0);  // burst packets of the link are taken
  CHECK(r.controller_input_error_compensated_m < r.controller_input_error_uncompensated_m);
  CHECK(r.bare_floor_fusing_every_velocity.dropouts == 0);
}

// Where the flight software falls short against the rigid-body plant (docs/state-estimation.md,
// "Known limits"): on this seed the scale comes out 3.6 % off (the target is 3 %, met on 15 of seeds
// 1-20), and the bare floor's velocity dropout goes undetected, so dead reckoning across it is as wrong
// as fusing every velocity. This test passes while either falls short; once both hold it fails and
// must become an ordinary check again.
TEST_CASE("estimation: the rigid-body plant's known shortfalls on seed 3 (scale within 3 %, the bare floor's dropout detected)", "[!shouldfail]") {
  const EstimationResults r = run_estimation_experiments(lab_plant(), truth_vision(), 3, estimation::EstimatorConfig{});
  INFO("scale " << r.scale_error_percent << " %, bare floor: " << r.bare_floor.dropouts << " dropouts, error "
                << r.bare_floor.final_error_m << " m (fusing every velocity " << r.bare_floor_fusing_every_velocity.final_error_m << " m)");
  REQUIRE(r.scale_error_percent < 3.0);
  REQUIRE(r.bare_floor.dropouts >= 1);
  REQUIRE(r.bare_floor.final_error_m < r.bare_floor_fusing_every_velocity.final_error_m);
}
