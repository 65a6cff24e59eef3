// Final values of a run: energy terms, broken bonds, fragments and body velocities.
#include "hexdem/solver/run_summary.hpp"

#include <cstdio>
#include <numeric>

#include "hexdem/io/vtu_writer.hpp"

namespace hexdem::solver {

std::vector<std::string> run_summary_columns(const std::vector<std::string>& body_names) {
  std::vector<std::string> cols{"time",    "step",          "kinetic",      "elastic",        "external_work",
                                "damping", "plastic",       "fracture",     "contact_damping", "friction",
                                "break_kinetic", "input",   "total",        "relative_error", "broken_bonds",
                                "fragments"};
  for (const std::string& b : body_names)
    for (const char* c : {"fragments", "debris", "mass", "vx", "vy", "kinetic"}) cols.push_back(b + "." + c);
  return cols;
}

RunSummary run_summary(const Solver& s) {
  const Model& m = s.model();
  const std::size_t n = m.num_disks();
  // Fragments: connected components of the disks over the intact bonds (union-find).
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto root = [&parent](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    if (!m.bond_intact(b)) continue;
    const std::size_t a = root(static_cast<std::size_t>(m.bi[b])), c = root(static_cast<std::size_t>(m.bj[b]));
    if (a != c) parent[std::max(a, c)] = std::min(a, c);
  }
  const std::vector<std::string>& names = s.lattice().body_names;
  const std::size_t nb = names.size();
  std::vector<std::size_t> size(n, 0);
  for (std::size_t i = 0; i < n; ++i) ++size[root(i)];
  std::vector<double> fragments(nb, 0), debris(nb, 0), mass(nb, 0), px(nb, 0), py(nb, 0), kin(nb, 0);
  double total_fragments = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = static_cast<std::size_t>(m.body[i]);
    if (root(i) == i) {
      fragments[b] += 1;
      debris[b] += size[i] == 1;
      total_fragments += 1;
    }
    mass[b] += m.mass[i];
    px[b] += m.mass[i] * s.vx_mid(i);
    py[b] += m.mass[i] * s.vy_mid(i);
    kin[b] += 0.5 * (m.mass[i] * (m.vx_old[i] * m.vx[i] + m.vy_old[i] * m.vy[i]) +
                     m.disk_inertia(i) * m.omega_old[i] * m.omega[i]);
  }
  const EnergyBalance& e = s.energy();
  RunSummary out;
  out.columns = run_summary_columns(names);
  // The state is at t_n of the last step: its time is one step before the solver's clock.
  const double t = static_cast<double>(s.step_index() - 1) * s.dt();
  out.values = {t,
                static_cast<double>(s.step_index() - 1),
                e.kinetic,
                e.elastic,
                e.external_work,
                e.damping,
                e.plastic,
                e.fracture,
                e.contact_damping,
                e.friction,
                e.break_kinetic,
                e.input(),
                e.total(),
                e.relative_error(),
                static_cast<double>(s.broken_bonds()),
                total_fragments};
  for (std::size_t b = 0; b < nb; ++b) {
    const double inv = mass[b] > 0 ? 1.0 / mass[b] : 0.0;
    for (double v : {fragments[b], debris[b], mass[b], px[b] * inv, py[b] * inv, kin[b]}) out.values.push_back(v);
  }
  return out;
}

void write_run_summary(const std::string& path, const RunSummary& summary) {
  std::string text;
  for (std::size_t k = 0; k < summary.columns.size(); ++k) text += (k ? "," : "") + summary.columns[k];
  text += "\n";
  for (std::size_t k = 0; k < summary.values.size(); ++k) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%s%.17g", k ? "," : "", summary.values[k]);
    text += buf;
  }
  text += "\n";
  io::write_file_atomic(path, text);
}

}  // namespace hexdem::solver
