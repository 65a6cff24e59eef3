// Checkpoint and restart at the solver level (checkpoint.hpp): the member list covers every
// member of Model and Solver, a round trip restores every stored record exactly, and a
// restored solver continues bit-identically.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;
namespace fs = std::filesystem;

/// A J2 striker on a breakable block (plane strain): plasticity, fracture and contacts.
const char* kImpact = R"([case]
geometry = "plane-strain"
[lattice]
radius = 0.5e-3
[[body]]
name = "target"
material = 1
[[body.shape]]
type = "rectangle"
min = [0, 0]
max = [0.012, 0.005]
boundary = { bottom = "base" }
[[body]]
name = "striker"
material = 2
[[body.shape]]
type = "rectangle"
min = [0.004, 0.0054]
max = [0.008, 0.0084]
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
tensile_strength = 4e6
compressive_strength = 40e6
cohesion = 11.5e6
friction_angle = 30.0
friction = 0.5
[[material]]
id = 2
name = "steel"
density = 7850.0
E = 210e9
nu = 0.3
friction = 0.3
yield_stress = 400e6
tangent_modulus = 2.1e9
plasticity = "j2"
[[boundary]]
set = "base"
type = "fixed"
[[initial_velocity]]
body = "striker"
velocity = [0.0, -200.0]
[contact]
damping = 0.1
[[wall]]
point = [0, -0.0006]  # below the bottom edge's semi-disks at r = 0.5 and 0.6 mm (an overlap at t = 0 is refused)
normal = [0, 1]
[time]
end = 12e-6
)";

std::string temp_path(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("hexdem_test_checkpoint_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return (d / name).string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void advance(Solver& s, int steps) {
  for (int k = 0; k < steps; ++k) ASSERT_TRUE(s.advance(k % 7 == 0)) << s.blow_up().reason;
}

/// 40 more steps of the solver and of its restored copy give the same checkpoint, byte for byte.
void expect_same_continuation(Solver& a, Solver& b, const RunState& run, const std::string& p1, const std::string& p2) {
  advance(a, 40);
  advance(b, 40);
  write_checkpoint(p1, a, run);
  write_checkpoint(p2, b, run);
  EXPECT_TRUE(slurp(p1) == slurp(p2)) << "the continuation differs";
  EXPECT_EQ(a.energy().total(), b.energy().total());
}

/// Writes a's checkpoint, restores it into a fresh solver of the same case and lattice, and
/// checks that both continue identically (expect_same_continuation); `tag` names the files.
void restore_and_continue(const Case& c, const meshing::Lattice& lattice, Solver& a, const std::string& tag) {
  RunState run;
  const std::string p1 = temp_path(tag + "_a.chk"), p2 = temp_path(tag + "_b.chk");
  write_checkpoint(p1, a, run);
  Solver b(c, lattice);
  RunState back;
  read_checkpoint(p1, b, back);
  expect_same_continuation(a, b, run, p1, p2);
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
}

TEST(Checkpoint, MemberListCoversModelAndSolver) {
  const Case c = parse_case(kImpact, "impact.toml", ".");
  const Solver s(c, mesh_case(c));
  const std::vector<std::string> gaps = checkpoint_coverage_gaps(s);
  std::string all;
  for (const std::string& g : gaps) all += g + "\n";
  EXPECT_TRUE(gaps.empty()) << "members missing from visit_model / visit_solver in checkpoint.cpp:\n" << all;
  // Every per-disk and per-bond state vector named in the issue is stored.
  const std::vector<std::string> names = checkpoint_record_names(s);
  for (const char* want : {"model.ux", "model.vx", "model.omega", "model.f_n", "model.u_s", "model.alpha_n",
                           "model.eps_p_xx", "model.beta_33", "model.state", "model.failed_rows", "model.failed_row", "model.plastic_work",
                           "model.disk_plastic_work", "model.minv_xx", "contacts", "wall_fn.0",
                           "energy", "ext_b_before", "damp_a", "step", "time", "run.frame_times", "run.energy_bytes"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
}

TEST(Checkpoint, MemoryCensusCountsEveryHeldArray) {
  // The census that `hexdem bench` prints: each member's heap bytes, largest first.
  const Case c = parse_case(kImpact, "impact.toml", ".");
  const Solver s(c, mesh_case(c));
  const Model& m = s.model();
  const auto census = memory_census(s);
  ASSERT_FALSE(census.empty());
  for (std::size_t k = 1; k < census.size(); ++k) EXPECT_GE(census[k - 1].second, census[k].second);
  const auto bytes = [&](const std::string& name) -> std::size_t {
    for (const auto& [n, b] : census)
      if (n == name) return b;
    return 0;
  };
  EXPECT_EQ(bytes("model.x0"), m.x0.capacity() * sizeof(double));
  EXPECT_EQ(bytes("model.f_n"), m.f_n.capacity() * sizeof(double));
  EXPECT_EQ(bytes("model.state"), m.state.capacity());
  EXPECT_GE(bytes("model.x0"), m.num_disks() * sizeof(double));
  // Contacts are on (bonds break): the broad phase counts its own work space.
  EXPECT_GT(bytes("sweep"), m.num_disks() * 4 * sizeof(double));
  // Empty arrays are not listed.
  for (const auto& [n, b] : census) EXPECT_GT(b, 0u) << n;
}

TEST(Checkpoint, RoundTripRestoresEveryRecordAndContinuesBitIdentically) {
  const Case c = parse_case(kImpact, "impact.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  advance(a, 60);  // past the impact: bonds broken, disks yielded, contacts loaded
  ASSERT_GT(a.broken_bonds(), 0u);
  ASSERT_GT(a.energy().plastic, 0.0);
  RunState run;
  run.next_frame = 1.5e-6;
  run.frames = {{0.0, "impact/impact_000000000.vtu"}, {1e-6, "impact/impact_000000009.vtu"}};
  run.last_frame = "out/impact/impact_000000009.vtu";
  run.energy_bytes = 1234;
  const std::string p1 = temp_path("a.chk"), p2 = temp_path("b.chk");
  write_checkpoint(p1, a, run);
  EXPECT_FALSE(fs::exists(p1 + ".tmp"));

  Solver b(c, lattice);
  RunState back;
  read_checkpoint(p1, b, back);
  EXPECT_EQ(back.next_frame, run.next_frame);
  ASSERT_EQ(back.frames.size(), 2u);
  EXPECT_EQ(back.frames[1].file, run.frames[1].file);
  EXPECT_EQ(back.last_frame, run.last_frame);
  EXPECT_EQ(back.energy_bytes, 1234u);
  // Written again, the restored state is the same file byte for byte: every record round-trips.
  write_checkpoint(p2, b, back);
  EXPECT_TRUE(slurp(p1) == slurp(p2)) << "a record changed in the round trip";

  // Both continue through more contact, fracture and yielding: identical to the bit.
  expect_same_continuation(a, b, run, p1, p2);
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
}

TEST(Checkpoint, DruckerPragerDisksRoundTripAndContinueBitIdentically) {
  // The striker of kImpact made of Drucker-Prager concrete (its yield stress k - alpha p).
  std::string text = kImpact;
  const std::string steel = "yield_stress = 400e6\ntangent_modulus = 2.1e9\nplasticity = \"j2\"\n";
  text.replace(text.find(steel), steel.size(), "cohesion = 11.5e6\nfriction_angle = 30.0\nplasticity = \"drucker-prager\"\n");
  text.replace(text.find("E = 210e9\nnu = 0.3"), 18, "E = 30e9\nnu = 0.2");
  const Case c = parse_case(text, "impact.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  ASSERT_FALSE(a.model().j2.alpha.empty());
  const std::vector<std::string> names = checkpoint_record_names(a);
  EXPECT_NE(std::find(names.begin(), names.end(), "model.j2_alpha"), names.end());
  advance(a, 60);
  ASSERT_GT(a.energy().plastic, 0.0);
  restore_and_continue(c, lattice, a, "dp");
}

TEST(Checkpoint, RandomStrengthAndStiffnessRoundTripAndContinueBitIdentically) {
  // kImpact's target with both random fields ([random]): the stiffness factors are a record,
  // the target's springs are per bond, and the continuation is identical to the bit.
  const std::string text =
      std::string(kImpact) + "[random]\nseed = 3\ncorrelation_length = 2e-3\nstrength_cov = 0.1\nstiffness_cov = 0.2\n";
  const Case c = parse_case(text, "impact.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  ASSERT_FALSE(a.model().stiffness_scale.empty());
  EXPECT_GT(a.time_step().stiffness_max, 1.0);
  const std::vector<std::string> names = checkpoint_record_names(a);
  EXPECT_NE(std::find(names.begin(), names.end(), "model.stiffness_scale"), names.end());
  advance(a, 60);
  ASSERT_GT(a.broken_bonds(), 0u);
  restore_and_continue(c, lattice, a, "rs");
}

TEST(Checkpoint, SmearedDamageRoundTripsAndContinuesBitIdentically) {
  // kImpact's target with smeared damage (damage_band): its damaging bonds' rows (kind 3,
  // their drivers relative to the criteria) are restored, and they stay in the disks' fits.
  const Case c =
      parse_case(kImpact, "impact.toml", ".", {"material.1.fracture_energy=100", "material.1.damage_band=2e-3"});
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  const auto damaging = [](const Model& m) {
    std::size_t n = 0;
    for (std::size_t b = 0; b < m.num_bonds(); ++b) n += m.bond_intact(b) && m.bond_crack(b) == Model::kDamageCrack;
    return n;
  };
  for (int k = 0; k < 4000 && damaging(a.model()) < 5; ++k) ASSERT_TRUE(a.advance(false));
  ASSERT_GE(damaging(a.model()), 5u) << "no bond started to damage";
  advance(a, 20);
  restore_and_continue(c, lattice, a, "sd");
}

/// Runs `c` 60 steps of the impact (bonds broken), checks that its checkpoint continues bit for
/// bit in a new solver of the same case (meshed again), and that the case `other` cannot read it.
void round_trip_then_refuse(const Case& c, Solver& a, const Case& other, const std::string& tag) {
  advance(a, 60);
  ASSERT_GT(a.broken_bonds(), 0u);
  RunState run;
  const std::string p1 = temp_path(tag + "_a.chk"), p2 = temp_path(tag + "_b.chk");
  write_checkpoint(p1, a, run);
  Solver b(c, mesh_case(c));
  RunState back;
  read_checkpoint(p1, b, back);
  expect_same_continuation(a, b, run, p1, p2);
  Solver o(other, mesh_case(other));
  EXPECT_THROW(read_checkpoint(p1, o, back), InputError);
}

TEST(Checkpoint, HilbertOrderedRunRoundTripsAndIsNotTheRowsRun) {
  // The disks along a Hilbert curve ([mesh] order): the checkpoint holds the renumbered state,
  // a restart meshes the same order again, and the rows-ordered case cannot read it.
  const Case c = parse_case(std::string("[mesh]\norder = \"hilbert\"\n") + kImpact, "impact.toml", ".");
  ASSERT_EQ(c.disk_order, meshing::DiskOrder::Hilbert);
  Solver a(c, mesh_case(c));
  round_trip_then_refuse(c, a, parse_case(kImpact, "impact.toml", "."), "h");
}

TEST(Checkpoint, IrregularLatticeRoundTripsAndAnotherSeedIsRefused) {
  // [mesh] jitter: a restart meshes the same moved disks again (the seed and the sites decide
  // them), continues bit for bit with broken bonds touching at their rest length or 2r, and a
  // case with another jitter seed cannot read the checkpoint.
  const Case c = parse_case(std::string("[mesh]\njitter = 0.25\njitter_seed = 4\n") + kImpact, "impact.toml", ".");
  Solver a(c, mesh_case(c));
  ASSERT_TRUE(a.model().touch_at_rest);
  round_trip_then_refuse(c, a, parse_case(std::string("[mesh]\njitter = 0.25\njitter_seed = 5\n") + kImpact, "impact.toml", "."),
                         "j");
}

TEST(Checkpoint, SpreadContactRadiiRoundTripAndAnotherSpreadIsRefused) {
  // [contact] radius_spread: a restart builds the same contact radii again (the seed and the
  // positions decide them) and continues bit for bit; another spread is another case.
  std::string with = kImpact, other = kImpact;
  const std::string contact = "[contact]\n";
  ASSERT_NE(with.find(contact), std::string::npos);
  with.replace(with.find(contact), contact.size(), contact + "radius_spread = 0.13\n");
  other.replace(other.find(contact), contact.size(), contact + "radius_spread = 0.1\n");
  const std::string jitter = "[mesh]\njitter = 0.3\njitter_seed = 4\n";
  const Case c = parse_case(jitter + with, "impact.toml", ".");
  Solver a(c, mesh_case(c));
  ASSERT_FALSE(a.model().contact_radius.empty());
  round_trip_then_refuse(c, a, parse_case(jitter + other, "impact.toml", "."), "s");
}

TEST(Checkpoint, AnotherCaseOrLatticeIsRefused) {
  const Case c = parse_case(kImpact, "impact.toml", ".");
  Solver a(c, mesh_case(c));
  advance(a, 5);
  const std::string p = temp_path("c.chk");
  write_checkpoint(p, a, RunState{});
  // Another material value: another effective case.
  const Case other = parse_case(kImpact, "impact.toml", ".", {"material.1.E=31e9"});
  Solver b(other, mesh_case(other));
  RunState run;
  try {
    read_checkpoint(p, b, run);
    FAIL() << "a checkpoint of another case was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checkpoint of another case"), std::string::npos) << e.what();
  }
  // The same case text on a lattice meshed with another radius.
  Case coarse = c;
  for (auto& body : coarse.outline.bodies) body.radius = 0.6e-3;
  Solver d(coarse, mesh_case(coarse));
  EXPECT_THROW(read_checkpoint(p, d, run), InputError);
}

/// One record of a checkpoint file (checkpoint.hpp, "File layout").
struct RawRecord {
  std::string name;
  std::uint32_t elem = 0;
  std::uint64_t count = 0;
  std::string data;
};

/// Rewrites the checkpoint `from` into `to` with `edit` applied to its records and a fresh
/// checksum: a file whose checksum is valid but whose content is whatever `edit` made it.
void forge(const std::string& from, const std::string& to, const std::function<void(std::vector<RawRecord>&)>& edit) {
  const std::string in = slurp(from);
  constexpr std::size_t header = 8 + 4 + 8 + 8 + 8;
  ASSERT_GE(in.size(), header + 8);
  std::uint64_t count = 0;
  std::memcpy(&count, in.data() + header - 8, 8);
  std::vector<RawRecord> records;
  std::size_t at = header;
  for (std::uint64_t k = 0; k < count; ++k) {
    RawRecord r;
    std::uint32_t len = 0;
    std::memcpy(&len, in.data() + at, 4);
    r.name = in.substr(at + 4, len);
    at += 4 + len;
    std::memcpy(&r.elem, in.data() + at, 4);
    std::memcpy(&r.count, in.data() + at + 4, 8);
    at += 12;
    r.data = in.substr(at, r.elem * r.count);
    at += r.data.size();
    records.push_back(std::move(r));
  }
  ASSERT_EQ(at, in.size() - 8);
  edit(records);
  std::string out = in.substr(0, header - 8);
  auto put = [&out](auto v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(static_cast<std::uint64_t>(records.size()));
  for (const RawRecord& r : records) {
    put(static_cast<std::uint32_t>(r.name.size()));
    out += r.name;
    put(r.elem);
    put(r.count);
    out += r.data;
  }
  put(hash_words(out.data(), out.size()));
  std::ofstream(to, std::ios::binary) << out;
}

RawRecord& record(std::vector<RawRecord>& records, const std::string& name) {
  for (RawRecord& r : records)
    if (r.name == name) return r;
  ADD_FAILURE() << "no record " << name;
  return records.front();
}

/// Sets the T at byte `offset` of element k of a record (offset 0 of an element of size T: the element).
template <class T>
std::function<void(std::vector<RawRecord>&)> set_element(const std::string& name, std::size_t k, T value,
                                                         std::size_t offset = 0) {
  return [=](std::vector<RawRecord>& records) {
    RawRecord& r = record(records, name);
    ASSERT_GE(r.elem, offset + sizeof(T)) << name;
    ASSERT_LT(k, r.count) << name;
    std::memcpy(r.data.data() + k * r.elem + offset, &value, sizeof(T));
  };
}

std::function<void(std::vector<RawRecord>&)> set_text(const std::string& name, const std::string& text) {
  return [=](std::vector<RawRecord>& records) {
    RawRecord& r = record(records, name);
    r.data = text;
    r.count = text.size();
  };
}

TEST(Checkpoint, ForgedContentWithAValidChecksumIsRefused) {
  // A checkpoint whose checksum is right but whose content does not fit the model it is
  // read into: one line naming the file, the record and the value (InputError: exit code 2),
  // before anything reads an index out of range.
  const Case c = parse_case(kImpact, "impact.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  advance(a, 10);
  const std::int64_t disks = static_cast<std::int64_t>(a.model().num_disks());
  const std::int64_t bonds = static_cast<std::int64_t>(a.model().num_bonds());
  RunState run;
  run.frames = {{0.0, "impact/impact_000000000.vtu"}, {a.time() / 2, "impact/impact_000000005.vtu"}};
  run.last_frame = "out/impact/impact_000000005.vtu";
  const std::string good = temp_path("good.chk"), bad = temp_path("forged.chk");
  write_checkpoint(good, a, run);
  {
    // Unchanged, the rewritten file reads (the forging itself changes nothing).
    forge(good, bad, [](std::vector<RawRecord>&) {});
    Solver b(c, lattice);
    RunState back;
    EXPECT_NO_THROW(read_checkpoint(bad, b, back));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Forgery {
    const char* what;
    std::function<void(std::vector<RawRecord>&)> edit;
    std::string message;
  };
  const std::vector<Forgery> forgeries = {
      {"bond end out of range", set_element<std::int32_t>("model.bi", 0, 1000000),
       "record 'model.bi' element 0 is 1000000, outside 0.." + std::to_string(disks - 1)},
      {"negative bond end", set_element<std::int32_t>("model.bj", 3, -1), "record 'model.bj' element 3 is -1"},
      {"bond ends swapped", [](std::vector<RawRecord>& r) {
         std::int32_t i = 0, j = 0;
         std::memcpy(&i, record(r, "model.bi").data.data(), 4);
         std::memcpy(&j, record(r, "model.bj").data.data(), 4);
         std::memcpy(record(r, "model.bi").data.data(), &j, 4);
         std::memcpy(record(r, "model.bj").data.data(), &i, 4);
       }, "record 'model.bj' element 0 is"},
      {"adjacency offset past the entries", set_element<std::int32_t>("model.adj_offset", static_cast<std::size_t>(disks), 100000000),
       "record 'model.adj_offset' element " + std::to_string(disks) + " is 100000000, outside 0.." + std::to_string(2 * bonds)},
      {"adjacency offsets not monotone", set_element<std::int32_t>("model.adj_offset", 2, 0),
       "record 'model.adj_offset' element 2 is 0, below element 1"},
      {"adjacency entry past the bonds", set_element<std::int32_t>("model.adj_entry", 0, 100000000),
       "record 'model.adj_entry' element 0 is 100000000, not a bond"},
      {"adjacency entry ~b past the bonds", set_element<std::int32_t>("model.adj_entry", 1, ~100000000),
       "record 'model.adj_entry' element 1 is -100000001, not a bond"},
      {"bond state out of the enum", set_element<std::uint8_t>("model.state", 0, 200),
       "record 'model.state' element 0 is 200, outside 0..4"},
      {"disk kind out of the enum", set_element<std::uint8_t>("model.kind", 0, 200), "record 'model.kind' element 0 is 200"},
      {"body out of range", set_element<std::int32_t>("model.body", 0, 99), "record 'model.body' element 0 is 99"},
      {"body material not the case's", set_element<std::int32_t>("model.body_material", 0, 99),
       "record 'model.body_material' element 0 is 99"},
      {"moved reference centre", set_element<double>("model.x0", 3, 5.0), "record 'model.x0' element 3 is 5"},
      {"failed row out of range", set_element<std::int32_t>("model.failed_row", 0, 1000000),
       "record 'model.failed_row' element 0 is 1000000"},
      {"short per-disk record", [](std::vector<RawRecord>& r) {
         RawRecord& vx = record(r, "model.vx");
         vx.data.resize(8);
         vx.count = 1;
       }, "record 'model.vx' has 1 elements, the case's model has " + std::to_string(disks)},
      {"contact between missing disks", [](std::vector<RawRecord>& r) {
         RawRecord& ct = record(r, "contacts");  // a contact of no force in front of the list
         const std::int32_t ends[2] = {5000000, 7000000};
         std::string first(ct.elem, '\0');
         std::memcpy(first.data(), ends, sizeof ends);
         ct.data.insert(0, first);
         ++ct.count;
       }, "record 'contacts' element 0 joins disks 5000000 and 7000000"},
      {"NaN time", set_element<double>("time", 0, nan), "record 'time' is nan"},
      {"time past the end", set_element<double>("time", 0, 1.0), "record 'time' is 1, expected a finite value in [0, "},
      {"time not step x dt", set_element<double>("time", 0, 0.5 * a.time()), "but step 10 at dt"},
      {"huge step", set_element<std::int64_t>("step", 0, std::int64_t{1} << 62), "record 'step' is 4611686018427387904"},
      {"negative step", set_element<std::int64_t>("step", 0, -1), "record 'step' is -1"},
      {"NaN time step", set_element<double>("dt_info", 0, nan), "record 'dt_info' holds the time step nan"},
      {"NaN energy", set_element<double>("energy", 0, nan, sizeof(double)), "record 'energy.elastic' is nan"},
      {"NaN frame time", set_element<double>("run.frame_times", 1, nan), "record 'run.frame_times' element 1 is nan"},
      {"NaN next frame", set_element<double>("run.next_frame", 0, nan), "record 'run.next_frame' is nan"},
      {"frame path with ..", set_text("run.frame_files", "impact/impact_000000000.vtu\n../../victim.vtu\n"),
       "record 'run.frame_files' line 2 is '../../victim.vtu'"},
      {"absolute frame path", set_text("run.frame_files", "/tmp/impact/impact_000000000.vtu\nimpact/impact_000000005.vtu\n"),
       "record 'run.frame_files' line 1 is '/tmp/impact/impact_000000000.vtu'"},
      {"frame of another folder", set_text("run.frame_files", "impact/impact_000000000.vtu\nimpact/../impact/impact_000000005.vtu\n"),
       "record 'run.frame_files' line 2"},
      {"duplicate record", [](std::vector<RawRecord>& r) { r.push_back(record(r, "step")); }, "record 'step' appears twice"},
      {"NaN displacement", set_element<double>("model.ux", 7, nan), "record 'model.ux' element 7 is nan, not finite"},
      {"infinite velocity", set_element<double>("model.vy", 2, std::numeric_limits<double>::infinity()),
       "record 'model.vy' element 2 is inf, not finite"},
      {"NaN shear force", set_element<double>("model.f_s", 0, nan), "record 'model.f_s' element 0 is nan, not finite"},
  };
  const Solver fresh(c, lattice);
  for (const Forgery& f : forgeries) {
    SCOPED_TRACE(f.what);
    forge(good, bad, f.edit);
    Solver b = fresh;  // a solver freshly built from the case, as `hexdem run --restart` reads into
    RunState back;
    try {
      read_checkpoint(bad, b, back);
      ADD_FAILURE() << "a forged checkpoint (" << f.what << ") was read";
    } catch (const InputError& e) {
      const std::string text = e.what();
      EXPECT_EQ(text.rfind(bad + ": damaged checkpoint: ", 0), 0u) << text;
      EXPECT_NE(text.find(f.message), std::string::npos) << text;
      EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    }
  }
}

TEST(Checkpoint, ForgedCrackStateIsRefused) {
  // The block with a fracture energy: its bonds soften, and a cracking bond's crack state
  // (damage, drivers, kind) is in its failed bond's row. A row that does not hold a crack
  // of a known kind, holds a non-finite value, or an intact bond's row without a crack
  // (an intact bond has a row exactly while it cracks) is a damaged checkpoint.
  const Case c = parse_case(kImpact, "impact.toml", ".", {"material.1.fracture_energy=100"});
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  const auto cracking_bond = [](const Model& m) -> std::int64_t {
    for (std::size_t b = 0; b < m.num_bonds(); ++b)
      if (m.bond_intact(b) && m.bond_crack(b) != Model::kNoCrack) return static_cast<std::int64_t>(b);
    return -1;
  };
  for (int k = 0; k < 4000 && cracking_bond(a.model()) < 0; ++k) ASSERT_TRUE(a.advance(false));
  const std::int64_t b = cracking_bond(a.model());
  ASSERT_GE(b, 0) << "no bond started to crack";
  const Model& m = a.model();
  const auto row = static_cast<std::size_t>(m.failed_row[static_cast<std::size_t>(b)]);
  EXPECT_GT(m.failed_rows[row].delta_f, m.failed_rows[row].delta0) << "the row holds the crack's drivers";
  const std::string good = temp_path("crack_good.chk"), bad = temp_path("crack_forged.chk");
  write_checkpoint(good, a, RunState{});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string at = "record 'model.failed_rows' row " + std::to_string(row);
  const std::vector<std::tuple<const char*, std::function<void(std::vector<RawRecord>&)>, std::string>> forgeries = {
      {"unknown crack kind", set_element<std::int64_t>("model.failed_rows", row, 7, offsetof(Model::FailedBond, crack)),
       at + " crack is 7, not 0, 1, 2 or 3"},
      {"NaN damage", set_element<double>("model.failed_rows", row, nan, offsetof(Model::FailedBond, damage)),
       at + " damage is nan, not finite"},
      {"infinite failure driver", set_element<double>("model.failed_rows", row, std::numeric_limits<double>::infinity(),
                                                      offsetof(Model::FailedBond, delta_f)),
       at + " delta_f is inf, not finite"},
      {"cracking bond without a crack", set_element<std::int64_t>("model.failed_rows", row, 0, offsetof(Model::FailedBond, crack)),
       "gives intact bond " + std::to_string(b) + " a row that holds no crack"},
  };
  {
    forge(good, bad, [](std::vector<RawRecord>&) {});
    Solver back(c, lattice);
    RunState run;
    EXPECT_NO_THROW(read_checkpoint(bad, back, run));
  }
  for (const auto& [what, edit, message] : forgeries) {
    SCOPED_TRACE(what);
    forge(good, bad, edit);
    Solver back(c, lattice);
    RunState run;
    try {
      read_checkpoint(bad, back, run);
      ADD_FAILURE() << "a forged checkpoint (" << what << ") was read";
    } catch (const InputError& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find(message), std::string::npos) << text;
      EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    }
  }
}

}  // namespace
