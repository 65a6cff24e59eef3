// Reading scalar values from parsed TOML, with one-line errors.
#include "hexdem/meshing/toml_values.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "hexdem/error.hpp"

namespace hexdem::meshing {

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string describe(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return format_number(f->get());
  if (const auto* s = node.as_string()) return "\"" + s->get() + "\"";
  std::ostringstream out;
  node.visit([&](const auto& n) { out << n; });
  std::string text = out.str();
  std::replace(text.begin(), text.end(), '\n', ' ');
  constexpr std::size_t max_length = 60;
  if (text.size() > max_length) text = text.substr(0, max_length) + "...";
  return text;
}

toml::table parse_toml(std::string_view text, const std::string& source_name) {
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& error) {
    const auto& begin = error.source().begin;
    std::string description(error.description());
    std::replace(description.begin(), description.end(), '\n', ' ');
    throw InputError(source_name + ":" + std::to_string(begin.line) + ":" +
                     std::to_string(begin.column) + ": TOML parse error: " + description);
  }
}

std::string read_text_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open file");
  std::ostringstream contents;
  contents << file.rdbuf();
  return contents.str();
}

void TomlValues::fail(const toml::source_region& at, const std::string& path,
                      const std::string& problem) const {
  std::string message = source_;
  if (at.path != nullptr && at.path->rfind("--set ", 0) == 0) {
    message += ": " + *at.path;  // a value given on the command line (case --set overrides)
  } else if (at.begin.line > 0) {
    message += ":" + std::to_string(at.begin.line);
  }
  message += ": ";
  if (!path.empty()) message += path + ": ";
  throw InputError(message + problem);
}

double TomlValues::number(const toml::node& node, const std::string& path) const {
  double value = 0.0;
  if (const auto* i = node.as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    value = f->get();
  } else {
    fail(node, path, "expected a number (got " + describe(node) + ")");
  }
  if (!std::isfinite(value)) fail(node, path, "must be finite (got " + describe(node) + ")");
  return value;
}

double TomlValues::positive(const toml::node& node, const std::string& path) const {
  const double value = number(node, path);
  if (!(value > 0.0)) fail(node, path, "must be > 0 (got " + describe(node) + ")");
  return value;
}

std::string TomlValues::text(const toml::node& node, const std::string& path) const {
  const auto* s = node.as_string();
  if (s == nullptr) fail(node, path, "expected a string (got " + describe(node) + ")");
  return s->get();
}

}  // namespace hexdem::meshing
