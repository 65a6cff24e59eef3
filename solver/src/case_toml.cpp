/// \file case_toml.cpp
/// Reads case files (format: docs/case-format.md) with toml++.
///
/// Each table's keys are listed once, in a `Key` array: the list gives the allowed keys (any
/// other key is an error, to catch typos), the required ones, the order of reading (a key may
/// rely on the keys before it) and the function that stores the value. Adding a key to the
/// format means adding one entry to one list (and the field to case.hpp).

#include "hexdem/solver/case_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_jitter.hpp"
#include "hexdem/meshing/outline_dxf.hpp"
#include "hexdem/meshing/outline_toml.hpp"
#include "hexdem/meshing/outline_toml_table.hpp"
#include "hexdem/meshing/text.hpp"
#include "hexdem/meshing/toml_values.hpp"

namespace hexdem::solver {

using meshing::describe;
using meshing::format_number;

const Material* Case::find_material(int id) const {
  for (const Material& m : materials)
    if (m.id == id) return &m;
  return nullptr;
}

namespace {

/// "a, b, c" in alphabetical order.
std::string sorted_list(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string child(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string item(std::string_view path, std::size_t index) {
  return std::string(path) + "[" + std::to_string(index) + "]";
}

class Reader;

/// One key of a table: its name, whether it must be given, and how its value is stored into
/// the table's record T. `read` may be null for a key the caller reads itself (`type`).
template <typename T>
struct Key {
  std::string_view name;
  bool required;
  void (*read)(const Reader& in, const toml::node& value, const std::string& path, T& out);
};

template <typename T>
using Keys = std::span<const Key<T>>;

/// The [mesh] table: where the outline comes from, and the lattice options passed to the
/// outline reader (like the command line of `hexdem mesh`).
struct MeshSettings {
  const toml::node* outline = nullptr;  ///< the `outline` value, if given
  std::string outline_file;             ///< as written in the case file
  meshing::ReadOptions options;
  std::int64_t max_disks = meshing::kDefaultMaxDisks;
  meshing::DiskOrder order = meshing::DiskOrder::Rows;
  double jitter = 0.0;
  std::int64_t jitter_seed = 1;
};

/// The allowed choices of a string-valued key.
template <typename E, std::size_t N>
using Choices = std::array<std::pair<std::string_view, E>, N>;

/// One reading of one case file.
class Reader : public meshing::TomlValues {
 public:
  Reader(std::string source, std::string base_dir)
      : TomlValues(std::move(source)), base_dir_(std::move(base_dir)) {}

  Case read(toml::table& root, std::optional<std::int64_t> max_disks);

  using TomlValues::fail;
  using TomlValues::number;
  using TomlValues::positive;
  using TomlValues::text;
  /// "FILE:LINE: PATH" for messages issued after reading (Case::where fields).
  std::string where(const toml::node& at, const std::string& path) const {
    const toml::source_region& r = at.source();
    if (r.path != nullptr && r.path->rfind("--set ", 0) == 0) return source_ + ": " + *r.path + ": " + path;
    return source_ + ":" + std::to_string(r.begin.line) + ": " + path;
  }

  double non_negative(const toml::node& node, const std::string& path) const;
  std::int64_t integer(const toml::node& node, const std::string& path, std::int64_t lo,
                       std::int64_t hi) const;
  bool boolean(const toml::node& node, const std::string& path) const;
  std::string name(const toml::node& node, const std::string& path) const;
  std::vector<std::string> names(const toml::node& node, const std::string& path) const;
  std::array<double, 2> vector2(const toml::node& node, const std::string& path) const;
  const toml::table& table(const toml::node& node, const std::string& path) const;
  TimeFunction time_function(const toml::node& node, const std::string& path) const;
  int axis(const toml::node& node, const std::string& path) const;

  template <typename E, std::size_t N>
  E choice(const toml::node& node, const std::string& path, const Choices<E, N>& choices) const;

  /// Checks for unknown keys, then reads every key of `keys` that is present, in the order of
  /// the list, and fails on a missing required one. `context` qualifies the allowed keys in
  /// messages (e.g. `for type = "pulse"`).
  template <typename T>
  void read_keys(const toml::table& table, const std::string& path, Keys<T> keys, T& out,
                 std::string_view context = {}) const;

 private:
  /// Calls f(table, path, index) for each table of the array of tables `root[key]`.
  template <typename F>
  void for_each_table(const toml::table& root, std::string_view key, F&& f) const;

  void read_case_table(const toml::table& root, Case& c) const;
  MeshSettings read_mesh(const toml::table& root) const;
  void read_outline(toml::table& root, const MeshSettings& mesh, Case& c) const;
  void read_materials(const toml::table& root, Case& c) const;
  void read_boundaries(const toml::table& root, Case& c) const;
  void read_loads(const toml::table& root, Case& c) const;
  void read_initial_velocities(const toml::table& root, Case& c) const;
  void read_time(const toml::table& root, Case& c) const;
  void read_output(const toml::table& root, Case& c) const;
  void read_probes(const toml::table& root, Case& c) const;
  void check_bodies(const Case& c) const;

  /// Fails unless `set` names a boundary set of the outline.
  void check_set(const Case& c, const std::string& set, const toml::node& at,
                 const std::string& path) const;
  /// Fails unless `body` names a body of the outline.
  void check_body(const Case& c, const std::string& body, const toml::node& at,
                  const std::string& path) const;

  std::string base_dir_;
};

// Choices of string-valued keys.

constexpr Choices<Geometry, 3> kGeometries{{{"plane-stress", Geometry::PlaneStress},
                                            {"plane-strain", Geometry::PlaneStrain},
                                            {"axisymmetric", Geometry::Axisymmetric}}};
constexpr Choices<ShearModel, 2> kShearModels{
    {{"local-strain", ShearModel::LocalStrain}, {"rotation", ShearModel::Rotation}}};
constexpr Choices<CapMass, 2> kCapMasses{{{"disk", CapMass::Disk}, {"whole_cell", CapMass::WholeCell}}};
constexpr Choices<meshing::DiskOrder, 2> kDiskOrders{
    {{"rows", meshing::DiskOrder::Rows}, {"hilbert", meshing::DiskOrder::Hilbert}}};
constexpr Choices<PlasticityModel, 4> kPlasticityModels{{{"auto", PlasticityModel::Auto},
                                                        {"spring", PlasticityModel::Spring},
                                                        {"j2", PlasticityModel::J2},
                                                        {"drucker-prager", PlasticityModel::DruckerPrager}}};
constexpr Choices<BoundaryCondition::Kind, 4> kBoundaryKinds{
    {{"fixed", BoundaryCondition::Kind::Fixed},
     {"roller", BoundaryCondition::Kind::Roller},
     {"symmetry", BoundaryCondition::Kind::Symmetry},
     {"velocity", BoundaryCondition::Kind::Velocity}}};
constexpr Choices<Load::Kind, 2> kLoadKinds{
    {{"pressure", Load::Kind::Pressure}, {"body-force", Load::Kind::BodyForce}}};
constexpr Choices<TimeFunction::Kind, 4> kFunctionKinds{
    {{"constant", TimeFunction::Kind::Constant},
     {"pulse", TimeFunction::Kind::Pulse},
     {"ramp-hold", TimeFunction::Kind::RampHold},
     {"table", TimeFunction::Kind::Table}}};
constexpr std::array<std::string_view, 5> kProbeFields{"displacement", "velocity", "stress",
                                                       "rotation", "spin"};

// The keys of every table. The generic lambdas convert to Key::read for their record type.

constexpr std::array<std::string_view, 15> kTopLevelKeys{
    "case", "mesh",   "material", "boundary", "load",    "initial_velocity",
    "time", "output", "probe",    "units",    "lattice", "body", "contact", "wall", "random"};
/// Top-level keys of an inline outline (docs/outline-format.md).
constexpr std::array<std::string_view, 3> kOutlineKeys{"units", "lattice", "body"};

constexpr std::array<Key<Case>, 4> kCaseKeys{{
    {"name", false,
     [](const auto& in, const auto& v, const auto& p, auto& c) {
       c.name = in.name(v, p);
       if (const std::string problem = case_name_problem(c.name); !problem.empty())
         in.fail(v, p, problem + " (got " + describe(v) + ")");
     }},
    {"geometry", true,
     [](const auto& in, const auto& v, const auto& p, auto& c) {
       c.geometry = in.choice(v, p, kGeometries);
     }},
    {"thickness", false,
     [](const auto& in, const auto& v, const auto& p, auto& c) {
       if (c.geometry == Geometry::Axisymmetric)
         in.fail(v, p,
                 "not allowed in axisymmetric mode (quantities are per radian) (got " +
                     describe(v) + ")");
       c.thickness = in.positive(v, p);
       // Beyond these the masses and energies (thickness^2 in the energy check) underflow or
       // overflow a double: the run would fail at its first step as a numerical blow-up.
       if (!(c.thickness >= 1e-100 && c.thickness <= 1e100))
         in.fail(v, p, "must lie in [1e-100, 1e100] m (got " + describe(v) + ")");
     }},
    {"shear_model", false,
     [](const auto& in, const auto& v, const auto& p, auto& c) {
       c.shear_model = in.choice(v, p, kShearModels);
     }},
}};

constexpr std::array<Key<MeshSettings>, 9> kMeshKeys{{
    {"outline", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.outline_file = in.name(v, p);
       m.outline = &v;
     }},
    {"radius", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.options.radius = in.positive(v, p);
     }},
    {"angle", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.options.angle_deg = in.angle(v, p);
     }},
    {"origin", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       const auto o = in.vector2(v, p);
       m.options.origin = meshing::Vec2{o[0], o[1]};
     }},
    {"scale", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.options.scale = in.positive(v, p);
     }},
    {"max_disks", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.max_disks = in.integer(v, p, 1, INT64_MAX);
     }},
    {"order", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.order = in.choice(v, p, kDiskOrders); }},
    {"jitter", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.jitter = in.number(v, p);
       if (!(m.jitter >= 0.0 && m.jitter <= meshing::kMaxJitter))
         in.fail(v, p, "must lie in [0, " + format_number(meshing::kMaxJitter) +
                           "] (a fraction of the disk radius) (got " + describe(v) + ")");
     }},
    {"jitter_seed", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.jitter_seed = in.integer(v, p, 0, INT64_MAX); }},
}};

/// Keys of [[material]]; which of E, nu / c11, c12, c22, c66 are needed is checked after.
constexpr std::array<Key<Material>, 23> kMaterialKeys{{
    {"id", true,
     [](const auto& in, const auto& v, const auto& p, auto& m) {
       m.id = static_cast<int>(in.integer(v, p, 0, INT_MAX));
     }},
    {"name", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.name = in.name(v, p); }},
    {"density", true,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.density = in.number(v, p); }},
    {"E", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.E = in.number(v, p); }},
    {"nu", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.nu = in.number(v, p); }},
    {"c11", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.c.c11 = in.number(v, p); }},
    {"c12", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.c.c12 = in.number(v, p); }},
    {"c22", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.c.c22 = in.number(v, p); }},
    {"c66", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.c.c66 = in.number(v, p); }},
    {"yield_stress", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.yield_stress = in.number(v, p); }},
    {"tangent_modulus", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.tangent_modulus = in.number(v, p); }},
    {"plasticity", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.plasticity = in.choice(v, p, kPlasticityModels); }},
    {"tensile_strength", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.tensile_strength = in.number(v, p); }},
    {"compressive_strength", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.compressive_strength = in.number(v, p); }},
    {"cohesion", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.cohesion = in.number(v, p); }},
    {"friction_angle", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.friction_angle = in.number(v, p); }},
    {"rate_dependent", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.rate_dependent = in.boolean(v, p); }},
    {"friction", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.friction = in.number(v, p); }},
    {"fracture_energy", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.fracture_energy = in.number(v, p); }},
    {"shear_softening", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.shear_softening = in.boolean(v, p); }},
    {"radial_cracks", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.radial_cracks = in.number(v, p); }},
    {"nonlocal_radius", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.nonlocal_radius = in.number(v, p); }},
    {"damage_band", false,
     [](const auto& in, const auto& v, const auto& p, auto& m) { m.damage_band = in.number(v, p); }},
}};
constexpr std::array<std::string_view, 4> kFailureKeys{"tensile_strength", "compressive_strength", "cohesion",
                                                       "friction_angle"};
constexpr std::array<std::string_view, 2> kIsotropicKeys{"E", "nu"};
constexpr std::array<std::string_view, 4> kOrthotropicKeys{"c11", "c12", "c22", "c66"};

// [[boundary]]: `type` selects the key list.
using BC = BoundaryCondition;
constexpr Key<BC> kBoundarySet{
    "set", true,
    [](const auto& in, const auto& v, const auto& p, auto& b) { b.set = in.name(v, p); }};
constexpr Key<BC> kBoundaryType{"type", true, nullptr};
constexpr std::array<Key<BC>, 3> kFixedKeys{{
    kBoundarySet,
    kBoundaryType,
    {"fix_rotation", false,
     [](const auto& in, const auto& v, const auto& p, auto& b) {
       b.fix_rotation = in.boolean(v, p);
     }},
}};
constexpr std::array<Key<BC>, 3> kRollerKeys{{
    kBoundarySet,
    kBoundaryType,
    {"component", true,
     [](const auto& in, const auto& v, const auto& p, auto& b) { b.component = in.axis(v, p); }},
}};
constexpr std::array<Key<BC>, 5> kVelocityKeys{{
    kBoundarySet,
    kBoundaryType,
    {"vx", false,
     [](const auto& in, const auto& v, const auto& p, auto& b) {
       b.velocity[0] = in.number(v, p);
     }},
    {"vy", false,
     [](const auto& in, const auto& v, const auto& p, auto& b) {
       b.velocity[1] = in.number(v, p);
     }},
    {"function", false,
     [](const auto& in, const auto& v, const auto& p, auto& b) {
       b.function = in.time_function(v, p);
     }},
}};

// [[load]]: `type` selects the key list.
constexpr Key<Load> kLoadType{"type", true, nullptr};
constexpr Key<Load> kLoadFunction{"function", false,
                                  [](const auto& in, const auto& v, const auto& p, auto& l) {
                                    l.function = in.time_function(v, p);
                                  }};
constexpr std::array<Key<Window>, 3> kWindowKeys{{
    {"axis", true,
     [](const auto& in, const auto& v, const auto& p, auto& w) { w.axis = in.axis(v, p); }},
    {"min", true,
     [](const auto& in, const auto& v, const auto& p, auto& w) { w.min = in.number(v, p); }},
    {"max", true,
     [](const auto& in, const auto& v, const auto& p, auto& w) {
       w.max = in.number(v, p);
       if (!(w.max > w.min))
         in.fail(v, p, "must be > min = " + format_number(w.min) + " (got " + describe(v) + ")");
     }},
}};
constexpr std::array<Key<Load>, 5> kPressureKeys{{
    kLoadType,
    {"set", true,
     [](const auto& in, const auto& v, const auto& p, auto& l) { l.set = in.name(v, p); }},
    {"p0", true,
     [](const auto& in, const auto& v, const auto& p, auto& l) { l.p0 = in.number(v, p); }},
    {"window", false,
     [](const auto& in, const auto& v, const auto& p, auto& l) {
       Window w;
       in.read_keys(in.table(v, p), p, Keys<Window>(kWindowKeys), w);
       l.window = w;
     }},
    kLoadFunction,
}};
constexpr std::array<Key<Load>, 4> kBodyForceKeys{{
    kLoadType,
    {"acceleration", true,
     [](const auto& in, const auto& v, const auto& p, auto& l) {
       l.acceleration = in.vector2(v, p);
     }},
    {"bodies", false,
     [](const auto& in, const auto& v, const auto& p, auto& l) { l.bodies = in.names(v, p); }},
    kLoadFunction,
}};

constexpr std::array<Key<InitialVelocity>, 2> kInitialVelocityKeys{{
    {"body", true,
     [](const auto& in, const auto& v, const auto& p, auto& iv) { iv.body = in.name(v, p); }},
    {"velocity", true,
     [](const auto& in, const auto& v, const auto& p, auto& iv) {
       iv.velocity = in.vector2(v, p);
     }},
}};

constexpr std::array<Key<TimeControl>, 7> kTimeKeys{{
    {"end", true,
     [](const auto& in, const auto& v, const auto& p, auto& t) { t.end = in.positive(v, p); }},
    {"dt", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) { t.dt = in.positive(v, p); }},
    {"safety", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) {
       t.safety = in.number(v, p);
       if (!(t.safety > 0.0 && t.safety <= 1.0))
         in.fail(v, p, "must lie in (0, 1] (got " + describe(v) + ")");
     }},
    {"allow_unstable", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) {
       t.allow_unstable = in.boolean(v, p);
     }},
    {"mass_damping", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) {
       t.mass_damping = in.non_negative(v, p);
     }},
    {"energy_warning", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) { t.energy_warning = in.positive(v, p); }},
    {"energy_limit", false,
     [](const auto& in, const auto& v, const auto& p, auto& t) {
       t.energy_limit = in.positive(v, p);
       if (t.energy_limit < t.energy_warning)
         in.fail(v, p, "must not be below energy_warning = " + format_number(t.energy_warning) + " (got " +
                           describe(v) + ")");
     }},
}};

constexpr std::array<Key<OutputControl>, 7> kOutputKeys{{
    {"interval", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.interval = in.non_negative(v, p);
     }},
    {"frames", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) { o.frames = in.boolean(v, p); }},
    {"probe_interval", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.probe_interval = in.non_negative(v, p);
     }},
    {"compression_level", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.compression_level = static_cast<int>(in.integer(v, p, 0, 9));
     }},
    {"body_history", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) { o.body_history = in.names(v, p); }},
    {"checkpoint_interval", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.checkpoint_interval = in.non_negative(v, p);
     }},
    {"reactions", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) { o.reactions = in.names(v, p); }},
}};

constexpr std::array<Key<Wall>, 3> kWallKeys{{
    {"point", true,
     [](const auto& in, const auto& v, const auto& p, auto& w) { w.point = in.vector2(v, p); }},
    {"normal", true,
     [](const auto& in, const auto& v, const auto& p, auto& w) {
       const auto n = in.vector2(v, p);
       const double len = std::hypot(n[0], n[1]);
       if (!(len > 0)) in.fail(v, p, "must not be zero (got " + describe(v) + ")");
       w.normal = {n[0] / len, n[1] / len};
     }},
    {"friction", false,
     [](const auto& in, const auto& v, const auto& p, auto& w) { w.friction = in.non_negative(v, p); }},
}};

constexpr std::array<Key<ContactControl>, 4> kContactKeys{{
    {"damping", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.damping = in.non_negative(v, p);
       if (!(o.damping < 1.0)) in.fail(v, p, "must lie in [0, 1) (fraction of critical damping, got " + describe(v) + ")");
     }},
    {"resolution", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.resolution = in.positive(v, p);
       if (!(o.resolution <= 0.9)) in.fail(v, p, "must lie in (0, 0.9] (omega dt of a contact, got " + describe(v) + ")");
     }},
    {"cap_mass", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) { o.cap_mass = in.choice(v, p, kCapMasses); }},
    {"radius_spread", false,
     [](const auto& in, const auto& v, const auto& p, auto& o) {
       o.radius_spread = in.number(v, p);
       if (!(o.radius_spread >= 0.0 && o.radius_spread <= meshing::kMaxRadiusSpread))
         in.fail(v, p, "must lie in [0, " + format_number(meshing::kMaxRadiusSpread) +
                           "] (a fraction of the disk radius) (got " + describe(v) + ")");
     }},
}};

constexpr std::array<Key<RandomField>, 4> kRandomKeys{{
    {"seed", true,
     [](const auto& in, const auto& v, const auto& p, auto& r) { r.seed = in.integer(v, p, 0, INT64_MAX); }},
    {"correlation_length", true,
     [](const auto& in, const auto& v, const auto& p, auto& r) { r.correlation_length = in.positive(v, p); }},
    {"strength_cov", false,
     [](const auto& in, const auto& v, const auto& p, auto& r) {
       r.strength_cov = in.non_negative(v, p);
       if (!(r.strength_cov <= 1.0)) in.fail(v, p, "must lie in [0, 1] (coefficient of variation, got " + describe(v) + ")");
     }},
    {"stiffness_cov", false,
     [](const auto& in, const auto& v, const auto& p, auto& r) {
       r.stiffness_cov = in.non_negative(v, p);
       if (!(r.stiffness_cov <= 1.0))
         in.fail(v, p, "must lie in [0, 1] (coefficient of variation, got " + describe(v) + ")");
     }},
}};

constexpr std::array<Key<Probe>, 3> kProbeKeys{{
    {"name", true,
     [](const auto& in, const auto& v, const auto& p, auto& pr) {
       pr.name = in.name(v, p);
       const bool ok = std::all_of(pr.name.begin(), pr.name.end(), [](char ch) {
         return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_' || ch == '-';
       });
       if (!ok)
         in.fail(v, p, "must consist of letters, digits, '_' and '-' (got " + describe(v) + ")");
     }},
    {"point", true,
     [](const auto& in, const auto& v, const auto& p, auto& pr) { pr.point = in.vector2(v, p); }},
    {"fields", false,
     [](const auto& in, const auto& v, const auto& p, auto& pr) {
       pr.fields = in.names(v, p);
       const toml::array& list = *v.as_array();
       for (std::size_t k = 0; k < pr.fields.size(); ++k) {
         const std::string& field = pr.fields[k];
         if (std::find(kProbeFields.begin(), kProbeFields.end(), field) == kProbeFields.end())
           in.fail(*list.get(k), item(p, k),
                   "unknown field '" + field +
                       "' (fields: displacement, velocity, stress, rotation, spin)");
         if (std::find(pr.fields.begin(), pr.fields.begin() + static_cast<std::ptrdiff_t>(k),
                       field) != pr.fields.begin() + static_cast<std::ptrdiff_t>(k))
           in.fail(*list.get(k), item(p, k), "duplicate field '" + field + "'");
       }
     }},
}};

// Time functions: `type` selects the key list.
constexpr Key<TimeFunction> kFunctionType{"type", true, nullptr};
constexpr std::array<Key<TimeFunction>, 1> kConstantKeys{{kFunctionType}};
constexpr std::array<Key<TimeFunction>, 3> kPulseKeys{{
    kFunctionType,
    {"alpha", true,
     [](const auto& in, const auto& v, const auto& p, auto& f) {
       f.alpha = in.non_negative(v, p);
     }},
    {"beta", true,
     [](const auto& in, const auto& v, const auto& p, auto& f) { f.beta = in.positive(v, p); }},
}};
constexpr std::array<Key<TimeFunction>, 3> kRampHoldKeys{{
    kFunctionType,
    {"t1", true,
     [](const auto& in, const auto& v, const auto& p, auto& f) { f.t1 = in.positive(v, p); }},
    {"t2", true,
     [](const auto& in, const auto& v, const auto& p, auto& f) {
       f.t2 = in.number(v, p);
       if (!(f.t2 >= f.t1))
         in.fail(v, p, "must be >= t1 = " + format_number(f.t1) + " (got " + describe(v) + ")");
     }},
}};
constexpr std::array<Key<TimeFunction>, 2> kTableKeys{{
    kFunctionType,
    {"points", true,
     [](const auto& in, const auto& v, const auto& p, auto& f) {
       const toml::array* list = v.as_array();
       if (list == nullptr || list->size() < 2)
         in.fail(v, p, "expected at least 2 points [[t, value], ...] (got " + describe(v) + ")");
       for (std::size_t k = 0; k < list->size(); ++k) {
         const auto point = in.vector2(*list->get(k), item(p, k));
         if (k > 0 && !(point[0] > f.table.back().first))
           in.fail(*list->get(k), item(p, k),
                   "times must increase (got t = " + format_number(point[0]) +
                       " after t = " + format_number(f.table.back().first) + ")");
         f.table.emplace_back(point[0], point[1]);
       }
     }},
}};

double Reader::non_negative(const toml::node& node, const std::string& path) const {
  const double value = number(node, path);
  if (!(value >= 0.0)) fail(node, path, "must be >= 0 (got " + describe(node) + ")");
  return value;
}

std::int64_t Reader::integer(const toml::node& node, const std::string& path, std::int64_t lo,
                             std::int64_t hi) const {
  const auto* i = node.as_integer();
  if (i == nullptr) fail(node, path, "expected an integer (got " + describe(node) + ")");
  if (i->get() < lo || i->get() > hi)
    fail(node, path,
         "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
             describe(node) + ")");
  return i->get();
}

bool Reader::boolean(const toml::node& node, const std::string& path) const {
  const auto* b = node.as_boolean();
  if (b == nullptr) fail(node, path, "expected true or false (got " + describe(node) + ")");
  return b->get();
}

std::string Reader::name(const toml::node& node, const std::string& path) const {
  std::string value = TomlValues::name(node, path);
  if (value.empty()) fail(node, path, "must not be empty");
  return value;
}

std::vector<std::string> Reader::names(const toml::node& node, const std::string& path) const {
  const toml::array* list = node.as_array();
  if (list == nullptr || list->empty())
    fail(node, path,
         "expected a non-empty array of names [\"...\", ...] (got " + describe(node) + ")");
  std::vector<std::string> out;
  for (std::size_t k = 0; k < list->size(); ++k) out.push_back(name(*list->get(k), item(path, k)));
  return out;
}

std::array<double, 2> Reader::vector2(const toml::node& node, const std::string& path) const {
  const toml::array* list = node.as_array();
  if (list == nullptr || list->size() != 2)
    fail(node, path, "expected a pair [x, y] (got " + describe(node) + ")");
  return {number(*list->get(0), item(path, 0)), number(*list->get(1), item(path, 1))};
}

const toml::table& Reader::table(const toml::node& node, const std::string& path) const {
  const toml::table* t = node.as_table();
  if (t == nullptr) fail(node, path, "expected a table { ... } (got " + describe(node) + ")");
  return *t;
}

int Reader::axis(const toml::node& node, const std::string& path) const {
  static constexpr Choices<int, 4> axes{{{"x", 0}, {"y", 1}, {"r", 0}, {"z", 1}}};
  return choice(node, path, axes);
}

template <typename E, std::size_t N>
E Reader::choice(const toml::node& node, const std::string& path,
                 const Choices<E, N>& choices) const {
  const std::string value = text(node, path);
  std::string list;
  for (const auto& [key, result] : choices) {
    if (key == value) return result;
    list += (list.empty() ? "\"" : ", \"") + std::string(key) + "\"";
  }
  fail(node, path, "expected one of " + list + " (got " + describe(node) + ")");
}

template <typename T>
void Reader::read_keys(const toml::table& table, const std::string& path, Keys<T> keys, T& out,
                       std::string_view context) const {
  for (const auto& [key, node] : table) {
    const bool known =
        std::any_of(keys.begin(), keys.end(), [&](const Key<T>& k) { return k.name == key.str(); });
    if (known) continue;
    std::string list;
    for (const Key<T>& k : keys) list += (list.empty() ? "" : ", ") + std::string(k.name);
    fail(key.source(), path,
         "unknown key '" + meshing::escape_text(key.str()) + "' (allowed" +
             (context.empty() ? "" : " " + std::string(context)) + ": " + list + ")");
  }
  for (const Key<T>& k : keys) {
    if (const toml::node* node = table.get(k.name)) {
      if (k.read != nullptr) k.read(*this, *node, child(path, k.name), out);
    } else if (k.required) {
      fail(table, path, "missing key '" + std::string(k.name) + "'");
    }
  }
}

TimeFunction Reader::time_function(const toml::node& node, const std::string& path) const {
  const toml::table& t = table(node, path);
  const toml::node* type = t.get("type");
  if (type == nullptr)
    fail(t, path,
         "missing key 'type' (\"constant\", \"pulse\", \"ramp-hold\" or \"table\") in " +
             describe(t));
  TimeFunction f;
  f.kind = choice(*type, child(path, "type"), kFunctionKinds);
  const std::string context = "for type = " + describe(*type);
  switch (f.kind) {
    case TimeFunction::Kind::Constant:
      read_keys(t, path, Keys<TimeFunction>(kConstantKeys), f, context);
      break;
    case TimeFunction::Kind::Pulse:
      read_keys(t, path, Keys<TimeFunction>(kPulseKeys), f, context);
      break;
    case TimeFunction::Kind::RampHold:
      read_keys(t, path, Keys<TimeFunction>(kRampHoldKeys), f, context);
      break;
    case TimeFunction::Kind::Table:
      read_keys(t, path, Keys<TimeFunction>(kTableKeys), f, context);
      break;
  }
  return f;
}

template <typename F>
void Reader::for_each_table(const toml::table& root, std::string_view key, F&& f) const {
  const toml::node* node = root.get(key);
  if (node == nullptr) return;
  const toml::array* list = node->as_array();
  if (list != nullptr && list->empty()) return;
  if (list == nullptr || !list->is_array_of_tables()) {
    // A --set that named a table of a missing array made a plain table: say how to add one.
    const toml::source_region& r = node->source();
    const bool from_set = r.path != nullptr && r.path->rfind("--set ", 0) == 0;
    fail(*node, std::string(key),
         "expected [[" + std::string(key) + "]] tables (got " + describe(*node) + ")" +
             (from_set ? "; --set '" + std::string(key) + "+={...}' adds a table" : std::string()));
  }
  for (std::size_t i = 0; i < list->size(); ++i) f(*list->get(i)->as_table(), item(key, i), i);
}

Case Reader::read(toml::table& root, std::optional<std::int64_t> max_disks) {
  for (const auto& [key, node] : root) {
    if (std::find(kTopLevelKeys.begin(), kTopLevelKeys.end(), key.str()) != kTopLevelKeys.end())
      continue;
    std::string list;
    for (std::string_view k : kTopLevelKeys) list += (list.empty() ? "" : ", ") + std::string(k);
    fail(key.source(), "", "unknown key '" + meshing::escape_text(key.str()) + "' (allowed: " + list + ")");
  }

  Case c;
  c.source = source_;
  c.name = std::filesystem::path(source_).stem().string();
  read_case_table(root, c);
  if (c.name == std::filesystem::path(source_).stem().string()) {
    if (const std::string problem = case_name_problem(c.name); !problem.empty())
      throw InputError(source_ + ": the file name does not make a case name: " + problem +
                       " (give [case] name)");
  }
  MeshSettings mesh = read_mesh(root);
  if (max_disks) mesh.max_disks = *max_disks;  // `hexdem run --max-disks N`
  c.max_disks = mesh.max_disks;
  // The outline readers check the limit before they validate the loops.
  mesh.options.max_disks = mesh.max_disks;
  mesh.options.max_disks_hint = kMaxDisksHint;
  c.disk_order = mesh.order;
  c.mesh_jitter = mesh.jitter;
  c.mesh_jitter_seed = mesh.jitter_seed;
  read_outline(root, mesh, c);
  read_materials(root, c);
  check_bodies(c);
  read_boundaries(root, c);
  read_loads(root, c);
  read_initial_velocities(root, c);
  read_time(root, c);
  read_output(root, c);
  read_probes(root, c);
  for_each_table(root, "wall", [&](const toml::table& t, const std::string& path, std::size_t) {
    Wall w;
    read_keys(t, path, Keys<Wall>(kWallKeys), w);
    w.where = where(t, path);
    c.walls.push_back(w);
  });
  return c;
}

void Reader::read_case_table(const toml::table& root, Case& c) const {
  const toml::node* node = root.get("case");
  if (node == nullptr)
    throw InputError(source_ + ": missing table [case] (with at least `geometry`)");
  read_keys(table(*node, "case"), "case", Keys<Case>(kCaseKeys), c);
}

MeshSettings Reader::read_mesh(const toml::table& root) const {
  MeshSettings mesh;
  if (const toml::node* node = root.get("mesh"))
    read_keys(table(*node, "mesh"), "mesh", Keys<MeshSettings>(kMeshKeys), mesh);
  return mesh;
}

void Reader::read_outline(toml::table& root, const MeshSettings& mesh, Case& c) const {
  if (mesh.outline != nullptr) {
    for (std::string_view key : kOutlineKeys) {
      if (const toml::node* node = root.get(key))
        fail(*node, std::string(key),
             "not allowed together with [mesh] outline = \"" + mesh.outline_file +
                 "\" (give the outline in one place)");
    }
    if (mesh.outline_file.empty())
      fail(*mesh.outline, "mesh.outline", "expected the name of a .toml or .dxf outline file (got \"\")");
    std::filesystem::path file(mesh.outline_file);
    if (file.is_relative() && !base_dir_.empty()) file = std::filesystem::path(base_dir_) / file;
    const std::string path = file.lexically_normal().string();
    std::error_code ec;
    if (const auto st = std::filesystem::status(path, ec); !ec && std::filesystem::exists(st) &&
                                                           !std::filesystem::is_regular_file(st) && !std::filesystem::is_directory(st))
      fail(*mesh.outline, "mesh.outline",
           "outline file '" + path + "' is not a regular file (a FIFO, device or socket) (got " +
               describe(*mesh.outline) + ")");
    if (!std::ifstream(path))
      fail(*mesh.outline, "mesh.outline",
           "cannot open outline file '" + path + "' (got " + describe(*mesh.outline) + ")");
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (extension == ".toml") {
      c.outline = meshing::read_outline_toml(path, mesh.options);
    } else if (extension == ".dxf") {
      if (!mesh.options.radius)
        fail(*mesh.outline, "mesh.outline",
             "a DXF outline needs the disk radius: give [mesh] radius (got " +
                 describe(*mesh.outline) + ")");
      c.outline = meshing::read_outline_dxf(path, mesh.options, &c.warnings);
    } else {
      fail(*mesh.outline, "mesh.outline",
           "expected a .toml or .dxf outline file (got " + describe(*mesh.outline) + ")");
    }
  } else {
    if (root.get("body") == nullptr)
      throw InputError(source_ +
                       ": no outline: give [mesh] outline = \"FILE\" or inline [[body]] tables");
    // Move (not copy) the nodes: toml++ keeps source positions on moves only, and the outline
    // reader quotes the case file's lines.
    toml::table part;
    for (auto&& [key, node] : root)
      if (std::find(kOutlineKeys.begin(), kOutlineKeys.end(), key.str()) != kOutlineKeys.end())
        part.insert(key, std::move(node));
    c.outline = meshing::outline_from_toml(part, source_, mesh.options);
  }

  if (c.geometry == Geometry::Axisymmetric) {
    // The meridian half-plane r >= 0 (physics.md section 10).
    for (const meshing::BodyOutline& body : c.outline.bodies) {
      double extent = 0.0;
      for (const meshing::Loop& loop : body.outers)
        for (const meshing::Vec2& p : loop.points)
          extent = std::max({extent, std::abs(p.x), std::abs(p.y)});
      for (const meshing::Loop& loop : body.outers) {
        for (const meshing::Vec2& p : loop.points) {
          if (p.x < -1e-9 * extent)
            throw InputError(body.where + ": axisymmetric bodies must lie in r >= 0 (point (" +
                             format_number(p.x) + ", " + format_number(p.y) + ") m)");
        }
      }
    }
  }
}

void Reader::read_materials(const toml::table& root, Case& c) const {
  for_each_table(root, "material", [&](const toml::table& t, const std::string& path, std::size_t) {
    Material m;
    read_keys(t, path, Keys<Material>(kMaterialKeys), m);
    const auto given = [&](const auto& keys) {
      return std::any_of(keys.begin(), keys.end(),
                         [&](std::string_view k) { return t.contains(k); });
    };
    const bool isotropic = given(kIsotropicKeys), orthotropic = given(kOrthotropicKeys);
    if (isotropic && orthotropic)
      fail(*t.get(t.contains("E") ? "E" : "nu"), path,
           "give either E and nu (isotropic) or c11, c12, c22, c66 (orthotropic), not both");
    if (!isotropic && !orthotropic)
      fail(t, path,
           "missing elastic constants: give E and nu (isotropic) or c11, c12, c22, c66 "
           "(orthotropic)");
    m.isotropic = isotropic;
    const auto require = [&](const auto& keys, const char* kind) {
      for (std::string_view k : keys)
        if (!t.contains(k))
          fail(t, path, "missing key '" + std::string(k) + "' (" + kind + " material)");
    };
    if (isotropic)
      require(kIsotropicKeys, "isotropic");
    else
      require(kOrthotropicKeys, "orthotropic");
    if (m.name.empty()) m.name = "material-" + std::to_string(m.id);
    // Failure needs all of its strengths; plasticity needs both of its keys. A Drucker-Prager
    // material takes its cone from cohesion and friction_angle and does not break.
    const bool dp = m.plasticity == PlasticityModel::DruckerPrager;
    if (dp) {
      for (std::string_view k : {"tensile_strength", "compressive_strength", "fracture_energy"})
        if (const toml::node* n = t.get(k))
          fail(*n, child(path, std::string(k)),
               "plasticity = \"drucker-prager\" disks do not break (releasing a disk's plastic strain at a "
               "break created energy, docs/model.md \"Drucker-Prager disks\"); drop " + std::string(k) +
                   " (got " + describe(*n) + ")");
    }
    m.breakable = !dp && given(kFailureKeys);
    if (m.breakable) require(kFailureKeys, "breakable");
    if (!dp && t.contains("yield_stress") != t.contains("tangent_modulus"))
      fail(t, path, "give both yield_stress and tangent_modulus (plasticity) or neither");
    if (const toml::node* p = t.get("plasticity")) {
      const std::string where = child(path, "plasticity");
      const std::string value = "\"" + std::string(plasticity_model_name(m.plasticity)) + "\"";
      if (dp) {
        // The cone comes from the Mohr-Coulomb pair (Material::drucker_prager); hardening
        // (tangent_modulus) is optional.
        if (const toml::node* y = t.get("yield_stress"))
          fail(*y, child(path, "yield_stress"),
               "\"drucker-prager\" takes its yield from cohesion and friction_angle; drop yield_stress (got " +
                   format_number(m.yield_stress) + ")");
        if (!t.contains("cohesion") || !t.contains("friction_angle"))
          fail(*p, where, "needs cohesion and friction_angle (got " + value + ")");
      } else if (!t.contains("yield_stress")) {
        fail(*p, where, "needs yield_stress and tangent_modulus (got " + value + ")");
      }
      // Disk-level J2 needs the out-of-plane strain (plane strain: zero; axisymmetry: u_r / r)
      // and the local strain of every disk.
      const bool per_disk = m.plasticity == PlasticityModel::J2 || dp;
      if (per_disk && c.geometry == Geometry::PlaneStress)
        fail(*p, where,
             value + " is available in plane strain and axisymmetry only, not in plane stress" +
                 (dp ? std::string() : std::string("; use \"spring\" or \"auto\"")) + " (got " + value + ")");
      if (per_disk && c.shear_model == ShearModel::Rotation)
        fail(*p, where,
             value + " needs [case] shear_model = \"local-strain\", not \"rotation\" (got " + value + ")");
    }

    if (const auto problem = m.check())
      fail(*t.get(problem->key), child(path, problem->key), problem->problem);
    if (!m.isotropic && c.geometry == Geometry::Axisymmetric)
      fail(t, path,
           "material '" + m.name + "' (id " + std::to_string(m.id) +
               "): orthotropic materials are not supported in axisymmetric mode (give E and nu)");
    if (const Material* other = c.find_material(m.id))
      fail(*t.get("id"), child(path, "id"),
           "duplicate material id " + std::to_string(m.id) + " (also material '" + other->name +
               "')");
    c.materials.push_back(std::move(m));
  });
}

void Reader::check_bodies(const Case& c) const {
  for (const meshing::BodyOutline& body : c.outline.bodies) {
    if (c.find_material(body.material) != nullptr) continue;
    std::vector<std::string> ids;
    for (const Material& m : c.materials) ids.push_back(std::to_string(m.id));
    throw InputError(body.where + ": material: no [[material]] with id " +
                     std::to_string(body.material) +
                     (ids.empty() ? std::string(" (the case has no [[material]])")
                                  : " (ids: " + sorted_list(ids) + ")"));
  }
}

void Reader::check_body(const Case& c, const std::string& body, const toml::node& at,
                        const std::string& path) const {
  std::vector<std::string> bodies;
  for (const meshing::BodyOutline& b : c.outline.bodies) bodies.push_back(b.name);
  if (!contains(bodies, body))
    fail(at, path, "unknown body '" + body + "' (bodies: " + sorted_list(bodies) + ")");
}

void Reader::check_set(const Case& c, const std::string& set, const toml::node& at,
                       const std::string& path) const {
  const auto& sets = c.outline.boundary_names;
  if (contains(sets, set)) return;
  fail(at, path,
       "unknown boundary set '" + set + "' (" +
           (sets.empty() ? std::string("the outline has no boundary sets")
                         : "sets: " + sorted_list(sets)) +
           ")");
}

void Reader::read_boundaries(const toml::table& root, Case& c) const {
  for_each_table(root, "boundary", [&](const toml::table& t, const std::string& path, std::size_t) {
    const toml::node* type = t.get("type");
    if (type == nullptr)
      fail(t, path, "missing key 'type' (\"fixed\", \"roller\", \"symmetry\" or \"velocity\")");
    BoundaryCondition b;
    b.kind = choice(*type, child(path, "type"), kBoundaryKinds);
    b.where = where(t, path);
    const std::string context = "for type = " + describe(*type);
    switch (b.kind) {
      case BC::Kind::Fixed:
        read_keys(t, path, Keys<BC>(kFixedKeys), b, context);
        break;
      case BC::Kind::Roller:
      case BC::Kind::Symmetry:
        read_keys(t, path, Keys<BC>(kRollerKeys), b, context);
        break;
      case BC::Kind::Velocity:
        read_keys(t, path, Keys<BC>(kVelocityKeys), b, context);
        if (!b.velocity[0] && !b.velocity[1])
          fail(t, path, "a velocity boundary needs vx and/or vy");
        break;
    }
    check_set(c, b.set, *t.get("set"), child(path, "set"));
    c.boundaries.push_back(std::move(b));
  });
}

void Reader::read_loads(const toml::table& root, Case& c) const {
  for_each_table(root, "load", [&](const toml::table& t, const std::string& path, std::size_t) {
    const toml::node* type = t.get("type");
    if (type == nullptr) fail(t, path, "missing key 'type' (\"pressure\" or \"body-force\")");
    Load load;
    load.kind = choice(*type, child(path, "type"), kLoadKinds);
    load.where = where(t, path);
    const std::string context = "for type = " + describe(*type);
    if (load.kind == Load::Kind::Pressure) {
      read_keys(t, path, Keys<Load>(kPressureKeys), load, context);
      check_set(c, load.set, *t.get("set"), child(path, "set"));
    } else {
      read_keys(t, path, Keys<Load>(kBodyForceKeys), load, context);
      if (const toml::node* bodies = t.get("bodies"))
        for (std::size_t k = 0; k < load.bodies.size(); ++k) {
          const toml::node& at = *bodies->as_array()->get(k);
          check_body(c, load.bodies[k], at, item(child(path, "bodies"), k));
          if (std::find(load.bodies.begin(), load.bodies.begin() + static_cast<std::ptrdiff_t>(k), load.bodies[k]) !=
              load.bodies.begin() + static_cast<std::ptrdiff_t>(k))
            fail(at, item(child(path, "bodies"), k), "duplicate body '" + load.bodies[k] + "'");
        }
    }
    c.loads.push_back(std::move(load));
  });
}

void Reader::read_initial_velocities(const toml::table& root, Case& c) const {
  for_each_table(
      root, "initial_velocity", [&](const toml::table& t, const std::string& path, std::size_t) {
        InitialVelocity iv;
        read_keys(t, path, Keys<InitialVelocity>(kInitialVelocityKeys), iv);
        iv.where = where(t, path);
        const toml::node& body = *t.get("body");
        check_body(c, iv.body, body, child(path, "body"));
        for (const InitialVelocity& other : c.initial_velocities)
          if (other.body == iv.body)
            fail(body, child(path, "body"),
                 "body '" + iv.body + "' already has an initial velocity (" + other.where + ")");
        c.initial_velocities.push_back(std::move(iv));
      });
}

void Reader::read_time(const toml::table& root, Case& c) const {
  const toml::node* node = root.get("time");
  if (node == nullptr) throw InputError(source_ + ": missing table [time] (with at least `end`)");
  const toml::table& t = table(*node, "time");
  read_keys(t, "time", Keys<TimeControl>(kTimeKeys), c.time);
  if (c.time.dt && !(c.time.end / *c.time.dt <= kMaxSteps))
    fail(*t.get("dt"), "time.dt",
         "end / dt = " + format_number(c.time.end / *c.time.dt) + " steps, more than " +
             format_number(kMaxSteps) + " (got dt = " + describe(*t.get("dt")) + ", end = " +
             format_number(c.time.end) + ")");
}

void Reader::read_output(const toml::table& root, Case& c) const {
  if (const toml::node* node = root.get("output")) {
    const toml::table& t = table(*node, "output");
    read_keys(t, "output", Keys<OutputControl>(kOutputKeys), c.output);
    if (const toml::node* bodies = t.get("body_history")) {
      const std::vector<std::string>& names = c.output.body_history;
      for (std::size_t k = 0; k < names.size(); ++k) {
        const toml::node& at = *bodies->as_array()->get(k);
        const std::string path = item("output.body_history", k);
        check_body(c, names[k], at, path);
        if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k), names[k]) !=
            names.begin() + static_cast<std::ptrdiff_t>(k))
          fail(at, path, "duplicate body '" + names[k] + "'");
      }
    }
    if (const toml::node* sets = t.get("reactions")) {
      const std::vector<std::string>& names = c.output.reactions;
      for (std::size_t k = 0; k < names.size(); ++k) {
        const toml::node& at = *sets->as_array()->get(k);
        const std::string path = item("output.reactions", k);
        check_set(c, names[k], at, path);
        if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k), names[k]) !=
            names.begin() + static_cast<std::ptrdiff_t>(k))
          fail(at, path, "duplicate boundary set '" + names[k] + "'");
      }
    }
  }
  if (const toml::node* node = root.get("contact"))
    read_keys(table(*node, "contact"), "contact", Keys<ContactControl>(kContactKeys), c.contact);
  if (const toml::node* node = root.get("random")) {
    RandomField r;
    read_keys(table(*node, "random"), "random", Keys<RandomField>(kRandomKeys), r);
    c.random = r;
  }
}

void Reader::read_probes(const toml::table& root, Case& c) const {
  for_each_table(root, "probe", [&](const toml::table& t, const std::string& path, std::size_t) {
    Probe probe;
    read_keys(t, path, Keys<Probe>(kProbeKeys), probe);
    probe.where = where(t, path);
    // An axisymmetric model lies in r >= 0: a probe at r < 0 would record the disk mirrored
    // across the axis, which the model does not hold.
    if (c.geometry == Geometry::Axisymmetric && !(probe.point[0] >= 0))
      fail(*t.get("point"), child(path, "point"),
           "axisymmetric probes must lie in r >= 0 (got " + describe(*t.get("point")) + ")");
    if (probe.fields.empty()) probe.fields.assign(kProbeFields.begin(), kProbeFields.end());
    for (const Probe& other : c.probes)
      if (other.name == probe.name)
        fail(*t.get("name"), child(path, "name"),
             "duplicate probe name '" + probe.name + "' (" + other.where + ")");
    c.probes.push_back(std::move(probe));
  });
}

// ---- --set overrides (docs/case-format.md, "Overrides") --------------------------------

/// TOML text of a basic string.
std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

/// The table of `list` that `selector` names: by `id`, else `name` (or `body`), else, when no
/// table has an `id`, `name` or `body`, by position. Null if none.
toml::table* select_table(toml::array& list, const std::string& selector, std::string& choices) {
  std::int64_t number = -1;
  const char* end = selector.data() + selector.size();
  const auto [ptr, ec] = std::from_chars(selector.data(), end, number);
  const bool is_number = ec == std::errc() && ptr == end && number >= 0;
  bool named = false;
  std::vector<std::string> seen;
  for (const std::string_view key : {"id", "name", "body"}) {
    for (toml::node& n : list) {
      toml::table* t = n.as_table();
      const toml::node* v = t != nullptr ? t->get(key) : nullptr;
      if (v == nullptr) continue;
      named = true;
      if (const auto* i = v->as_integer()) {
        seen.push_back(std::string(key) + " " + std::to_string(i->get()));
        if (is_number && i->get() == number) return t;
      } else if (const auto* str = v->as_string()) {
        seen.push_back(std::string(key) + " '" + str->get() + "'");
        if (str->get() == selector) return t;
      }
    }
  }
  if (!named && is_number && static_cast<std::size_t>(number) < list.size()) return list.get(static_cast<std::size_t>(number))->as_table();
  if (!named)
    choices = list.size() == 0 ? "there are none" : "select by position 0 to " + std::to_string(list.size() - 1);
  else
    choices = sorted_list(seen);
  return nullptr;
}

void apply_override(toml::table& root, const std::string& spec, const std::string& source_name) {
  const std::string label = "--set " + spec;
  auto fail = [&](const std::string& problem) -> void { throw InputError(source_name + ": " + label + ": " + problem); };
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos) fail("expected KEY=VALUE, e.g. time.end=2e-4");
  // KEY+=VALUE appends VALUE, an inline table or an array of them, to the array of tables KEY.
  const bool append = eq > 0 && spec[eq - 1] == '+';
  const std::string key = spec.substr(0, append ? eq - 1 : eq), value = spec.substr(eq + 1);
  std::vector<std::string> parts;
  for (std::size_t at = 0;;) {
    const std::size_t dot = key.find('.', at);
    parts.push_back(key.substr(at, dot == std::string::npos ? std::string::npos : dot - at));
    if (dot == std::string::npos) break;
    at = dot + 1;
  }
  for (const std::string& part : parts)
    if (part.empty() || part.find_first_of(" \t\"'[]") != std::string::npos)
      fail("bad key '" + key + "' (expected dotted names, e.g. material.1.E)");
  if (value.empty()) fail("missing value after '='");

  // Parse `"a"."b"."c" = VALUE` as its own document named after the --set, so that every
  // node it makes carries that name into the reader's messages; text that is no TOML value
  // is a string.
  std::string dotted;
  for (const std::string& part : parts) dotted += (dotted.empty() ? "" : ".") + toml_string(part);
  toml::table doc;
  if (append) {
    // The new tables, checked before anything is changed.
    try {
      doc = toml::parse(dotted + " = " + value, label);
    } catch (const toml::parse_error& e) {
      fail("expected an inline table such as {name = \"tip\", point = [0, 0.01]} after '+=' (" +
           std::string(e.description()) + ")");
    }
    const auto parent_of = [&](toml::table& d) {
      toml::table* parent = &d;
      for (std::size_t q = 0; q + 1 < parts.size(); ++q) parent = parent->get(parts[q])->as_table();
      return parent;
    };
    const auto value_of = [&](toml::table& d) { return parent_of(d)->get(parts.back()); };
    // One table is parsed again as an array of one, so that the array, as its tables, carries
    // the --set's name into the reader's messages.
    if (value_of(doc)->is_table()) doc = toml::parse(dotted + " = [" + value + "]", label);
    toml::array* tables = value_of(doc)->as_array();
    if (tables == nullptr || tables->empty() || !tables->is_array_of_tables())
      fail("expected an inline table such as {name = \"tip\", point = [0, 0.01]} after '+=' (got " +
           describe(*value_of(doc)) + ")");
    // The array of tables the key names, walked as below; missing parts are created.
    toml::table* dst = &root;
    std::string path;
    for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
      path = child(path, parts[k]);
      toml::node* existing = dst->get(parts[k]);
      if (existing == nullptr) {
        dst->insert(parts[k], toml::table{});
        existing = dst->get(parts[k]);
      }
      if (toml::table* t = existing->as_table()) {
        dst = t;
        continue;
      }
      toml::array* list = existing->as_array();
      if (list == nullptr || !list->is_array_of_tables() || k + 2 >= parts.size())
        fail("'" + path + "' is a value (" + describe(*existing) + "), not a table");
      std::string choices;
      toml::table* chosen = select_table(*list, parts[k + 1], choices);
      if (chosen == nullptr) fail("no [[" + path + "]] table '" + parts[k + 1] + "' (" + choices + ")");
      dst = chosen;
      path = child(path, parts[k + 1]);
      ++k;
    }
    const std::string& last = parts.back();
    path = child(path, last);
    toml::node* existing = dst->get(last);
    if (existing == nullptr) {
      // With the parsed key, whose source names the --set in the reader's messages.
      const auto parsed = parent_of(doc)->find(last);
      dst->insert(parsed->first, std::move(*tables));
      return;
    }
    toml::array* list = existing->as_array();
    if (list == nullptr || !(list->empty() || list->is_array_of_tables()))
      fail("'" + path + "' is not an array of tables (" + describe(*existing) + "): '+=' appends tables to [[" + path +
           "]]");
    for (toml::node& t : *tables) list->push_back(std::move(*t.as_table()));
    return;
  }
  try {
    doc = toml::parse(dotted + " = " + value, label);
  } catch (const toml::parse_error&) {
    doc = toml::parse(dotted + " = " + toml_string(value), label);
  }

  // Walk root and doc together; the first missing part moves doc's subtree into root.
  toml::table* dst = &root;
  toml::table* src = &doc;
  std::string path;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string& part = parts[k];
    auto it = src->find(part);
    toml::node* existing = dst->get(part);
    path = child(path, part);
    if (k + 1 == parts.size() || existing == nullptr) {
      dst->insert_or_assign(it->first, std::move(it->second));
      return;
    }
    if (toml::table* t = existing->as_table()) {
      dst = t;
      src = it->second.as_table();
      continue;
    }
    toml::array* list = existing->as_array();
    if (list == nullptr || !list->is_array_of_tables())
      fail("'" + path + "' is a value (" + describe(*existing) + "), not a table");
    const std::string& selector = parts[k + 1];
    if (k + 2 == parts.size())
      fail("'" + path + "." + selector + "' selects a whole [[" + part + "]] table; give one of its keys");
    std::string choices;
    toml::table* chosen = select_table(*list, selector, choices);
    if (chosen == nullptr)
      fail("no [[" + path + "]] table '" + selector + "' (" + choices + "); '" + path +
           "+={...}' adds one");
    dst = chosen;
    src = it->second.as_table()->get(selector)->as_table();
    path = child(path, selector);
    ++k;
  }
}

/// The case as run, as TOML: the root after the overrides, with the name made explicit and
/// the outline file made absolute, so that the text runs alone from any folder and reads
/// back to itself.
std::string effective_text(const toml::table& root, const std::string& source_name, const std::string& base_dir) {
  toml::table copy = root;
  if (toml::table* c = copy["case"].as_table(); c != nullptr && !c->contains("name"))
    c->insert("name", std::filesystem::path(source_name).stem().string());
  if (toml::table* mesh = copy["mesh"].as_table()) {
    if (const auto* outline = mesh->get_as<std::string>("outline")) {
      std::filesystem::path file(outline->get());
      if (file.is_relative() && !file.empty()) {  // an empty name is refused by read_outline
        file = std::filesystem::absolute(base_dir.empty() ? file : std::filesystem::path(base_dir) / file);
        mesh->insert_or_assign("outline", file.lexically_normal().string());
      }
    }
  }
  std::ostringstream out;
  out << "# The case as run (hexdem run with every --set applied); run it alone with `hexdem run`.\n";
  out << copy << "\n";
  return out.str();
}

}  // namespace

std::string case_name_problem(const std::string& name) {
  if (name.empty()) return "a case name must not be empty";
  if (name == "." || name == "..") return "a case name must be a file name, not '.' or '..'";
  if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
    return "a case name is a file name stem and must not hold '/' or '\\'";
  if (meshing::has_control_character(name))
    return "a case name must not hold control characters";
  if (name.size() > kMaxCaseNameLength)
    return "a case name must have at most " + std::to_string(kMaxCaseNameLength) + " characters";
  return {};
}

Case parse_case(std::string_view text, const std::string& source_name,
                const std::string& base_dir, const std::vector<std::string>& overrides,
                std::optional<std::int64_t> max_disks) {
  toml::table root = meshing::parse_toml(text, source_name);
  for (const std::string& spec : overrides) apply_override(root, spec, source_name);
  std::string effective = effective_text(root, source_name, base_dir);
  Case c = Reader(source_name, base_dir).read(root, max_disks);
  c.effective_toml = std::move(effective);
  return c;
}

Case read_case(const std::string& path, const std::vector<std::string>& overrides,
               std::optional<std::int64_t> max_disks) {
  return parse_case(meshing::read_text_file(path), path, std::filesystem::path(path).parent_path().string(),
                    overrides, max_disks);
}

}  // namespace hexdem::solver
