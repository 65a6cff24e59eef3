#pragma once
/// \file output.hpp
/// Run output (docs/file-format.md): `DIR/<case>.pvd` with one `.vtu` per frame in
/// `DIR/<case>/`, `DIR/<case>.energy.csv` (Eq. 25 per output step), `DIR/<case>.probes.csv`,
/// `DIR/<case>.bodies.csv` (rigid-body histories of the `[output] body_history` bodies) and
/// `DIR/<case>.reactions.csv` (forces of the `[output] reactions` sets, N or N/rad).
/// Frames and the .pvd are written atomically (temporary name, then rename), so an
/// interrupted run leaves only complete frames and a .pvd that lists them.

#include <array>
#include <cstdint>
#include <fstream>
#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/solver.hpp"

namespace hexdem::solver {

/// A CSV file written in whole rows: rows collect in memory and reach the file at flush(),
/// in writes that never cross a 4 KiB page of the file, laid out so that no row straddles a
/// page boundary (a row that ends a page is preceded by blanks), so that a killed run leaves
/// whole rows (rows_fit_pages() says when a file is too wide for that). Every write is checked:
/// a failure throws InputError naming the file and the reason (a full disk is not success).
class CsvFile {
public:
  CsvFile() = default;
  CsvFile(const CsvFile&) = delete;
  CsvFile& operator=(const CsvFile&) = delete;
  ~CsvFile();

  /// Creates (truncates) the file, or with `append` continues it (a restart); throws
  /// InputError "PATH: cannot write (reason)".
  void open(const std::string& path, bool append = false);
  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  CsvFile& operator<<(std::string_view text) {
    buffer_.append(text);
    return *this;
  }
  CsvFile& operator<<(char c) {
    buffer_.push_back(c);
    return *this;
  }
  CsvFile& operator<<(std::int64_t v) { return *this << std::string_view(std::to_string(v)); }
  /// Writes the rows collected so far (call after a whole row).
  void flush();
  /// Flushes and closes, checking the close.
  void close();
  /// The layout unit: Linux stops a killed process's write() only at a page boundary.
  static constexpr std::uint64_t kPage = 4096;
  /// Whether rows are laid out to never straddle a page (false for files whose rows can be
  /// longer than half a page); known after the first flush.
  [[nodiscard]] bool rows_fit_pages() const { return max_row_ != 0 && max_row_ <= kPage / 2; }

private:
  std::string path_;
  std::string buffer_;
  std::string layout_;        ///< the rows of one flush with their padding (reused)
  std::size_t max_row_ = 0;   ///< bytes of the longest possible row, from the column count
  std::uint64_t written_ = 0;  ///< bytes in the file
  int fd_ = -1;
};

/// Creates `dir` and its parents; InputError naming the folder and the reason otherwise (a
/// file of that name, no permission). For `hexdem run` and `hexdem sweep`.
void make_folder(const std::string& dir);

class RunOutput {
public:
  /// Creates DIR (and DIR/<case>/, emptied of old frames of this case) and opens the CSVs.
  /// Throws InputError naming the path and the reason if it cannot.
  RunOutput(const Solver& solver, const std::string& dir);
  /// Continues the output of a run from a checkpoint's `resume` state: keeps the frames it
  /// lists (removes later ones of this case), rewrites the .pvd with them, and truncates the
  /// CSVs to the recorded sizes to append from there. Throws InputError if a CSV is missing
  /// or shorter than recorded (restart in the folder the checkpoint was written for).
  RunOutput(const Solver& solver, const std::string& dir, const RunState& resume);
  /// The output's part of a checkpoint: frames written, last frame, CSV sizes (flushed).
  void save_state(RunState& state);

  /// Writes a frame of the state at t_n (call from Solver::advance's at_tn, after the CSV
  /// rows of t_n) and rewrites the .pvd. Flushes the CSVs first, so that every CSV reaches
  /// at least the last frame the .pvd lists.
  void write_frame(const Solver& solver);
  /// Appends the energy balance at t_n (requires advance(diagnostics = true)) and flushes
  /// every CSV.
  void write_energy(const Solver& solver);
  /// Appends one row of the reactions of the `[output] reactions` sets at t_n (call with
  /// the energy row, before write_energy, which flushes it; no-op without the key):
  /// `<set>.fx`, `<set>.fy` per set (Solver::reaction). Allocates nothing.
  void write_reactions(const Solver& solver);
  /// Appends one row of probe values at t_n.
  void write_probes(const Solver& solver);
  /// Appends one row of body histories at t_n (no-op without `[output] body_history`).
  /// Per body: mass, centre of mass, mass-averaged velocity, momentum and the leap-frog
  /// kinetic energy `1/2 m v(t-dt/2).v(t+dt/2)` plus spin (the energy balance's form, so the
  /// bodies' kinetic energies add up to its `kinetic`). Allocates nothing.
  void write_bodies(const Solver& solver);

  /// Writes `<case>.status` (one line; replaced atomically): `running` while the run goes,
  /// `completed` at its end, `completed with warning: <warning>` when a run-health warning
  /// fired (exit code 3), or `failed: <reason>` (docs/file-format.md). Analysis scripts refuse
  /// a series that did not complete, and pass the warning on.
  void write_status(const std::string& line);
  /// Lists every frame in the .pvd, writes out and closes the CSVs (end of a run, or of a
  /// stopped one); throws InputError on a failed write.
  void finish();
  /// Writes what the CSVs hold (all whole rows).
  void flush_csvs();

  [[nodiscard]] const std::string& pvd_path() const { return pvd_path_; }
  [[nodiscard]] const std::string& status_path() const { return status_path_; }
  [[nodiscard]] const std::string& energy_path() const { return energy_path_; }
  [[nodiscard]] const std::string& probes_path() const { return probes_path_; }
  [[nodiscard]] const std::string& bodies_path() const { return bodies_path_; }
  [[nodiscard]] const std::string& reactions_path() const { return reactions_path_; }
  [[nodiscard]] const std::string& last_frame() const { return last_frame_; }
  [[nodiscard]] std::size_t frames() const { return pvd_.size(); }

  /// Contacts written as extra line cells (buffers that must outlive the write).
  struct ContactCells {
    std::vector<std::int32_t> i, j;
    std::vector<double> f_n, f_s;
  };
  /// The frame's grid description (exposed for tests of the frame contract).
  static io::LineGrid frame_grid(const Solver& solver, ContactCells& contacts);

private:
  /// Checks everything that can refuse the run (probes, body histories, and on a restart the
  /// checkpoint's frames and CSVs) before the folder is touched, then prepares the folder: a
  /// refused run leaves a finished folder as it was (its status, frames, .pvd and CSVs).
  void open(const Solver& solver, const RunState* resume);
  /// Restart: checks that `path` holds at least `bytes` whose hash is `hash` (the run's own
  /// rows); changes nothing.
  static void check_for_restart(const std::string& path, std::uint64_t bytes, std::uint64_t hash);
  /// Restart, after every check passed: cuts `path` to `bytes`.
  static void truncate_for_restart(const std::string& path, std::uint64_t bytes);

  struct ProbePoint {
    std::size_t disk;
    std::vector<std::string> fields;
  };
  std::string dir_, frame_dir_, name_;
  std::string pvd_path_, energy_path_, probes_path_, bodies_path_, reactions_path_, status_path_, last_frame_;
  std::vector<io::PvdEntry> pvd_;
  std::size_t pvd_listed_ = 0;  ///< frames the .pvd on disk lists (list_frames)
  std::chrono::steady_clock::time_point pvd_written_{};
  /// Rewrites the .pvd with every frame written: always with `all`, otherwise after each of
  /// the first 16 frames, then once 1/16 more have come or 2 s have passed, so that a series
  /// of N frames costs O(N) in rewrites, not O(N^2). A reader always finds whole frames listed.
  void list_frames(bool all);
  CsvFile energy_, probes_, bodies_, reactions_;
  std::vector<ProbePoint> probe_points_;
  /// Body histories: slot of each body index (-1: not recorded), and the per-slot sums
  /// (m, m x, m y, m vx, m vy, kinetic) reused for every row.
  std::vector<int> body_slot_;
  std::vector<std::array<double, 6>> body_sums_;
  ContactCells contact_cells_;
  int compression_level_ = 1;
};

/// Options of `hexdem run`.
struct RunOptions {
  std::string out_dir;     ///< output folder (default: "<case>-output" beside the working dir)
  int threads = 0;         ///< OpenMP threads (0: the runtime's default)
  bool progress = false;   ///< a progress line on stderr
  bool quiet = false;      ///< no summary on stdout
  /// Checkpoint to continue from (`--restart`); empty: start at t = 0.
  std::string restart;
};

/// Meshes and runs a case. Returns the exit code: 0 on success, 1 on a numerical blow-up or
/// an energy balance failure (reported on stderr with the last good frame), 3 when the run
/// reached its end time with a run-health warning (its energy error passed
/// `[time] energy_warning`). Throws InputError on bad input.
int run_case(const Case& c, const RunOptions& options);

}  // namespace hexdem::solver
