#pragma once
/// \file subcommands.hpp
/// Subcommands of the hexdem program kept in their own files (check_command.cpp,
/// sweep_command.cpp, bench_command.cpp). Usage in main(), as for `post`:
///
///     const Subcommand check = add_check_command(app);
///     app.parse(argc, argv);
///     if (*check.cmd) return check.run();  // inside the try that catches InputError
///
/// `run` throws hexdem::InputError (exit 2) on bad input and returns the exit code.

#include <functional>

namespace CLI {
class App;
}

namespace hexdem::app {

struct Subcommand {
  CLI::App* cmd;             ///< the subcommand (owned by the parent app)
  std::function<int()> run;  ///< runs the parsed command
};

/// `hexdem bench --disks N --model rotation|local-strain [--failure] [--contacts] --steps S
/// --threads T`: times the solver's step on a square block of about N disks and prints
/// particle-steps/s, bond-steps/s and peak bytes/disk on its last three lines
/// (docs/benchmarks.md).
Subcommand add_bench_command(CLI::App& app);

/// `hexdem check CASE [--set KEY=VALUE]...`: reads, meshes and sets the case up without
/// running it, and prints the summary (disks per body and set, time step, stability,
/// warnings).
Subcommand add_check_command(CLI::App& app);

/// `hexdem sweep STUDY.toml [--jobs N] [--dry-run]`: a parameter study (docs/studies.md).
Subcommand add_sweep_command(CLI::App& app);

}  // namespace hexdem::app
