#pragma once
// Where the source tree is (config/, web/, assets/, tests/data/), for default paths. Compiled into one
// translation unit only, so the other objects do not depend on the checkout's location.
#include <filesystem>

namespace labo {

std::filesystem::path source_root();

}  // namespace labo
