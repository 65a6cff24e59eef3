#pragma once
/// \file outline_toml.hpp
/// Reads an outline from TOML (format: docs/outline-format.md).

#include <cstdint>
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
  /// If > 0, the caller's limit on the estimated disk count (`--max-disks`, `[mesh]
  /// max_disks`), checked with the readers' ceiling before the loops are validated, so that an
  /// outline that the generator would refuse is refused before its arcs' chords reach CGAL;
  /// the message names max_disks_hint as the way to raise it.
  std::int64_t max_disks = 0;
  std::string max_disks_hint;
};

/// Reads a TOML outline file. Throws InputError "FILE: KEY: message (value)" or
/// "FILE:LINE:COL: parse error" on bad input; a missing or empty file is an error.
Outline read_outline_toml(const std::string& path, const ReadOptions& options);

/// Same, from a string; `source_name` is used in messages.
Outline parse_outline_toml(std::string_view text, const std::string& source_name,
                           const ReadOptions& options);

}  // namespace hexdem::meshing
