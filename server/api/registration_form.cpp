#include "server/api/registration_form.hpp"

#include <charconv>
#include <stdexcept>

#include "localization/face/person_shape.hpp"
#include "server/api/multipart_form.hpp"

namespace labo::server {

namespace {

// A PNG's or JPEG's size, read from its header.
struct ImageHeader {
  bool png = false;  // else JPEG
  int width = 0, height = 0;
};

unsigned byte_at(std::string_view s, std::size_t i) { return static_cast<unsigned char>(s[i]); }
unsigned be16(std::string_view s, std::size_t i) { return byte_at(s, i) << 8 | byte_at(s, i + 1); }
unsigned long be32(std::string_view s, std::size_t i) {
  return static_cast<unsigned long>(be16(s, i)) << 16 | be16(s, i + 2);
}

std::optional<ImageHeader> png_header(std::string_view b) {
  // Signature, then the IHDR chunk first: length, "IHDR", width, height.
  if (b.size() < 24 || b.substr(12, 4) != "IHDR") return std::nullopt;
  const unsigned long w = be32(b, 16), h = be32(b, 20);
  if (w == 0 || h == 0 || w > 1u << 20 || h > 1u << 20) return std::nullopt;
  return ImageHeader{true, static_cast<int>(w), static_cast<int>(h)};
}

std::optional<ImageHeader> jpeg_header(std::string_view b) {
  std::size_t i = 2;  // after SOI
  while (i + 4 <= b.size()) {
    if (byte_at(b, i) != 0xFF) return std::nullopt;
    const unsigned marker = byte_at(b, i + 1);
    if (marker == 0xFF) { ++i; continue; }  // fill byte
    if (marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) { i += 2; continue; }
    const unsigned length = be16(b, i + 2);
    if (length < 2) return std::nullopt;
    // Start of frame: every SOFn but DHT (C4), JPG (C8) and DAC (CC) carries the size.
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (i + 9 > b.size()) return std::nullopt;
      const int h = static_cast<int>(be16(b, i + 5)), w = static_cast<int>(be16(b, i + 7));
      if (w == 0 || h == 0) return std::nullopt;
      return ImageHeader{false, w, h};
    }
    if (marker == 0xDA || marker == 0xD9) return std::nullopt;  // scan or end before a frame header
    i += 2 + length;
  }
  return std::nullopt;
}

std::optional<bool> parse_flag(std::string_view text) {
  if (text == "true" || text == "1" || text == "on") return true;
  if (text == "false" || text == "0" || text == "") return false;
  return std::nullopt;
}

// A photo part: declared an image, its bytes a PNG or JPEG of the camera's size.
std::optional<FormRefusal> check_photo(const FormPart& part, int index, const FormLimits& limits) {
  const std::string which = part.name + " photo " + std::to_string(index + 1) + (part.filename.empty() ? "" : " (" + part.filename + ")");
  if (part.content_type != "image/png" && part.content_type != "image/jpeg")
    return FormRefusal{415, which + " is sent as '" + part.content_type + "', expected image/png or image/jpeg"};
  const std::string_view b = part.body;
  const bool png = b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8);
  const bool jpeg = b.size() >= 3 && byte_at(b, 0) == 0xFF && byte_at(b, 1) == 0xD8 && byte_at(b, 2) == 0xFF;
  if (!png && !jpeg) return FormRefusal{415, which + " is not a PNG or JPEG image (its first bytes say neither)"};
  const auto header = png ? png_header(b) : jpeg_header(b);
  if (!header) return FormRefusal{400, which + ": the image's header is damaged or cut"};
  if (header->width != limits.width || header->height != limits.height)
    return FormRefusal{422, which + " is " + std::to_string(header->width) + "x" + std::to_string(header->height) +
                                ", expected the front camera's " + std::to_string(limits.width) + "x" +
                                std::to_string(limits.height) + ": take the photos with the drone's front camera"};
  return std::nullopt;
}

}  // namespace

std::variant<RegistrationForm, FormRefusal> read_registration_form(std::string_view content_type, std::string_view body,
                                                                   const FormLimits& limits) {
  if (!is_multipart_form(content_type))
    return FormRefusal{415, "send the photos as multipart/form-data (fields name, frontal, turn, replace, ipd_mm)"};
  const auto parsed = parse_multipart_form(content_type, body, static_cast<std::size_t>(limits.max_frontal + limits.max_turns + 3));
  if (const auto* error = std::get_if<std::string>(&parsed)) return FormRefusal{400, "malformed form: " + *error};
  RegistrationForm form;
  bool named = false, replace_seen = false, ipd_seen = false;
  for (const FormPart& part : std::get<std::vector<FormPart>>(parsed)) {
    if (part.name == "frontal" || part.name == "turn") {
      auto& list = part.name == "frontal" ? form.frontal : form.turns;
      const int limit = part.name == "frontal" ? limits.max_frontal : limits.max_turns;
      if (static_cast<int>(list.size()) == limit)
        return FormRefusal{400, "at most " + std::to_string(limit) + " '" + part.name + "' photos"};
      if (auto refusal = check_photo(part, static_cast<int>(list.size()), limits)) return *refusal;
      list.emplace_back(part.body);
    } else if (part.name == "name" && !named) {
      form.name = std::string(part.body);
      try {
        face::validate_person_name(form.name);
      } catch (const std::invalid_argument&) {
        return FormRefusal{400, "'name' must be 1-64 characters of A-Z a-z 0-9 _ -, got '" + form.name.substr(0, 80) + "'"};
      }
      named = true;
    } else if (part.name == "replace" && !replace_seen) {
      const auto flag = parse_flag(part.body);
      if (!flag) return FormRefusal{400, "'replace' must be true or false"};
      form.replace = *flag;
      replace_seen = true;
    } else if (part.name == "ipd_mm" && !ipd_seen) {
      double mm = 0;
      const auto [end, ec] = std::from_chars(part.body.data(), part.body.data() + part.body.size(), mm);
      if (ec != std::errc{} || end != part.body.data() + part.body.size() || !(mm >= 40 && mm <= 90))
        return FormRefusal{400, "'ipd_mm' must be the interpupillary distance in mm, 40 to 90"};
      form.interpupillary_distance_m = mm / 1000.0;
      ipd_seen = true;
    } else {
      return FormRefusal{400, "unknown or repeated field '" + part.name + "' (expected name, frontal, turn, replace, ipd_mm)"};
    }
  }
  if (!named) return FormRefusal{400, "the form needs a 'name'"};
  if (form.frontal.empty()) return FormRefusal{400, "the form needs at least one 'frontal' photo"};
  return form;
}

}  // namespace labo::server
