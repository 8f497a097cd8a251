#include "server/runtime/drone_backend.hpp"

#include <stdexcept>

namespace labo {

// The backends need the AR.Drone driver and emulator (branch link), the simulated lab (branch sim)
// and the flight software (branch control). Until those are merged, serve refuses to start with
// a message that says so instead of pretending to fly.
std::unique_ptr<DroneBackend> make_drone_backend(const DroneSpec& spec, const AppConfig&, Logger) {
  throw std::runtime_error("cannot fly the " + describe(spec) +
                           ": this build has no drone driver or flight software yet (branches link, sim, control)");
}

}  // namespace labo
