#pragma once
// `--drone sim|ardrone[:HOST]|tello[:HOST]|replay:FILE`: which DroneLink the runtime flies, and
// everything it needs alive (the emulator and simulated lab for sim, the flight software, the
// runtime's threads).
#include <memory>
#include <string>

#include "core/log.hpp"
#include "server/app_config.hpp"
#include "server/lab/flight_service.hpp"

namespace labo::server {

struct DroneSpec {
  enum class Kind { Sim, Ardrone, Tello, Replay };
  Kind kind = Kind::Sim;
  std::string host = "192.168.1.1";  // ardrone (tello: 192.168.10.1)
  std::string file;                  // replay
};

// Throws UsageError naming the accepted forms.
DroneSpec parse_drone_spec(const std::string& text);
std::string describe(const DroneSpec& spec);

class DroneBackend {
 public:
  virtual ~DroneBackend() = default;
  virtual FlightService& flight() = 0;
};

// Builds and starts the backend; throws std::runtime_error when a part is missing or cannot start.
std::unique_ptr<DroneBackend> make_drone_backend(const DroneSpec& spec, const AppConfig& config, Logger log);

}  // namespace labo::server
