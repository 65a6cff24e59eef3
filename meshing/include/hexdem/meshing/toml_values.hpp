#pragma once
/// \file toml_values.hpp
/// Reading scalar values from parsed TOML with one-line errors "FILE:LINE: PATH: problem
/// (got VALUE)": shared by the outline reader and the case-file reader.

#include <toml++/toml.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

namespace hexdem::meshing {

/// Shortest decimal text that reads back as `value`.
std::string format_number(double value);

/// A short one-line rendering of a TOML value for messages (long arrays and tables are cut).
std::string describe(const toml::node& node);

/// Deepest nesting of keys (dots in one key) and of arrays / inline tables that parse_toml
/// accepts.
inline constexpr std::size_t kMaxTomlNesting = 256;

/// Largest input file (outline, case, DXF) that read_text_file reads [bytes].
inline constexpr std::size_t kMaxInputBytes = std::size_t{256} << 20;

/// Parses TOML text; a syntax error becomes InputError "SOURCE:LINE:COL: TOML parse error: ...",
/// nesting deeper than kMaxTomlNesting InputError "SOURCE:LINE:COL: key nested N levels deep".
toml::table parse_toml(std::string_view text, const std::string& source_name);

/// The contents of a file; InputError "PATH: cannot open file" if it cannot be read, or
/// "PATH: file larger than N bytes" beyond max_bytes (read no further: /dev/zero ends).
std::string read_text_file(const std::string& path, std::size_t max_bytes = kMaxInputBytes);

class TomlValues {
public:
  explicit TomlValues(std::string source) : source_(std::move(source)) {}

  /// Throws InputError "FILE:LINE: PATH: problem" (no line when the region has none, no
  /// path when `path` is empty).
  [[noreturn]] void fail(const toml::source_region& at, const std::string& path,
                         const std::string& problem) const;
  [[noreturn]] void fail(const toml::node& at, const std::string& path,
                         const std::string& problem) const {
    fail(at.source(), path, problem);
  }
  /// An integer or floating-point value, finite.
  [[nodiscard]] double number(const toml::node& node, const std::string& path) const;
  /// A number > 0.
  [[nodiscard]] double positive(const toml::node& node, const std::string& path) const;
  /// A lattice angle [degrees] in [-kMaxAngle, kMaxAngle] (the lattice repeats every 60
  /// degrees; beyond a turn a value is a slip, and at 1e308 its radians overflow).
  [[nodiscard]] double angle(const toml::node& node, const std::string& path) const;
  static constexpr double kMaxAngle = 360.0;
  /// A string.
  [[nodiscard]] std::string text(const toml::node& node, const std::string& path) const;
  /// A string without control characters (NUL, line breaks, ...): a name.
  [[nodiscard]] std::string name(const toml::node& node, const std::string& path) const;

  [[nodiscard]] const std::string& source() const { return source_; }

protected:
  std::string source_;  ///< the file named in messages
};

}  // namespace hexdem::meshing
