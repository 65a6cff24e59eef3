// `hexdem bench --disks N --model M [--failure [--softening]] [--contacts] --steps S --threads T [--order O]`: the speed
// and memory of the solver's time step on a square block of concrete (docs/benchmarks.md,
// "Solver step: `hexdem bench`").
#include <CLI/CLI.hpp>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/case.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/solver.hpp"
#include "subcommands.hpp"

namespace hexdem::app {
namespace {

/// Bounds of the arguments (bad values exit 2 naming the option and the value).
constexpr double kMinDisks = 10, kMaxDisks = 3e8;  // the model holds at most 2^30 bonds
constexpr double kMaxSteps = 1e12;
constexpr int kMaxThreads = 1024;
/// Energy balance checked every this many steps, as `hexdem run` does without output.
constexpr std::int64_t kCheckInterval = 50;

struct BenchArgs {
  std::string disks = "100000";
  std::string model = "local-strain";
  std::string steps = "1000";
  std::string threads = "1";
  std::string order = "rows";
  bool failure = false;
  bool softening = false;
  bool contacts = false;
};

/// The whole of `text` as a finite number, or throws InputError naming `option`.
double parse_number(const std::string& option, const std::string& text, const char* expected) {
  char* end = nullptr;
  const double v = text.empty() ? NAN : std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw InputError(option + ": expected " + expected + " (got '" + text + "')");
  return v;
}

/// An integer in [lo, hi] (written as an integer or as 1e6), or throws InputError.
double parse_count(const std::string& option, const std::string& text, double lo, double hi, const char* range) {
  const std::string expected = std::string("an integer in ") + range;
  const double v = parse_number(option, text, expected.c_str());
  if (v != std::floor(v) || v < lo || v > hi) throw InputError(option + ": must be an integer in " + range + " (got " + text + ")");
  return v;
}

/// Resident memory of the process now [bytes] (VmRSS of /proc/self/status), 0 if unknown.
double resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return 0;
  char line[256];
  double kb = 0;
  while (std::fgets(line, sizeof line, f) != nullptr)
    if (std::sscanf(line, "VmRSS: %lf kB", &kb) == 1) break;
  std::fclose(f);
  return kb * 1024.0;
}

/// CPU time of the process so far, all threads [s] (user + system).
double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/// Peak resident memory of the process [bytes] (getrusage: kilobytes on Linux).
double peak_resident_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) * 1024.0;
}

meshing::Loop rectangle(double x0, double y0, double x1, double y1) {
  meshing::Loop loop;
  loop.points = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  loop.edge_set.assign(4, -1);
  loop.edge_straight.assign(4, 1);
  loop.where = "bench: block";
  return loop;
}

int run_bench(const BenchArgs& a) {
  const double disks_wanted = parse_count("--disks", a.disks, kMinDisks, kMaxDisks, "10..3e8");
  const auto steps = static_cast<std::int64_t>(parse_count("--steps", a.steps, 1, kMaxSteps, "1..1e12"));
  const int threads = static_cast<int>(parse_count("--threads", a.threads, 1, kMaxThreads, "1..1024"));
  solver::ShearModel shear = solver::ShearModel::LocalStrain;
  if (a.model == "rotation") {
    shear = solver::ShearModel::Rotation;
  } else if (a.model != "local-strain") {
    throw InputError("--model: unknown model '" + a.model + "' (expected rotation or local-strain)");
  }
  meshing::DiskOrder order = meshing::DiskOrder::Rows;
  if (a.order == "hilbert") {
    order = meshing::DiskOrder::Hilbert;
  } else if (a.order != "rows") {
    throw InputError("--order: unknown order '" + a.order + "' (expected rows or hilbert)");
  }
  if (a.softening && !a.failure) throw InputError("--softening: needs --failure (the softening law is a failure law)");
  omp_set_num_threads(threads);

  // A square block of nx disks per row and ny rows (about disks_wanted in all), bottom row
  // at y = 0. With --contacts it is two bodies, the lower and the upper half, that touch
  // along the line half-way between two rows: the contacts of a case with several bodies.
  const double r = 0.5e-3, d = 2 * r, h = std::sqrt(3.0) * r;
  const auto nx = static_cast<std::int64_t>(std::max(2.0, std::round(std::sqrt(disks_wanted * h / d))));
  const double min_rows = a.contacts ? 4.0 : 2.0;  // with contacts, two rows per half at least
  const auto ny =
      static_cast<std::int64_t>(std::max(min_rows, std::round(disks_wanted / static_cast<double>(nx))));
  const double width = static_cast<double>(nx - 1) * d + r, height = static_cast<double>(ny - 1) * h;

  solver::Case c;
  c.name = "bench";
  c.source = "bench";
  c.geometry = solver::Geometry::PlaneStress;
  c.thickness = 1.0;
  c.shear_model = shear;
  c.max_disks = static_cast<std::int64_t>(2 * disks_wanted) + 1000;
  c.disk_order = order;
  solver::Material mat;
  mat.id = 1;
  mat.name = "concrete";
  mat.density = 2400;
  mat.E = 30e9;
  mat.nu = 0.2;
  if (a.failure) {
    // Concrete-like strengths: the block's stresses (about 1 MPa) stay below them, so the
    // failure checks run on every bond and nothing breaks (the count is printed).
    mat.breakable = true;
    mat.tensile_strength = 3e6;
    mat.compressive_strength = 30e6;
    mat.cohesion = 6e6;
    mat.friction_angle = 30;
    // --softening: the softening law (docs/model.md, "Fracture energy and softening") with the
    // local criterion, whose bound skips the checks of bonds far from every criterion.
    if (a.softening) mat.fracture_energy = 100.0;
  }
  c.materials.push_back(mat);
  const auto add_body = [&](const std::string& name, double y0, double y1) {
    meshing::BodyOutline b;
    b.name = name;
    b.material = 1;
    b.radius = r;
    b.where = "bench: body '" + name + "'";
    b.outers.push_back(rectangle(0, y0, width, y1));
    c.outline.bodies.push_back(b);
  };
  if (a.contacts) {
    const double cut = (static_cast<double>(ny / 2) - 0.5) * h;
    add_body("lower", 0, cut);
    add_body("upper", cut, height);
  } else {
    add_body("block", 0, height);
  }
  c.outline.source = "bench";
  c.time.end = 1.0;  // the step is safety x critical; the run takes `steps` steps of it
  c.output.frames = false;

  const double rss_before = resident_bytes();  // the program and its libraries
  const auto t0 = std::chrono::steady_clock::now();
  meshing::Lattice lattice = solver::mesh_case(c);
  const auto t_mesh = std::chrono::steady_clock::now();
  solver::Solver s(c, std::move(lattice));  // moved in: the solver keeps no second copy
  // A smooth deterministic velocity field (wavelengths of 19 to 31 spacings, 0.1 m/s) that
  // loads the springs everywhere.
  solver::Model& m = s.model();
  const double v0 = 0.1, k = 2 * std::numbers::pi / d;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double x = m.x0[i], y = m.y0[i];
    m.vx[i] = v0 * std::sin(k * x / 23 + 0.3) * std::cos(k * y / 31);
    m.vy[i] = v0 * std::cos(k * x / 19) * std::sin(k * y / 27 + 0.7);
  }
  const auto t_setup = std::chrono::steady_clock::now();
  const double cpu_setup = cpu_seconds();

  const std::size_t n_disks = m.num_disks(), n_bonds = m.num_bonds();
  for (std::int64_t n = 0; n < steps; ++n) {
    if (!s.advance(n % kCheckInterval == 0)) {
      std::fprintf(stderr, "hexdem: error: bench: the run failed at step %lld: %s\n",
                   static_cast<long long>(s.blow_up().step), s.blow_up().reason.c_str());
      return kExitRunFailed;
    }
  }
  const auto t_end = std::chrono::steady_clock::now();
  const double step_cpu = cpu_seconds() - cpu_setup;
  const double mesh_s = std::chrono::duration<double>(t_mesh - t0).count();
  const double setup_s = std::chrono::duration<double>(t_setup - t0).count();
  const double step_s = std::chrono::duration<double>(t_end - t_setup).count();
  const double total_steps = static_cast<double>(steps);
  const double peak = peak_resident_bytes();

  std::printf("hexdem bench: %s shear model, plane stress, concrete E = 30 GPa, nu = 0.2, rho = 2400 kg/m^3\n",
              solver::shear_model_name(shear));
  std::printf("  disks %zu (%lld rows of %lld, r = %.3g m), bonds %zu, bodies %zu\n", n_disks,
              static_cast<long long>(ny), static_cast<long long>(nx), r, n_bonds, s.lattice().body_names.size());
  std::printf("  failure %s\n", !a.failure   ? "off (elastic bonds)"
                                : a.softening ? "on, softening (G_F 100 J/m^2, f_t 3 MPa, f_c 30 MPa, c 6 MPa, phi 30 deg: "
                                                "the local criterion and its bound)"
                                              : "on (f_t 3 MPa, f_c 30 MPa, c 6 MPa, phi 30 deg: checked on every bond)");
  std::printf("  contacts %s\n", !s.contacts_enabled() ? "off"
                                 : a.contacts          ? "on (sweep and prune: two bodies touching along a row)"
                                                       : "on (sweep and prune: bonds can break)");
  std::printf("  threads %d, disk order %s\n", omp_get_max_threads(),
              order == meshing::DiskOrder::Hilbert ? "Hilbert curve" : "rows (as generated)");
  std::printf("  time step %.6g s, %lld steps (energy balance checked every %lld steps)\n", s.dt(),
              static_cast<long long>(steps), static_cast<long long>(kCheckInterval));
  std::printf("  set-up time %.3f s (mesh %.3f s, solver set-up %.3f s)\n", setup_s, mesh_s, setup_s - mesh_s);
  const solver::SetupTimes& st = s.setup_times();
  std::printf("  solver set-up: model %.3f s, random field %.3f s, sets %.3f s, contacts %.3f s, critical step %.3f s "
              "(%d Lanczos iterations on %zu disks: %s), energy scale %.3f s\n",
              st.model, st.random_field, st.sets, st.contacts, st.time_step, s.time_step().finite_iterations,
              s.finite_estimate_disks(), s.finite_estimate_disks() < s.model().num_disks() ? "the edge band" : "the whole model",
              st.energy_scale);
  // CPU time shows how much of the wall time the threads ran (a shared machine).
  std::printf("  step time %.3f s (%.6g s per step; CPU time of all threads %.3f s)\n", step_s, step_s / total_steps,
              step_cpu);
  if (s.contacts_enabled())
    std::printf("  broken bonds %zu, contact pairs %zu, contact detection %.3f s\n", s.broken_bonds(),
                s.contacts().size(), s.detection_seconds());
  // Where the memory is: the members' heap bytes per disk, the largest first.
  const auto census = solver::memory_census(s);
  double held = 0;
  for (const auto& e : census) held += static_cast<double>(e.second);
  std::printf("  memory held after the run %.1f bytes/disk:", held / static_cast<double>(n_disks));
  for (std::size_t k = 0; k < census.size() && k < 16; ++k)
    std::printf("%s %s %.1f", k == 0 ? "" : ",", census[k].first.c_str(),
                static_cast<double>(census[k].second) / static_cast<double>(n_disks));
  std::printf("%s\n", census.size() > 16 ? ", ..." : "");
  std::printf("  peak resident memory %.6g MB (%.6g MB before meshing: %.6g bytes/disk beyond it)\n", peak / 1e6,
              rss_before / 1e6, (peak - rss_before) / static_cast<double>(n_disks));
  std::printf("particle-steps/s: %.6g\n", static_cast<double>(n_disks) * total_steps / step_s);
  std::printf("bond-steps/s: %.6g\n", static_cast<double>(n_bonds) * total_steps / step_s);
  std::printf("peak bytes/disk: %.6g\n", peak / static_cast<double>(n_disks));
  return kExitOk;
}

}  // namespace

Subcommand add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time the solver's step on a square block of about N disks; print particle-steps/s, bond-steps/s "
               "and peak bytes per disk");
  cmd->add_option("--disks", args->disks, "About this many disks, 10..3e8 (default 100000)");
  cmd->add_option("--model", args->model, "Shear model: rotation or local-strain (default local-strain)");
  cmd->add_flag("--failure", args->failure, "Breakable bonds: the failure checks run (strengths too high for breaks)");
  cmd->add_flag("--softening", args->softening, "With --failure: the softening law (fracture energy 100 J/m^2)");
  cmd->add_flag("--contacts", args->contacts, "Two bodies in contact: the contact detection runs every step");
  cmd->add_option("--steps", args->steps, "Time steps to run and time, >= 1 (default 1000)");
  cmd->add_option("--threads", args->threads, "OpenMP threads, 1..1024 (default 1)");
  cmd->add_option("--order", args->order, "Disk order in memory: rows (as generated, the default) or hilbert");
  return {cmd, [args] { return run_bench(*args); }};
}

}  // namespace hexdem::app
