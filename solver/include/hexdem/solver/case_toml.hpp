#pragma once
/// \file case_toml.hpp
/// Reads a case file (TOML; docs/case-format.md): geometry, outline (a file or inline),
/// materials, boundary conditions, loads, initial velocities, time control, outputs, probes.
/// Every cross-reference (boundary sets, bodies, materials) is checked against the outline.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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
/// `overrides` are `--set` values "DOTTED.KEY=VALUE" applied to the file's TOML before it is
/// read (docs/case-format.md, "Overrides"): each dot descends one table; in an array of
/// tables the next part selects one table by its `id`, else its `name` (or, for
/// [[initial_velocity]], its `body`), else, for tables with neither, by position from 0.
/// VALUE is a TOML value, or else taken as a string. The checks and messages are the file's,
/// naming the --set. The result's effective_toml is the case as run.
/// max_disks, if given, replaces the case's [mesh] max_disks (`hexdem run --max-disks N`).
Case read_case(const std::string& path, const std::vector<std::string>& overrides = {},
               std::optional<std::int64_t> max_disks = std::nullopt);

/// Same from text; `source_name` names it in messages and `base_dir` resolves relative paths
/// (the outline file).
Case parse_case(std::string_view text, const std::string& source_name, const std::string& base_dir,
                const std::vector<std::string>& overrides = {}, std::optional<std::int64_t> max_disks = std::nullopt);


}  // namespace hexdem::solver
