// hexdem: the command-line program. Subcommands: mesh, run, check, sweep, bench, post.
// Exit codes: 0 success, 1 internal error (a bug), 2 bad input or an output that cannot be written
// (one-line message), 3 a run (or sweep) that reached its end with a run-health warning (energy
// balance above energy_warning), 4 a run that stopped as a failure (numerical blow-up, energy
// balance above energy_limit; a sweep with a member that did not run to its end).
#include <CLI/CLI.hpp>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <cerrno>
#include <cstring>
#include <string>
#include <thread>
#include <vector>
#include <cmath>
#include <cstdlib>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/meshing/lattice_vtu.hpp"
#include "hexdem/meshing/outline_dxf.hpp"
#include "hexdem/meshing/outline_toml.hpp"
#include "hexdem/meshing/toml_values.hpp"
#include "hexdem/meshing/text.hpp"
#include "hexdem/post/post_command.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/output.hpp"
#include "hexdem/version.hpp"
#include "subcommands.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem;

struct MeshArgs {
  std::string outline;
  std::string output;
  double radius = 0.0;
  double angle = 0.0;
  std::vector<double> origin;
  double scale = 0.0;
  bool axisymmetric = false;
  bool quiet = false;
  int threads = 0;
  int compression = 1;
  std::int64_t max_disks = meshing::kDefaultMaxDisks;
  double jitter = 0.0;           ///< --jitter: as [mesh] jitter
  std::int64_t jitter_seed = 1;  ///< --jitter-seed: as [mesh] jitter_seed
};

/// Most OpenMP threads `-j` accepts: libgomp fails (and crashes) creating a hundred thousand.
constexpr int kMaxThreads = 1024;

/// Most OpenMP threads on this machine: 4 x its hardware threads (at most kMaxThreads). Each
/// thread reserves a stack: 1024 of them under a 4 GB address-space limit failed in libgomp,
/// and OMP_NUM_THREADS=100000 crashed it (docs/case-format.md, "Threads").
int machine_max_threads() {
  const unsigned hw = std::thread::hardware_concurrency();
  return static_cast<int>(std::min<long>(kMaxThreads, 4L * std::max(1U, hw)));
}

/// Refuses (InputError) a thread count above machine_max_threads(): `-j N` given, else the
/// environment's OMP_NUM_THREADS (each of its comma-separated levels), which libgomp would use.
void check_thread_count(int j) {
  const int limit = machine_max_threads();
  const std::string bound = std::to_string(limit) + " (4 x the " + std::to_string(std::thread::hardware_concurrency()) +
                            " hardware threads of this machine, at most " + std::to_string(kMaxThreads) + ")";
  if (j > 0) {
    if (j > limit) throw InputError("-j " + std::to_string(j) + ": more threads than " + bound);
    return;
  }
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (env == nullptr) return;
  const std::string value(env);
  std::size_t at = 0;
  while (at <= value.size()) {
    std::size_t end = value.find(',', at);
    if (end == std::string::npos) end = value.size();
    std::string level = value.substr(at, end - at);
    level.erase(0, level.find_first_not_of(" \t"));
    level.erase(level.find_last_not_of(" \t") + 1);
    // Only whole numbers: anything else libgomp itself ignores with a warning.
    if (!level.empty() && std::all_of(level.begin(), level.end(), [](unsigned char ch) { return std::isdigit(ch); })) {
      if (level.size() > 9 || std::stol(level) > limit)
        throw InputError("OMP_NUM_THREADS=" + meshing::escape_text(value) + ": more threads than " + bound +
                         "; lower it or give -j");
    }
    at = end + 1;
  }
}

/// Refuses (InputError) an input that is not a regular file before it is opened: a FIFO
/// would block the open for ever.
void require_regular_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(path + ": " + what + " is not a regular file (a folder, FIFO, device or socket)");
}

/// Whether `output` names the same file as `input` (the same path, or a link to it).
bool same_file(const std::string& input, const std::string& output) {
  std::error_code ec;
  if (fs::equivalent(input, output, ec) && !ec) return true;
  const fs::path a = fs::weakly_canonical(input, ec);
  if (ec) return false;
  const fs::path b = fs::weakly_canonical(output, ec);
  return !ec && a == b;
}

/// `hexdem: error: MESSAGE` on one line (control characters of quoted input escaped).
/// A count option's check: a whole number >= 1 (CLI::PositiveNumber's message printed its
/// range up to the largest double, all 309 digits of it).
const CLI::Validator kWholeNumberAtLeastOne(
    [](std::string& value) -> std::string {
      std::int64_t v = 0;
      const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
      if (r.ec != std::errc() || r.ptr != value.data() + value.size() || v < 1)
        return "must be a whole number >= 1 (got " + value + ")";
      return {};
    },
    "INT>=1");

void print_error(const char* kind, const std::string& message) {
  std::cerr << "hexdem: " << kind << ": " << meshing::one_line(message) << "\n";
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

int run_mesh(const MeshArgs& a, const CLI::App& cmd) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.threads > 0) omp_set_num_threads(a.threads);
  {
    const std::string out = a.output.empty() ? fs::path(a.outline).stem().string() + ".vtu" : a.output;
    if (same_file(a.outline, out))
      throw InputError(out + ": the output is the outline itself (" + a.outline +
                       "); writing it would destroy the input: give another -o");
  }

  meshing::ReadOptions ro;
  if (cmd.count("--radius")) {
    if (!(a.radius > 0)) throw InputError("--radius: must be > 0 (got " + std::to_string(a.radius) + ")");
    ro.radius = a.radius;
  }
  if (cmd.count("--angle")) ro.angle_deg = a.angle;
  if (cmd.count("--origin")) ro.origin = meshing::Vec2{a.origin.at(0), a.origin.at(1)};
  if (cmd.count("--scale")) {
    if (!(a.scale > 0)) throw InputError("--scale: must be > 0 (got " + std::to_string(a.scale) + ")");
    ro.scale = a.scale;
  }
  ro.max_disks = a.max_disks;  // checked before the loops are validated, and again by the generator
  ro.max_disks_hint = "--max-disks N";

  std::vector<std::string> warnings;
  const std::string ext = lower_extension(a.outline);
  meshing::Outline outline;
  if (ext == ".dxf") {
    outline = meshing::read_outline_dxf(a.outline, ro, &warnings);
  } else if (ext == ".toml") {
    outline = meshing::read_outline_toml(a.outline, ro);
  } else {
    throw InputError(a.outline + ": unknown outline format '" + ext + "' (expected .toml or .dxf)");
  }
  for (const std::string& w : warnings) std::cerr << "hexdem: warning: " << w << "\n";

  meshing::GeneratorOptions go;
  go.mode = a.axisymmetric ? meshing::GeometryMode::Axisymmetric : meshing::GeometryMode::Plane;
  go.max_disks = a.max_disks;
  meshing::GeneratorReport rep;
  meshing::Lattice lattice = meshing::generate_lattice(outline, go, &rep);
  const std::int64_t jittered = meshing::jitter_lattice(lattice, a.jitter, static_cast<std::uint64_t>(a.jitter_seed));
  // A scale so small that the cells' areas underflow (--scale 1e-300) gives a lattice of
  // nothing: refused, as no disk fitting is.
  if (!(rep.cell_area_sum > 0) || !std::isfinite(rep.cell_area_sum))
    throw InputError(a.outline + ": the cells' total area is " + meshing::format_number(rep.cell_area_sum) +
                     " m^2" + (cmd.count("--scale") ? " (--scale " + meshing::format_number(a.scale) + ")" : std::string()) +
                     ": the outline's size in metres is out of range; check --scale and the units");

  std::string out = a.output;
  if (out.empty()) out = fs::path(a.outline).stem().string() + ".vtu";
  io::WriteOptions wo;
  wo.compression_level = a.compression;
  meshing::write_lattice_vtu(out, lattice, wo);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (!a.quiet) {
    std::string names;
    for (const auto& n : lattice.body_names) names += (names.empty() ? "" : ", ") + n;
    std::printf("hexdem mesh: %s -> %s (%s)\n", a.outline.c_str(), out.c_str(),
                a.axisymmetric ? "axisymmetric" : "plane");
    std::printf("  bodies      %zu (%s)\n", lattice.body_names.size(), names.c_str());
    std::printf("  disks       %lld (of which semi-disks %lld)\n", static_cast<long long>(rep.disks),
                static_cast<long long>(rep.semi_disks));
    std::printf("  bonds       %lld\n", static_cast<long long>(rep.bonds));
    std::printf("  sets        %zu", lattice.num_sets());
    for (std::size_t s = 0; s < lattice.num_sets(); ++s) {
      std::printf("%s%s (%lld)", s ? ", " : ": ", lattice.set_names[s].c_str(),
                  static_cast<long long>(lattice.set_offset[s + 1] - lattice.set_offset[s]));
    }
    std::printf("\n");
    std::printf("  area        cells %.9g m^2, region %.9g m^2, error %.2e\n", rep.cell_area_sum,
                rep.region_area, rep.area_error());
    std::printf("  smallest cell %.3f of a full hexagon\n", rep.min_cell_fraction);
    if (a.jitter > 0)
      std::printf("  jitter      %lld interior disks moved by up to %.6g r (seed %lld)\n", static_cast<long long>(jittered),
                  a.jitter, static_cast<long long>(a.jitter_seed));
    std::printf("  time        generation %.3f s, total %.3f s\n", rep.seconds, total);
  }
  return kExitOk;
}

struct RunArgs {
  std::string case_file;
  std::string out_dir;
  int threads = 0;
  bool quiet = false;
  std::vector<std::string> sets;  ///< --set KEY=VALUE overrides
  std::string restart;            ///< --restart FILE.chk
  std::optional<std::int64_t> max_disks;
};

int run_run(const RunArgs& a) {
  if (!a.restart.empty()) require_regular_file(a.restart, "the checkpoint (--restart)");
  solver::Case c = solver::read_case(a.case_file, a.sets, a.max_disks);
  for (const std::string& w : c.warnings) std::cerr << "hexdem: warning: " << w << "\n";
  solver::RunOptions ro;
  ro.out_dir = a.out_dir;
  ro.threads = a.threads;
  ro.quiet = a.quiet;
  ro.restart = a.restart;
  ro.progress = !a.quiet && isatty(STDERR_FILENO);
  return solver::run_case(c, ro);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hexdem: discrete element lattices for impact and fracture", "hexdem"};
  app.set_version_flag("--version", std::string("hexdem ") + HEXDEM_VERSION_STRING);
  app.require_subcommand(1);

  MeshArgs mesh;
  CLI::App* mesh_cmd = app.add_subcommand(
      "mesh", "Fill an outline (TOML or DXF) with disks on a hexagonal lattice and write a .vtu");
  mesh_cmd->add_option("outline", mesh.outline, "Outline file (.toml or .dxf)")->required();
  mesh_cmd->add_option("-o,--output", mesh.output, "Output .vtu (default: <outline name>.vtu)");
  mesh_cmd->add_option("-r,--radius", mesh.radius, "Disk radius r [m] (overrides the file's [lattice])");
  mesh_cmd->add_option("-a,--angle", mesh.angle, "Lattice axis angle from x [degrees]")
      ->check(CLI::Range(-meshing::TomlValues::kMaxAngle, meshing::TomlValues::kMaxAngle));
  mesh_cmd->add_option("--origin", mesh.origin, "A lattice point X Y [m]")->expected(2);
  mesh_cmd->add_flag("--axisymmetric", mesh.axisymmetric,
                     "Axisymmetric mode: x is the radius r >= 0, y the axis z");
  mesh_cmd->add_option("--scale", mesh.scale, "Metres per drawing unit (overrides units / $INSUNITS)");
  mesh_cmd->add_option("-j,--threads", mesh.threads, "OpenMP threads (default: all)")
      ->check(CLI::Range(0, kMaxThreads));
  mesh_cmd->add_option("--max-disks", mesh.max_disks,
                       "Refuse outlines estimated to need more disks (default 100000000)")
      ->check(kWholeNumberAtLeastOne);
  mesh_cmd->add_option("--jitter", mesh.jitter,
                       "Move the interior disks off their sites by up to this fraction of r, 0 to 0.3 (as [mesh] jitter)")
      ->check(CLI::Range(0.0, meshing::kMaxJitter));
  mesh_cmd->add_option("--jitter-seed", mesh.jitter_seed, "The jitter's random stream (as [mesh] jitter_seed; default 1)")
      ->check(CLI::Range(std::int64_t{0}, INT64_MAX));
  mesh_cmd->add_option("--compression-level", mesh.compression, "zlib level 0-9 for the .vtu")
      ->check(CLI::Range(0, 9));
  mesh_cmd->add_flag("-q,--quiet", mesh.quiet, "Print nothing on success");

  RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Mesh and run a case file; write a .pvd series, energy and probe CSVs");
  run_cmd->footer(
      "Exit codes: 0 done; 4 numerical blow-up or energy balance failure ([time] energy_limit; the last\n"
      "good frame is kept); 2 bad input or an output that cannot be written; 3 done, but the energy\n"
      "balance passed [time] energy_warning on the way (<case>.status: completed with warning);\n"
      "1 internal error (a bug).");
  run_cmd->add_option("case", run.case_file, "Case file (.toml)")->required();
  run_cmd->add_option("-o,--out", run.out_dir, "Output folder (default: <case name>-output)");
  run_cmd->add_option("-j,--threads", run.threads, "OpenMP threads (default: all)")
      ->check(CLI::Range(0, kMaxThreads));
  run_cmd->add_option("--max-disks", run.max_disks,
                      "Refuse outlines estimated to need more disks (default: [mesh] max_disks, "
                      "else 100000000)")
      ->check(kWholeNumberAtLeastOne);
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print nothing but errors");
  run_cmd->add_option("--set", run.sets, "Override a case value: KEY=VALUE, e.g. time.end=2e-4 or material.1.E=32e9")
      ->allow_extra_args(false)
      ->take_all();
  run_cmd->add_option("--restart", run.restart, "Continue from a checkpoint <case>.chk ([output] checkpoint_interval)");
  const hexdem::app::Subcommand check = hexdem::app::add_check_command(app);
  const hexdem::app::Subcommand sweep = hexdem::app::add_sweep_command(app);
  const hexdem::app::Subcommand bench = hexdem::app::add_bench_command(app);

  const hexdem::post::PostCommand post = hexdem::post::add_post_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print through CLI11; an error is one line, as every other input
    // error (CLI11 would add "Run with --help for more information." on a second line).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    print_error("error", e.what());
    return hexdem::kExitInputError;
  }

  try {
    // The thread count before any OpenMP region starts them (sweep members get -j, bench its
    // own --threads).
    if (*mesh_cmd) check_thread_count(mesh.threads);
    else if (*run_cmd) check_thread_count(run.threads);
    else if (!*sweep.cmd && !*bench.cmd) check_thread_count(0);
    int code = hexdem::kExitOk;
    if (*mesh_cmd) code = run_mesh(mesh, *mesh_cmd);
    else if (*run_cmd) code = run_run(run);
    else if (*check.cmd) code = check.run();
    else if (*sweep.cmd) code = sweep.run();
    else if (*bench.cmd) code = bench.run();
    else if (*post.cmd) code = post.run();
    // A report that could not be written (stdout on a full disk, /dev/full) is not a success.
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int err = errno;
      print_error("error", std::string("cannot write to standard output (") + std::strerror(err) + ")");
      return code == hexdem::kExitOk || code == hexdem::kExitWarning ? hexdem::kExitInputError : code;
    }
    return code;
  } catch (const hexdem::InputError& e) {
    print_error("error", e.what());
    return hexdem::kExitInputError;
  } catch (const std::bad_alloc&) {
    print_error("error", "out of memory");
    return hexdem::kExitFailure;
  } catch (const std::exception& e) {
    print_error("internal error", e.what());
    return hexdem::kExitFailure;
  }
  return hexdem::kExitOk;
}
