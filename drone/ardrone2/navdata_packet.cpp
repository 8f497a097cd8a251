#include "drone/ardrone2/navdata_packet.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::ardrone2 {

NavdataPacket::NavdataPacket() {
  for (const auto& spec : navdata_option_specs()) options_[spec.tag].raw.assign(spec.value_count(), 0.0);
  unknown.reserve(8);
}

void NavdataPacket::clear() {
  for (auto& o : options_) o.present = false;
  unknown.clear();
  checksum_ok = false;
}

std::size_t NavdataPacket::index_of(std::uint16_t tag, std::string_view field, std::size_t index) const {
  const NavdataOptionSpec* spec = find_option_spec(tag);
  if (!spec) throw std::out_of_range("navdata: unknown option tag " + std::to_string(tag));
  const auto first = field_value_index(*spec, field);
  if (!first) throw std::out_of_range("navdata: option " + std::string(spec->name) + " has no field " + std::string(field));
  for (const auto& f : spec->fields) {
    if (f.name == field && index >= f.count)
      throw std::out_of_range("navdata: index " + std::to_string(index) + " past " + std::string(field));
  }
  return *first + index;
}

double NavdataPacket::raw(std::uint16_t tag, std::string_view field, std::size_t index) const {
  return options_[tag < kKnownOptionCount ? tag : 0].raw[index_of(tag, field, index)];
}

void NavdataPacket::set(std::uint16_t tag, std::string_view field, double value, std::size_t index) {
  const std::size_t i = index_of(tag, field, index);
  auto& o = options_[tag];
  if (!o.present) add_option(tag);
  o.raw[i] = value;
}

std::uint32_t navdata_time_word(double seconds) {
  const double t = std::isfinite(seconds) ? std::max(0.0, seconds) : 0.0;
  const auto total_us = static_cast<std::uint64_t>(std::llround(t * 1e6));
  const auto secs = static_cast<std::uint32_t>((total_us / 1000000u) % 2048u);
  const auto usecs = static_cast<std::uint32_t>(total_us % 1000000u);
  return (secs << 21) | usecs;
}

void NavdataPacket::add_option(std::uint16_t tag) {
  const NavdataOptionSpec* spec = find_option_spec(tag);
  if (!spec) throw std::out_of_range("navdata: unknown option tag " + std::to_string(tag));
  auto& o = options_[tag];
  o.present = true;
  o.wire_size = spec->size;
  std::fill(o.raw.begin(), o.raw.end(), 0.0);
}

}  // namespace labo::ardrone2
