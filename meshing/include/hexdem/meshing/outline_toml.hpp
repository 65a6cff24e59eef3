#pragma once
/// \file outline_toml.hpp
/// Reads an outline from TOML (format: docs/outline-format.md).

#include <optional>
#include <string>
#include <string_view>

#include "hexdem/meshing/outline.hpp"

namespace hexdem::meshing {

/// Reader settings. Lattice options given here (the command line) override the file's
/// file-wide defaults; a body's own keys override both. After reading, every body has
/// radius, angle_deg and origin set.
struct ReadOptions {
  std::optional<double> radius;     ///< disk radius from the command line [m]
  std::optional<double> angle_deg;  ///< lattice angle from the command line [deg]
  std::optional<Vec2> origin;       ///< lattice origin from the command line [m]
  double chord_fraction = 1e-3;     ///< max sagitta of flattened arcs / disk radius [-]
  double scale = 0.0;               ///< if > 0, metres per file unit (overrides the file's unit)
};

/// Reads a TOML outline file. Throws InputError "FILE: KEY: message (value)" or
/// "FILE:LINE:COL: parse error" on bad input; a missing or empty file is an error.
Outline read_outline_toml(const std::string& path, const ReadOptions& options);

/// Same, from a string; `source_name` is used in messages.
Outline parse_outline_toml(std::string_view text, const std::string& source_name,
                           const ReadOptions& options);

}  // namespace hexdem::meshing
