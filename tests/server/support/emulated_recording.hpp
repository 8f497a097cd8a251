#pragma once
// A real flight recording for the replay tests: the AR.Drone driver recording a flight of the tiny
// emulated vehicle on loopback (navdata, H.264 video, notes), about `seconds` long. Tests only.
#include <chrono>
#include <filesystem>
#include <thread>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"

namespace labo::server::test {

inline void record_emulated_flight(const std::filesystem::path& file, double seconds) {
  labo::test::TinyVehicle vehicle;
  ardrone2::ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  ardrone2::ArdroneEmulator emulator(vehicle, es, Logger("test", LogLevel::Off));
  emulator.start();
  ardrone2::ArdroneLinkSettings ls = labo::test::link_settings_for(emulator);
  ls.recording = file;
  ardrone2::ArdroneLink link(ls, Logger("test", LogLevel::Off));
  link.start();
  link.takeoff();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  link.stop();
  emulator.stop();
}

}  // namespace labo::server::test
