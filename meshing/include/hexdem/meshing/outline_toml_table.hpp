#pragma once
/// \file outline_toml_table.hpp
/// Outline reading from an already parsed TOML table (the outline part of a case file).
/// Kept apart from outline_toml.hpp so that only users that parse TOML themselves see toml++.

#include <toml++/toml.h>

#include <string>

#include "hexdem/meshing/outline.hpp"
#include "hexdem/meshing/outline_toml.hpp"

namespace hexdem::meshing {

/// Reads an outline from `root`, which may hold only the keys `units`, `lattice` and `body`
/// (docs/outline-format.md). `source` names the file in messages; line numbers come from the
/// nodes' source regions.
Outline outline_from_toml(const toml::table& root, const std::string& source,
                          const ReadOptions& options);

}  // namespace hexdem::meshing
