#pragma once
/// \file case.hpp
/// A simulation case as read from a case file (docs/case-format.md). SI units throughout:
/// m, s, kg, Pa, N. The Case owns its data; the Outline is meshed by the solver at set-up.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/lattice_order.hpp"
#include "hexdem/meshing/outline.hpp"
#include "hexdem/solver/material.hpp"
#include "hexdem/solver/time_function.hpp"

namespace hexdem::solver {

/// How a case's user raises the disk limit, in the too-many-disks message.
inline constexpr const char* kMaxDisksHint = "[mesh] max_disks = N or --max-disks N";

/// Boundary condition on a named boundary set.
struct BoundaryCondition {
  enum class Kind {
    Fixed,     ///< both velocity components zero (and the spin, if fix_rotation)
    Roller,    ///< one velocity component zero: `component`
    Symmetry,  ///< mirror plane along x = const or y = const: `component` is the normal one;
               ///< disks on the plane are rollers with mirror-symmetric local strain, and
               ///< the bonds that would cross the plane to a disk's own mirror image act as
               ///< springs to the plane
    Velocity,  ///< prescribed velocity components, times `function`
  };
  Kind kind = Kind::Fixed;
  std::string set;                  ///< boundary set name (must exist in the lattice)
  int component = 0;                ///< Roller, Symmetry: 0 = x (r), 1 = y (z)
  std::array<std::optional<double>, 2> velocity;  ///< Velocity: [m/s], unset = free
  TimeFunction function;            ///< Velocity: amplitude factor
  bool fix_rotation = false;        ///< Fixed: also hold the disk spins at zero
  std::string where;                ///< "case.toml: boundary[2]" for messages
};

/// Spatial window of a load: only disks whose centre coordinate lies in [min, max].
struct Window {
  int axis = 0;       ///< 0 = x (r), 1 = y (z)
  double min = 0, max = 0;  ///< [m]
};

/// A load: pressure on a boundary set, or a body force (acceleration) on bodies.
struct Load {
  enum class Kind { Pressure, BodyForce };
  Kind kind = Kind::Pressure;
  std::string set;                    ///< Pressure: boundary set name
  double p0 = 0;                      ///< Pressure magnitude [Pa] (compression positive)
  std::optional<Window> window;       ///< Pressure: optional spatial window (Eq. 21's H(a-|x|))
  std::array<double, 2> acceleration{0, 0};  ///< BodyForce [m/s^2]
  std::vector<std::string> bodies;    ///< BodyForce: bodies (empty = all)
  TimeFunction function;              ///< amplitude factor over time
  std::string where;
};

/// Initial velocity of a body (e.g. a projectile).
struct InitialVelocity {
  std::string body;
  std::array<double, 2> velocity{0, 0};  ///< [m/s]
  std::string where;
};

/// A probe: time histories of fields at the disk nearest to a point.
struct Probe {
  std::string name;
  std::array<double, 2> point{0, 0};  ///< [m]
  std::vector<std::string> fields;    ///< any of: displacement, velocity, stress, rotation, spin
  std::string where;
};

/// The default [time] safety. The contacts' stiffness cap refers to this fraction of the
/// critical step whatever the step used (Solver::setup_contact_resolution).
inline constexpr double kDefaultSafety = 0.9;

struct TimeControl {
  double end = 0;                 ///< end time [s] (> 0)
  std::optional<double> dt;       ///< user time step [s]; default safety * critical step
  double safety = kDefaultSafety; ///< fraction of the critical step when dt is not given
  bool allow_unstable = false;    ///< accept a dt above the critical step (stability study)
  double mass_damping = 0;        ///< alpha of Eq. 18 [1/s]
  /// Run health (docs/case-format.md): |energy error| above energy_warning warns once, above
  /// energy_limit stops the run as a failure (exit 4). Fractions of the input energy [-].
  double energy_warning = 0.01;
  double energy_limit = 0.05;
};

struct OutputControl {
  double interval = 0;            ///< simulated time between frames [s]; 0 = first and last only
  bool frames = true;             ///< write .vtu frames and the .pvd
  double probe_interval = 0;      ///< between probe rows [s]; 0 = every step
  int compression_level = 1;      ///< zlib level of the frames
  /// Bodies (outline names) whose rigid-body history goes to `<case>.bodies.csv` every
  /// `probe_interval`: mass [kg or kg/rad], centre of mass [m], mass-averaged velocity [m/s],
  /// momentum [kg m/s or per rad], kinetic energy [J or J/rad]. Empty: no file.
  std::vector<std::string> body_history;
  /// Simulated time between checkpoints `<case>.chk` [s]; 0 = none (docs/file-format.md).
  double checkpoint_interval = 0;
  /// Boundary sets whose reaction (the force the set's condition exerts on the body, N or
  /// N/rad) goes to `<case>.reactions.csv` at every energy row, in this order. Empty: no file.
  std::vector<std::string> reactions;
};

/// A rigid planar wall: the half-plane behind the line through `point` with unit `normal`
/// pointing towards the disks. Disks touching it get a contact (compression only, Coulomb
/// friction, the case's dashpot fraction).
struct Wall {
  std::array<double, 2> point{0, 0};   ///< a point of the wall [m]
  std::array<double, 2> normal{0, 1};  ///< unit normal towards the disks
  std::optional<double> friction;      ///< Coulomb coefficient; default: the disk's material's
  std::string where;
};

/// The mass a contact's stiffness cap is reckoned with (ContactControl::cap_mass).
enum class CapMass {
  Disk,       ///< each disk's own mass
  WholeCell,  ///< the mass of each disk's whole hexagonal cell, at most Model::kMaxCapMassFactor times its own
};

/// Contacts: broken bonds (state II) and disks of different bodies (physics.md section 8).
struct ContactControl {
  double damping = 0;  ///< eta: fraction of critical damping of the normal dashpot, [0, 1)
  /// Contact resolution: every contact is made no stiffer than omega dt = resolution for its
  /// masses, omega = sqrt(k / m_eff) (docs/model.md, "Energy at contacts"), (0, 0.9].
  double resolution = 0.25;
  /// The masses of the cap: a disk whose cell the outline or the axis cuts is lighter than
  /// its neighbours, and its contacts softer; WholeCell reckons the cap with the mass of the
  /// whole cell (docs/model.md, "Energy at contacts").
  CapMass cap_mass = CapMass::Disk;
  /// Spread s of the contact radii: each interior disk touches others as a disk of radius
  /// r (1 + s (2u - 1)), u uniform from [mesh] jitter_seed, so that a broken packing is
  /// polydisperse and does not fall back into the lattice's rows (docs/model.md, "Contact
  /// radii"); [0, meshing::kMaxRadiusSpread], 0 = every disk touches at r.
  double radius_spread = 0;
};

/// Spatially correlated random strength (docs/model.md, "Random strength"): every strength of
/// a breakable bond and a ring's hoop strength are multiplied by a lognormal field of mean 1,
/// coefficient of variation strength_cov and Gaussian correlation exp(-d^2 / (2 l^2)), drawn
/// from `seed`; the field is a property of the material's space, not of the lattice. With
/// stiffness_cov > 0 the springs of those bonds (and a ring's hoop term) are multiplied by a
/// second, independent field of the same kind (docs/model.md, "Random stiffness").
struct RandomField {
  std::int64_t seed = 0;
  double correlation_length = 0;  ///< l [m]
  double strength_cov = 0.1;      ///< [-]
  double stiffness_cov = 0;       ///< [-]; 0: uniform stiffness
};

struct Case {
  std::string name;               ///< output base name (default: the case file's stem)
  std::string source;             ///< the case file
  Geometry geometry = Geometry::PlaneStress;
  double thickness = 1.0;         ///< plane geometries [m]
  ShearModel shear_model = ShearModel::LocalStrain;

  meshing::Outline outline;       ///< bodies (radius, angle, origin resolved per body)
  /// Largest estimated disk count the mesh may have ([mesh] max_disks, `--max-disks`;
  /// kMaxDisksHint in the message).
  std::int64_t max_disks = meshing::kDefaultMaxDisks;
  /// The disks' order in memory ([mesh] order): the generator's rows, or a Hilbert curve.
  meshing::DiskOrder disk_order = meshing::DiskOrder::Rows;
  /// [mesh] jitter: the interior disks moved off their sites by up to this fraction of r
  /// (meshing::jitter_lattice; 0, the default, keeps the regular lattice), with the stream
  /// [mesh] jitter_seed.
  double mesh_jitter = 0.0;
  std::int64_t mesh_jitter_seed = 1;
  std::vector<Material> materials;
  std::vector<BoundaryCondition> boundaries;
  std::vector<Load> loads;
  std::vector<InitialVelocity> initial_velocities;
  std::vector<Probe> probes;
  std::vector<Wall> walls;
  TimeControl time;
  OutputControl output;
  ContactControl contact;
  std::optional<RandomField> random;  ///< [random]; none: uniform strengths
  /// The case as run: the file's TOML with every --set override applied (written as
  /// `<case>.case.toml` beside the output; its hash identifies checkpoints). Empty for a
  /// Case built in code.
  std::string effective_toml;
  std::vector<std::string> warnings;  ///< non-fatal reader notes (e.g. DXF entities skipped),
                                      ///< one line each, for the program to print

  /// The material with this id, or nullptr.
  [[nodiscard]] const Material* find_material(int id) const;
};

}  // namespace hexdem::solver
