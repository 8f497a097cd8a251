#include "server/video/rendition.hpp"

namespace labo::server {

std::string_view to_string(Rendition rendition) { return rendition == Rendition::Low ? "low" : "source"; }

std::string_view to_string(RenditionChoice choice) {
  switch (choice) {
    case RenditionChoice::Auto: return "auto";
    case RenditionChoice::Source: return "source";
    case RenditionChoice::Low: return "low";
  }
  return "auto";
}

std::optional<RenditionChoice> parse_rendition_choice(std::string_view text) {
  for (const RenditionChoice c : {RenditionChoice::Auto, RenditionChoice::Source, RenditionChoice::Low})
    if (text == to_string(c)) return c;
  return std::nullopt;
}

}  // namespace labo::server
