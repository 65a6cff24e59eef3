// Reading scalar values from parsed TOML, with one-line errors.
#include "hexdem/meshing/toml_values.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hexdem/error.hpp"
#include "hexdem/meshing/text.hpp"

namespace hexdem::meshing {

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string describe(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return format_number(f->get());
  if (const auto* s = node.as_string()) {
    std::string quoted = "\"";  // appended, not "\"" + ...: GCC 12 warns (-Wrestrict) on that form
    quoted += escape_text(s->get());
    quoted += '"';
    return quoted;
  }
  std::ostringstream out;
  node.visit([&](const auto& n) { out << n; });
  std::string text = out.str();
  std::replace(text.begin(), text.end(), '\n', ' ');
  constexpr std::size_t max_length = 60;
  if (text.size() > max_length) text = text.substr(0, max_length) + "...";
  return text;
}

namespace {

/// Refuses text whose keys or values nest deeper than kMaxTomlNesting: toml++ parses dotted
/// keys and table headers recursively, and a key nested some 50,000 levels deep overflows
/// the stack. Counts the dots of each key (of a `key = value` line, a [table] header or an
/// inline table entry) and the depth of open arrays and inline tables, outside strings and
/// comments.
void check_nesting(std::string_view text, const std::string& source_name) {
  enum class State { Normal, Basic, Literal, MultiBasic, MultiLiteral, Comment };
  State state = State::Normal;
  std::size_t line = 1, column = 0, dots = 0;
  std::string open;       // the open brackets and braces, innermost last
  bool in_key = true;     // reading a key (its dots count)
  const auto fail = [&](const char* what, std::size_t levels) {
    throw InputError(source_name + ":" + std::to_string(line) + ":" + std::to_string(column) +
                     ": " + what + " nested " + std::to_string(levels) + " levels deep (limit " +
                     std::to_string(kMaxTomlNesting) + ")");
  };
  const auto starts = [&](std::size_t k, std::string_view s) { return text.substr(k, s.size()) == s; };
  const auto start_key = [&]() {
    in_key = true;
    dots = 0;
  };
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    ++column;
    if (c == '\n' && state != State::MultiBasic && state != State::MultiLiteral) {
      ++line;
      column = 0;
      state = State::Normal;  // ends a comment; an unterminated string is toml++'s to report
      if (open.empty()) start_key();
      continue;
    }
    if (c == '\n') {
      ++line;
      column = 0;
    }
    switch (state) {
      case State::Normal:
        if (c == '#') {
          state = State::Comment;
        } else if (starts(k, "\"\"\"")) {
          state = State::MultiBasic;
          k += 2;
        } else if (starts(k, "'''")) {
          state = State::MultiLiteral;
          k += 2;
        } else if (c == '"') {
          state = State::Basic;
        } else if (c == '\'') {
          state = State::Literal;
        } else if (c == '.' && in_key) {
          if (++dots > kMaxTomlNesting) fail("key", dots);
        } else if (c == '=') {
          in_key = false;
        } else if (c == '[' || c == '{') {
          const bool header = in_key && open.empty();  // [table] or [[array]] header
          if (!header) {
            open.push_back(c);
            if (open.size() > kMaxTomlNesting) fail("value", open.size());
          }
          if (c == '{') start_key();
          else if (!header) in_key = false;
        } else if (c == ']' || c == '}') {
          if (!open.empty()) open.pop_back();
        } else if (c == ',' && !open.empty() && open.back() == '{') {
          start_key();
        }
        break;
      case State::Basic:
        if (c == '\\') ++k;
        else if (c == '"') state = State::Normal;
        break;
      case State::Literal:
        if (c == '\'') state = State::Normal;
        break;
      case State::MultiBasic:
        if (c == '\\') ++k;
        else if (starts(k, "\"\"\"")) { state = State::Normal; k += 2; }
        break;
      case State::MultiLiteral:
        if (starts(k, "'''")) { state = State::Normal; k += 2; }
        break;
      case State::Comment:
        break;
    }
  }
}

}  // namespace

toml::table parse_toml(std::string_view text, const std::string& source_name) {
  check_nesting(text, source_name);
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& error) {
    const auto& begin = error.source().begin;
    std::string description(error.description());
    throw InputError(source_name + ":" + std::to_string(begin.line) + ":" +
                     std::to_string(begin.column) + ": TOML parse error: " +
                     escape_text(description));
  }
}

std::string read_text_file(const std::string& path, std::size_t max_bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
  // A FIFO would block the open for ever, a device would be read as text: only regular files
  // (or links to them) are inputs. A missing file is reported by the open below.
  if (const auto st = std::filesystem::status(path, ec); !ec && std::filesystem::exists(st) &&
                                                         !std::filesystem::is_regular_file(st))
    throw InputError(path + ": not a regular file (a FIFO, device or socket); give a file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open file");
  std::string contents;
  char buffer[65536];
  while (file.read(buffer, sizeof buffer) || file.gcount() > 0) {
    contents.append(buffer, static_cast<std::size_t>(file.gcount()));
    if (contents.size() > max_bytes)
      throw InputError(path + ": file larger than " + std::to_string(max_bytes) +
                       " bytes (not an outline or case file?)");
  }
  if (file.bad()) throw InputError(path + ": cannot read file");
  return contents;
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
  throw InputError(one_line(message + problem));
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

double TomlValues::angle(const toml::node& node, const std::string& path) const {
  const double value = number(node, path);
  if (!(std::abs(value) <= kMaxAngle)) fail(node, path, "must lie in [-360, 360] degrees (got " + describe(node) + ")");
  return value;
}

std::string TomlValues::text(const toml::node& node, const std::string& path) const {
  const auto* s = node.as_string();
  if (s == nullptr) fail(node, path, "expected a string (got " + describe(node) + ")");
  return s->get();
}

std::string TomlValues::name(const toml::node& node, const std::string& path) const {
  std::string value = text(node, path);
  if (has_control_character(value))
    fail(node, path, "must not hold control characters (got " + describe(node) + ")");
  return value;
}

}  // namespace hexdem::meshing
