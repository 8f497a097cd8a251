#include "core/source_tree.hpp"

namespace labo {

std::filesystem::path source_root() { return std::filesystem::path(LABO_SOURCE_DIR); }

}  // namespace labo
