#include <catch2/catch.hpp>

#include "localization/estimation/eval/estimation_experiment.hpp"
#include "localization/estimation/eval/model_fit.hpp"
#include "localization/estimation/eval/surrogate_plant.hpp"

using namespace labo;

namespace {
PlantFactory surrogate() {
  return [](unsigned seed, Seconds period) -> std::unique_ptr<EstimationPlant> {
    SurrogatePlantOptions o;
    o.navdata_period = period;
    return std::make_unique<SurrogatePlant>(seed, o);
  };
}
}  // namespace

TEST_CASE("estimation: lockstep experiments on the surrogate plant meet the issue's targets (seed 3)") {
  const EstimationResults r = run_estimation_experiments(surrogate(), 3, EstimatorConfig{}, VisionThresholds{});
  INFO("scale " << r.scale_error_percent << " %, hover " << r.hover_slam.position_rmse_m << " m, servo "
                << r.servo.position_rmse_m << " m, impulse return " << r.impulse_servo.return_time_s << " s");
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
  const ModelFitReport fit = fit_motion_model(plant, MotionModelConstants{}, 0.040, 0.100, 60.0, 2);
  CHECK(fit.fitted.tilt_max_rad == Approx(0.21).epsilon(0.1));        // the plant's 12 deg
  CHECK(fit.fitted.yaw_rate_max_radps == Approx(1.7).epsilon(0.1));   // the plant's 1.7 rad/s
  for (const ModelFitLaw& law : fit.laws) CHECK(law.residual_rms_after <= law.residual_rms_before * 1.01);
}
