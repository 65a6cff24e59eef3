#pragma once
/// \file run_summary.hpp
/// The final values of a run in one CSV row, `<case>.summary.csv` (docs/file-format.md):
/// the energy balance at the end time, bonds broken, fragments (groups of disks joined by
/// intact bonds) in all and per body, single-disk fragments (debris) per body, and each
/// body's mass, mass-averaged velocity and kinetic energy. `hexdem sweep` collects these rows.

#include <string>
#include <vector>

#include "hexdem/solver/solver.hpp"

namespace hexdem::solver {

struct RunSummary {
  std::vector<std::string> columns;
  std::vector<double> values;
};

/// The summary of the solver's state at t_n after its last advance(): energies of that step,
/// velocities at t_n (mean of the half steps), bond states of t_n's force pass.
RunSummary run_summary(const Solver& s);

/// Names of the summary's columns for a case with these bodies (without running it).
std::vector<std::string> run_summary_columns(const std::vector<std::string>& body_names);

/// Writes the summary as a two-line CSV, atomically.
void write_run_summary(const std::string& path, const RunSummary& summary);

}  // namespace hexdem::solver
