#pragma once
// The page's room outline from the lab description the server loaded (its lab file).
#include "drone/lab/lab_description.hpp"
#include "server/lab/flight_service.hpp"

namespace labo::server {

LabOutline lab_outline_from(const lab::LabDescription& lab);

}  // namespace labo::server
