#pragma once
/// \file checkpoint.hpp
/// Checkpoint and restart (docs/file-format.md, "Checkpoints"): the complete state of a run
/// (every per-disk and per-bond state vector of the Model, the Solver's contacts, wall
/// forces, energy ledger and trapezoid sums, step and time, and the output state of
/// `hexdem run`) in one binary file, written atomically: a temporary file in the same
/// folder, fsync, rename, fsync of the folder. A process killed while writing leaves the
/// previous checkpoint intact.
///
/// File layout (little-endian, as the machine writes it): the magic "HEXDEMCK", the format
/// version (u32), a hash of the effective case text (u64) and of the lattice (u64), the
/// number of records (u64), then per record its name (u32 length + bytes), element size
/// (u32), element count (u64) and the raw elements, and last an FNV-1a checksum (u64) of
/// everything before it. Records are found by name, so their order does not matter.
///
/// The broad phase of the contacts is not stored: it is rebuilt from the stored centres.
/// The candidate list may then differ from the uninterrupted run's, but only by pairs that
/// are apart and carry no force, so every force, energy and output is bit-identical.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/solver/solver.hpp"

namespace hexdem::solver {

/// Version of the checkpoint layout; a file of another version is refused. 2: the run state
/// records how far `<case>.reactions.csv` got (run.reactions_bytes, run.reactions_hash).
/// 3: the kinetic half step of breaks (model.break_kinetic, model.hoop_break_kinetic).
/// 4: the time-step record holds the Lanczos iteration count (dt_info.finite_iterations).
/// 5: spring stiffnesses per spring kind in plane models, no reference bond vectors.
/// 6: no adjacency reference vectors or signs (model.adj_entry), 32-bit adjacency offsets,
/// the material per body, the failed bonds' rows (model.failed_rows, model.failed_row).
/// 7: the Drucker-Prager disks (model.j2_alpha).
/// 8: no stored neighbour per adjacency entry, no shear displacement in an elastic lattice.
/// 9: the slip of a softening shear crack's faces in the failed bonds' rows (FailedBond::slip).
/// 10: an elastic lattice keeps each bond's pair force, not f_n, nx and ny. 11: the lattice
/// hash and the checksum take 8 bytes at a time.
/// 12: a softening bond's crack state (damage, kappa, delta0, delta_f and its kind) in its
/// failed bond's row, not per bond. 13: the random stiffness field's factor per bond.
inline constexpr std::uint32_t kCheckpointVersion = 13;

/// The run loop's own state (`hexdem run`), stored with the solver's.
struct RunState {
  double next_frame = 0;       ///< simulated time of the next frame [s]
  double next_probe = 0;       ///< of the next probe row [s]
  double next_checkpoint = 0;  ///< of the next checkpoint [s]
  double max_error = 0;        ///< largest |relative energy error| so far
  std::vector<io::PvdEntry> frames;  ///< frames written so far (the .pvd's entries)
  std::string last_frame;            ///< path of the last frame written
  /// Bytes of the energy, probe, body and reaction CSVs when the checkpoint was written: a
  /// restart truncates them there and appends.
  std::uint64_t energy_bytes = 0, probes_bytes = 0, bodies_bytes = 0, reactions_bytes = 0;
  /// FNV-1a hashes of those first bytes: a restart refuses CSVs another run has rewritten.
  std::uint64_t energy_hash = 0, probes_hash = 0, bodies_hash = 0, reactions_hash = 0;
};

/// FNV-1a 64-bit hash of bytes (the case's text and the CSVs' prefixes).
std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t h = 14695981039346656037ull);

/// 64-bit hash of bytes taken 8 at a time (the lattice's fingerprint and the file's checksum):
/// h = (h xor w) * 0x9e3779b97f4a7c15, then h xor= h >> 32, per little-endian word w; the last
/// size mod 8 bytes as FNV-1a. Each step is a bijection of h, so two inputs of one length that
/// differ in one word always hash apart. About 5 times as fast as FNV-1a, which takes a byte per
/// multiply (0.09 s of the set-up at 1,000,000 disks).
std::uint64_t hash_words(const void* data, std::size_t size, std::uint64_t h = 14695981039346656037ull);

/// Hash of the case as run: its effective TOML text (Case::effective_toml, the file with
/// every --set applied), or, for a Case built in code, its name and source.
std::uint64_t case_hash(const Case& c);
/// Hash of the solver's lattice and model layout: reference centres, radii, bodies,
/// materials, bonds and masses.
std::uint64_t lattice_hash(const meshing::Lattice& lattice);

/// Writes the checkpoint of `s` and `run` to `path` atomically. Throws std::runtime_error
/// naming the path if it cannot write.
void write_checkpoint(const std::string& path, const Solver& s, const RunState& run);

/// Reads a checkpoint into `s`, a Solver freshly built from the same case, and `run`.
/// Throws InputError with a one-line message naming the file if it is not a checkpoint, is
/// truncated or damaged, has another format version, or belongs to another case or lattice,
/// and, before returning, if its content does not fit the model and the run (a checksum
/// proves only that the file is the one written): the record and the offending value of a
/// vector of the wrong length, an index out of range (bond ends, adjacency, bodies, failed
/// rows, contacts), an enumerated value that is none of its values, a constant of the model
/// that is not the one the case builds, a time, step or time step that is not finite or
/// outside the run, or a frame that is not `<case>/<case>_<step>.vtu` in the output folder
/// (docs/file-format.md, "Checkpoints"). `s` may then hold part of the checkpoint.
void read_checkpoint(const std::string& path, Solver& s, RunState& run);

/// Members of Model and Solver that the checkpoint's list of members does not cover
/// (neither stored nor declared rebuilt at construction), as "Model: N bytes at offset O
/// after 'name'". Empty when the list is complete: a test fails when a member is added to
/// Model or Solver without being added to the list in checkpoint.cpp.
std::vector<std::string> checkpoint_coverage_gaps(const Solver& s);

/// Heap bytes held by each member of Solver and its Model that the checkpoint's member lists
/// name (vectors by capacity, the contact broad phase by its own count), largest first, as
/// ("model.f_n", bytes): the memory census that `hexdem bench` prints.
std::vector<std::pair<std::string, std::size_t>> memory_census(const Solver& s);

/// Names of the records a checkpoint of `s` holds (for tests and documentation).
std::vector<std::string> checkpoint_record_names(const Solver& s);

/// Access to the Solver's private state for the checkpoint (a friend of Solver).
struct CheckpointAccess;

}  // namespace hexdem::solver
