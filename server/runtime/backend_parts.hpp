#pragma once
// What the drone backends build from the configuration: the flight software's setup, the runtime's
// options, and for `--drone sim` the simulated lab and its emulator's loopback settings. Public so
// that a harness composing the same parts (the soak of bench/soak/, which puts faults between the
// emulator and the driver) flies exactly what `labodrone serve` flies.
#include <memory>

#include "control/flight_stack.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "server/app_config.hpp"
#include "server/runtime/flight_runtime.hpp"

namespace labo::server {

using sim::SimulatedLab;


// The lab's geometry, the control, camera, vision and estimation sections, and the real vision
// front-ends on the drone's frames.
control::FlightStackSetup flight_stack_setup(const AppConfig& config);
// The same with other cameras and estimation settings (a Tello's: its camera in front, tello_estimation).
control::FlightStackSetup flight_stack_setup(const AppConfig& config, const CamerasConfig& cameras,
                                             const estimation::EstimatorConfig& estimation);
FlightRuntimeOptions flight_runtime_options(const AppConfig& config);
// The same for an AR.Drone 2.0 (or the emulator) behind `link`: both cameras, and the bit rate the
// link asks of the drone, changed through it.
FlightRuntimeOptions flight_runtime_options(const AppConfig& config, ardrone2::ArdroneLink& link);
// The same for a drone whose video has one camera and no bit-rate setting (`no_bottom_camera` says why).
FlightRuntimeOptions flight_runtime_options(const AppConfig& config, const std::string& drone, const std::string& no_bottom_camera);

// The simulated lab of config.sim, its cameras showing the teacher's face textured from their
// photograph (built here because drone/ cannot call localization/).
std::unique_ptr<SimulatedLab> make_configured_lab(const AppConfig& config);
// config.emulator on 127.0.0.1 with free ports (0), so several servers and tests run side by side.
ardrone2::ArdroneEmulatorSettings loopback_emulator_settings(const AppConfig& config);
// config.link pointed at an emulator (or anything speaking for it) on 127.0.0.1 at these ports.
ardrone2::ArdroneLinkSettings loopback_link_settings(const AppConfig& config, int at_port, int navdata_port, int video_port);

}  // namespace labo::server
