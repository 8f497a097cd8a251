#include "core/cli_args.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

namespace labo {

std::optional<std::string> ParsedArgs::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string ParsedArgs::value_or(const std::string& name, const std::string& fallback) const {
  return value(name).value_or(fallback);
}

int ParsedArgs::integer_or(const std::string& name, int fallback, int min, int max) const {
  auto v = value(name);
  if (!v) return fallback;
  int out = 0;
  auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || end != v->data() + v->size() || out < min || out > max) {
    throw UsageError(name + ": '" + *v + "' is not an integer in [" + std::to_string(min) + ", " +
                     std::to_string(max) + "]");
  }
  return out;
}

double ParsedArgs::number_or(const std::string& name, double fallback, double min, double max) const {
  auto v = value(name);
  if (!v) return fallback;
  double out = 0;
  auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || end != v->data() + v->size() || !std::isfinite(out) || out < min || out > max) {
    std::ostringstream msg;
    msg << name << ": '" << *v << "' is not a number in [" << min << ", " << max << "]";
    throw UsageError(msg.str());
  }
  return out;
}

ParsedArgs parse_args(const CommandSpec& spec, std::span<const std::string> args) {
  ParsedArgs out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      out.help = true;
      return out;
    }
    if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.'))) {
      std::string name = a;
      std::optional<std::string> inline_value;
      if (auto eq = a.find('='); eq != std::string::npos) {
        name = a.substr(0, eq);
        inline_value = a.substr(eq + 1);
      }
      const OptionSpec* opt = nullptr;
      for (const auto& o : spec.options) {
        if (o.name == name) opt = &o;
      }
      if (!opt) throw UsageError("unknown option '" + name + "' for '" + spec.name + "' (see labodrone " + spec.name + " --help)");
      if (opt->value_name.empty()) {
        if (inline_value) throw UsageError("option '" + name + "' takes no value");
        out.values_[name] = "";
      } else if (inline_value) {
        out.values_[name] = *inline_value;
      } else {
        if (i + 1 >= args.size()) throw UsageError("option '" + name + "' needs a value " + opt->value_name);
        out.values_[name] = args[++i];
      }
      continue;
    }
    out.positionals.push_back(a);
  }
  const int n = static_cast<int>(out.positionals.size());
  if (n < spec.min_positionals || n > spec.max_positionals) {
    throw UsageError("'" + spec.name + "' takes " +
                     (spec.positionals.empty() ? std::string("no arguments") : spec.positionals) + ", got " +
                     std::to_string(n) + " argument(s)");
  }
  return out;
}

std::string usage(const CommandSpec& spec, const std::string& program) {
  std::ostringstream out;
  out << "usage: " << program << " " << spec.name;
  if (!spec.options.empty()) out << " [options]";
  if (!spec.positionals.empty()) out << ' ' << spec.positionals;
  out << "\n\n" << spec.summary << "\n";
  if (!spec.options.empty()) {
    out << "\noptions:\n";
    for (const auto& o : spec.options) {
      std::string left = o.name + (o.value_name.empty() ? "" : " " + o.value_name);
      out << "  " << left << std::string(left.size() < 24 ? 24 - left.size() : 1, ' ') << o.help << "\n";
    }
  }
  out << "  --help                  show this help\n";
  return out.str();
}

}  // namespace labo
