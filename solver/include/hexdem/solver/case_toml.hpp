#pragma once
/// \file case_toml.hpp
/// Reads a case file (TOML; docs/case-format.md): geometry, outline (a file or inline),
/// materials, boundary conditions, loads, initial velocities, time control, outputs, probes.
/// Every cross-reference (boundary sets, bodies, materials) is checked against the outline.

#include <string>
#include <string_view>

#include "hexdem/solver/case.hpp"

namespace hexdem::solver {

/// Reads a case file. Throws InputError "FILE:LINE: KEY: message (got VALUE)" on bad input.
Case read_case(const std::string& path);

/// Same from text; `source_name` names it in messages and `base_dir` resolves relative paths
/// (the outline file).
Case parse_case(std::string_view text, const std::string& source_name, const std::string& base_dir);

}  // namespace hexdem::solver
