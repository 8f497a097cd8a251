#pragma once
// The form of POST /api/people (docs/web.md "Registered people"): a person's name, whether to replace
// a registered one, their interpupillary distance, one or more frontal photos and an optional
// head-turn set, as multipart/form-data. Read and checked on the I/O thread without decoding a
// picture: each photo's type from its first bytes and its size from its header, so that a wrong
// photo is refused at once and the worker decodes only what it will use.
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace labo::server {

struct RegistrationForm {
  std::string name;
  bool replace = false;
  std::optional<double> interpupillary_distance_m;  // none: face.interpupillary_distance_mm
  std::vector<std::string> frontal;  // encoded PNG or JPEG, in the order sent
  std::vector<std::string> turns;    // the head turn's frames, in the order sent
};

// The status (400, 409 is the caller's, 415, 422) and what was wrong.
struct FormRefusal {
  int status = 400;
  std::string message;
};

struct FormLimits {
  int width = 640, height = 360;  // the front camera's: every photo must be this size
  int max_frontal = 10;
  int max_turns = 300;
};

std::variant<RegistrationForm, FormRefusal> read_registration_form(std::string_view content_type, std::string_view body,
                                                                   const FormLimits& limits);

}  // namespace labo::server
