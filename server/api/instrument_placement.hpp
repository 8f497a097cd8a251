#pragma once
// Whether an instrument can stand where an admin places it, by the lab file's outline: its panel and
// housing inside the room, clear of the benches and the platform (an instrument on a bench stands on
// its top). The same rules as the lab file's own instruments (drone/lab/lab_description.cpp).
#include <string>

#include "drone/lab/lab_description.hpp"
#include "server/lab/flight_service.hpp"

namespace labo::server {

// Empty when it fits; else what it runs into.
std::string placement_problem(const lab::InstrumentSpec& instrument, const LabOutline& lab);

}  // namespace labo::server
