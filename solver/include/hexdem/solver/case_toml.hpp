#pragma once
/// \file case_toml.hpp
/// Reads a case file (TOML; docs/case-format.md): geometry, outline (a file or inline),
/// materials, boundary conditions, loads, initial velocities, time control, outputs, probes.
/// Every cross-reference (boundary sets, bodies, materials) is checked against the outline.

#include <cstddef>
#include <string>
#include <string_view>

#include "hexdem/solver/case.hpp"

namespace hexdem::solver {

/// Most time steps a run may take: [time] end / dt beyond this is refused as bad input.
inline constexpr double kMaxSteps = 1e12;

/// Longest case name ([case] name or the case file's stem) [characters]: the name is the
/// stem of every output file (`<name>_000000000.vtu`, `<name>.energy.csv`).
inline constexpr std::size_t kMaxCaseNameLength = 200;

/// Why `name` cannot be a case name (a file stem: not empty, ".", "..", no '/', no control
/// character, at most kMaxCaseNameLength characters), or empty if it can.
std::string case_name_problem(const std::string& name);

/// Reads a case file. Throws InputError "FILE:LINE: KEY: message (got VALUE)" on bad input.
Case read_case(const std::string& path);

/// Same from text; `source_name` names it in messages and `base_dir` resolves relative paths
/// (the outline file).
Case parse_case(std::string_view text, const std::string& source_name, const std::string& base_dir);

}  // namespace hexdem::solver
