#pragma once
// The H.264 renditions a viewer can get: the drone's own stream, passed on as it came (the source),
// or the server's one shared lower-rate encode of the decoded frames (low; video/low_rendition.hpp).
// A leaf header: the wire structs of server/lab carry the rendition of each unit.
#include <cstdint>
#include <optional>
#include <string_view>

namespace labo::server {

enum class Rendition : std::uint8_t { Source = 0, Low = 1 };
std::string_view to_string(Rendition rendition);

// What a viewer asked for: follow its link (video/rendition_policy.hpp), or one rendition whatever
// the link.
enum class RenditionChoice { Auto, Source, Low };
std::string_view to_string(RenditionChoice choice);
std::optional<RenditionChoice> parse_rendition_choice(std::string_view text);

}  // namespace labo::server
