#include <boost/asio/ip/address.hpp>

#include "core/cli_args.hpp"
#include "server/runtime/drone_backend.hpp"

namespace labo {

DroneSpec parse_drone_spec(const std::string& text) {
  DroneSpec spec;
  if (text == "sim") return spec;
  if (text == "ardrone" || text.rfind("ardrone:", 0) == 0) {
    spec.kind = DroneSpec::Kind::Ardrone;
    if (text.size() > 8) {
      spec.host = text.substr(8);
      boost::system::error_code ec;
      boost::asio::ip::make_address(spec.host, ec);
      if (ec) throw UsageError("--drone: '" + spec.host + "' is not an IP address (ardrone:HOST)");
    }
    return spec;
  }
  if (text.rfind("replay:", 0) == 0 && text.size() > 7) {
    spec.kind = DroneSpec::Kind::Replay;
    spec.file = text.substr(7);
    return spec;
  }
  throw UsageError("--drone: '" + text + "' is not sim, ardrone, ardrone:HOST or replay:FILE");
}

std::string describe(const DroneSpec& spec) {
  switch (spec.kind) {
    case DroneSpec::Kind::Sim: return "simulated lab on loopback";
    case DroneSpec::Kind::Ardrone: return "AR.Drone 2.0 at " + spec.host;
    case DroneSpec::Kind::Replay: return "replay of " + spec.file;
  }
  return "?";
}

}  // namespace labo
