#include <boost/asio/ip/address.hpp>

#include "core/cli_args.hpp"
#include "server/runtime/drone_backend.hpp"

namespace labo::server {

namespace {

// "NAME" or "NAME:HOST" (an IP address) into `spec.host`; false when `text` is not of that name.
bool parse_drone_host(const std::string& text, const std::string& name, DroneSpec& spec) {
  if (text != name && text.rfind(name + ":", 0) != 0) return false;
  if (text.size() > name.size() + 1) {
    spec.host = text.substr(name.size() + 1);
    boost::system::error_code ec;
    boost::asio::ip::make_address(spec.host, ec);
    if (ec) throw UsageError("--drone: '" + spec.host + "' is not an IP address (" + name + ":HOST)");
  }
  return true;
}

}  // namespace

DroneSpec parse_drone_spec(const std::string& text) {
  DroneSpec spec;
  if (text == "sim") return spec;
  if (parse_drone_host(text, "ardrone", spec)) {
    spec.kind = DroneSpec::Kind::Ardrone;
    return spec;
  }
  spec.host = "192.168.10.1";  // the Tello's own access point
  if (parse_drone_host(text, "tello", spec)) {
    spec.kind = DroneSpec::Kind::Tello;
    return spec;
  }
  if (text.rfind("replay:", 0) == 0 && text.size() > 7) {
    spec.kind = DroneSpec::Kind::Replay;
    spec.file = text.substr(7);
    return spec;
  }
  throw UsageError("--drone: '" + text + "' is not sim, ardrone[:HOST], tello[:HOST] or replay:FILE");
}

std::string describe(const DroneSpec& spec) {
  switch (spec.kind) {
    case DroneSpec::Kind::Sim: return "simulated lab on loopback";
    case DroneSpec::Kind::Ardrone: return "AR.Drone 2.0 at " + spec.host;
    case DroneSpec::Kind::Tello: return "Tello (SDK 2.0) at " + spec.host;
    case DroneSpec::Kind::Replay: return "replay of " + spec.file;
  }
  return "?";
}

}  // namespace labo::server
