// `hexdem check CASE`: validate, mesh and set up a case without running it; print the
// summary (docs/case-format.md, "Checking a case").
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"
#include "subcommands.hpp"

namespace hexdem::app {
namespace {

struct CheckArgs {
  std::string case_file;
  std::vector<std::string> sets;
  bool whole_model_step = false;
};

int run_check(const CheckArgs& a) {
  const solver::Case c = solver::read_case(a.case_file, a.sets);
  meshing::GeneratorReport rep;
  const meshing::Lattice lattice = solver::mesh_case(c, &rep);
  // The solver's set-up: materials and their stability (Bloch), boundary sets, loads,
  // overlaps of bodies, and the time step. Refusals throw InputError like `hexdem run`.
  solver::Solver s(c, lattice);
  const solver::Model& m = s.model();

  std::printf("hexdem check: %s (%s, %s shear model): ok\n", c.source.c_str(), solver::geometry_name(c.geometry),
              solver::shear_model_name(c.shear_model));
  std::printf("  disks %zu (semi-disks %lld), bonds %zu%s\n", lattice.num_disks(), static_cast<long long>(rep.semi_disks),
              lattice.num_bonds(),
              c.disk_order == meshing::DiskOrder::Hilbert ? " (numbered along a Hilbert curve: [mesh] order)" : "");
  if (c.mesh_jitter > 0)
    std::printf("  irregular lattice: interior disks moved by up to %.6g r ([mesh] jitter, jitter_seed %lld)\n",
                c.mesh_jitter, static_cast<long long>(c.mesh_jitter_seed));
  if (c.contact.radius_spread > 0)
    std::printf("  contact radii: interior disks touch at r (1 +- %.6g) ([contact] radius_spread, jitter_seed %lld)\n",
                c.contact.radius_spread, static_cast<long long>(c.mesh_jitter_seed));
  std::vector<std::size_t> per_body(lattice.body_names.size(), 0);
  for (std::int32_t b : lattice.body) ++per_body[static_cast<std::size_t>(b)];
  for (std::size_t b = 0; b < lattice.body_names.size(); ++b) {
    const solver::BlochResult& br = s.bloch()[b];
    const solver::Material* mat = c.find_material(c.outline.bodies[b].material);
    std::printf("  body %-12s %zu disks, material %d '%s', r = %.6g m, Bloch %s, critical step %.6g s\n",
                lattice.body_names[b].c_str(), per_body[b], mat != nullptr ? mat->id : -1,
                mat != nullptr ? mat->name.c_str() : "?", c.outline.bodies[b].radius.value_or(0.0),
                br.stable ? "stable" : "UNSTABLE", br.dt_critical);
  }
  for (std::size_t k = 0; k < lattice.num_sets(); ++k) {
    // Conditions act on the members whose centre lies within r of the edge.
    std::size_t held = 0;
    for (auto e = lattice.set_offset[k]; e < lattice.set_offset[k + 1]; ++e) {
      const auto i = static_cast<std::size_t>(lattice.set_disk[e]);
      held += lattice.set_distance[e] < (1 - 1e-6) * m.radius[i];
    }
    std::printf("  set  %-12s %lld disks (%zu within r of the edge)\n", lattice.set_names[k].c_str(),
                static_cast<long long>(lattice.set_offset[k + 1] - lattice.set_offset[k]), held);
  }
  const solver::TimeStepInfo& ts = s.time_step();
  std::printf("  time step %.6g s (%s; critical %.6g s: Bloch %.6g s, finite model %.6g s; Eq. 24 %.6g s)\n", ts.dt,
              ts.user_dt ? "given" : "safety x critical", ts.dt_critical, ts.dt_bloch, ts.dt_finite, ts.dt_eq24);
  if (ts.stiffness_max > 1)
    std::printf("  random stiffness: largest factor %.6g, the critical step is the uniform model's / %.6g\n",
                ts.stiffness_max, std::sqrt(ts.stiffness_max));
  std::printf("  stability: dt / critical = %.3f%s\n", ts.dt / ts.dt_critical,
              ts.dt <= ts.dt_critical ? "" : " (ABOVE the critical step: allow_unstable)");
  if (s.contacts_enabled() || !c.walls.empty())
    std::printf("  contacts: omega <= %.6g 1/s (resolution %.6g / %.6g s, the default step, "
                "whatever the step used)%s\n",
                std::sqrt(m.contact_omega2), c.contact.resolution, ts.dt_contact,
                m.whole_cell_cap ? ", the cap reckoned with the disks' whole cells ([contact] cap_mass)" : "");
  const std::size_t estimated = s.finite_estimate_disks();
  if (estimated < m.num_disks())
    std::printf("  finite model: Lanczos on the edge band, %zu of %zu disks (%d iterations)\n", estimated, m.num_disks(),
                ts.finite_iterations);
  else
    std::printf("  finite model: Lanczos on the whole model (%d iterations)\n", ts.finite_iterations);
  if (a.whole_model_step && estimated < m.num_disks()) {
    // The band's estimate against the whole model's (docs/model.md, "Time integration").
    // With a random stiffness field the whole model is the scaled one, and the band's value
    // is compared as the step uses it: divided by sqrt(stiffness_max), a safe bound.
    const double dt_finite = ts.dt_finite / std::sqrt(ts.stiffness_max);
    const double w2 = s.finite_omega2_max();
    const double dt_whole = w2 > 0 ? solver::finite_model_step(w2) : dt_finite;
    std::printf("  whole model: finite model %.9g s against the band's %.9g s (%+.2e)%s\n", dt_whole, dt_finite,
                dt_finite / dt_whole - 1, ts.stiffness_max > 1 ? " (the band's / sqrt(largest stiffness factor))" : "");
  }
  std::printf("  %lld steps to t = %.6g s\n", static_cast<long long>(s.total_steps()), c.time.end);
  if (c.output.checkpoint_interval > 0)
    std::printf("  checkpoints every %.6g s\n", c.output.checkpoint_interval);
  for (const std::string& line : s.plasticity_report()) std::printf("  %s\n", line.c_str());
  std::vector<std::string> warnings = c.warnings;  // the reader's, then the set-up's
  warnings.insert(warnings.end(), s.warnings().begin(), s.warnings().end());
  for (const std::string& w : warnings) std::printf("  warning: %s\n", w.c_str());
  std::printf("  %zu warning%s\n", warnings.size(), warnings.size() == 1 ? "" : "s");
  return kExitOk;
}

}  // namespace

Subcommand add_check_command(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Read, mesh and set up a case without running it; print disks per body and set, time step, stability");
  cmd->add_option("case", args->case_file, "Case file (.toml)")->required();
  cmd->add_option("--set", args->sets, "Override a case value: KEY=VALUE (as for run)")->allow_extra_args(false)->take_all();
  cmd->add_flag("--whole-model-step", args->whole_model_step,
                "Also estimate the finite model's critical step on the whole model (Lanczos), when the solver "
                "estimated it on the edge band, and print both");
  return {cmd, [args] { return run_check(*args); }};
}

}  // namespace hexdem::app
