#pragma once
/// \file solver.hpp
/// The explicit solver: central differences (leap-frog) with optional mass damping (Eq. 18),
/// boundary conditions, loads, the stable time step (physics.md section 5) and the energy
/// balance (section 6, Eq. 25). SI units.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hexdem/meshing/lattice.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/solver/case.hpp"
#include "hexdem/solver/model.hpp"
#include "hexdem/solver/stability.hpp"
#include "hexdem/solver/sweep_prune.hpp"

namespace hexdem::solver {

struct CheckpointAccess;  // checkpoint.hpp

/// Energy balance at a time t_n [J] (per unit... as the model: J for plane models with their
/// thickness, J per radian for axisymmetric ones).
struct EnergyBalance {
  double kinetic = 0;        ///< 1/2 m v(t-dt/2).v(t+dt/2) + spin, the leap-frog kinetic energy
  double elastic = 0;        ///< springs and hoop term
  double external_work = 0;  ///< work of loads and prescribed velocities since t = 0
  double damping = 0;          ///< energy dissipated by mass damping
  double plastic = 0;          ///< plastic work of the hardening springs (Eq. 16)
  double fracture = 0;         ///< energy stored in bonds when they broke
  double contact_damping = 0;  ///< energy dissipated by contact dashpots
  double friction = 0;         ///< energy dissipated by contact friction
  /// Leap-frog's kinetic half step of breaks and damage steps [J], of either sign and O(dt):
  /// a force at t_n that a break changes by dF changes the kinetic energy at t_n by
  /// (dt/2) v(t-dt/2).dF (docs/model.md, "Energy at a break").
  double break_kinetic = 0;
  double initial = 0;          ///< kinetic + elastic energy at t = 0 (e.g. a projectile)
  /// The model's own energy scale [J]: the elastic energy of every body at a uniform strain
  /// of 1e-9. Errors are measured against max(|E_in|, scale), so a run with no input energy
  /// is judged against it instead of against round-off.
  double scale = 0;
  /// Eq. 25: input E_in = initial + external work; total E_t = kinetic + elastic + every
  /// dissipated energy.
  [[nodiscard]] double input() const { return initial + external_work; }
  [[nodiscard]] double total() const {
    return kinetic + elastic + damping + plastic + fracture + contact_damping + friction + break_kinetic;
  }
  /// Err = (E_in - E_t) / max(|E_in|, scale).
  [[nodiscard]] double relative_error() const {
    const double s = std::max(std::abs(input()), scale);
    return s > 0 ? (input() - total()) / s : 0.0;
  }
};

/// How the time step was chosen.
struct TimeStepInfo {
  double dt = 0;            ///< the step used [s]
  double dt_critical = 0;   ///< min(dt_bloch, dt_finite), with the contact dashpot's reduction [s]
  /// The step the contacts' stiffness cap refers to [s]: the default step (kDefaultSafety x
  /// dt_critical, landing on the end time), whatever [time] dt or safety
  /// (Solver::setup_contact_resolution).
  double dt_contact = 0;
  double dt_bloch = 0;      ///< smallest Bloch critical step over the bodies [s]
  double dt_finite = 0;     ///< 2/omega_max of the finite model (Lanczos) [s]
  double dt_eq24 = 0;       ///< the paper's Eq. 24, for comparison [s]
  int finite_iterations = 0;  ///< Lanczos iterations of dt_finite
  /// The largest factor of the random stiffness field (1 without one): dt_bloch and dt_finite
  /// are the uniform model's, and the critical step is their minimum / sqrt(stiffness_max).
  double stiffness_max = 1;
  bool user_dt = false;
};

/// Wall time of the solver's set-up by part [s] (printed by `hexdem bench`).
struct SetupTimes {
  double model = 0;         ///< materials, Bloch analysis, the model's arrays
  double random_field = 0;  ///< [random] strengths
  double sets = 0;          ///< boundaries, loads, reactions, initial velocities
  double contacts = 0;      ///< contact detection set-up
  double time_step = 0;     ///< the critical step of the finite model
  double energy_scale = 0;  ///< contact resolution and the energy scale
};

/// Why Solver::advance stopped a run: a numerical blow-up (the state is no longer finite, the
/// kinetic and elastic energy have grown far beyond the input, or the elastic energy is
/// negative) or an energy balance error beyond [time] energy_limit.
struct BlowUp {
  enum class Kind { None, BlowUp, EnergyLimit };
  Kind kind = Kind::None;
  std::int64_t step = 0;
  double time = 0;
  std::string reason;
};

/// The finite model's critical step 2 / sqrt(1.02 omega2_max) [s] from a Lanczos estimate of
/// omega_max^2 [1/s^2] (the 2 % for what the iteration has not reached); infinite for 0.
[[nodiscard]] double finite_model_step(double omega2_max);

/// The disk a probe records: the one whose reference centre is nearest to its point. Throws
/// InputError (naming the probe, the distance and the radius) if that centre is farther than
/// 2r: the point lies outside every body.
[[nodiscard]] std::size_t probe_disk(const Model& m, const Probe& p);

class Solver {
public:
  /// Builds the model from the lattice (meshed from case.outline), applies initial
  /// velocities, checks each material's stability (Bloch analysis; an unstable shear model is
  /// refused with InputError naming the material, the condition and the remedy) and chooses
  /// the time step (a user dt above the critical step is refused unless allow_unstable).
  /// The lattice is taken by value (move it in: no copy); once the model is built, the
  /// solver keeps only its names, boundary sets and fingerprint (lattice_hash()), not a second
  /// copy of the disks and bonds.
  Solver(const Case& c, meshing::Lattice lattice);

  /// One step from t_n to t_{n+1}: forces at t_n, velocities to t_{n+1/2}, then (if given)
  /// `at_tn(*this)` with the state at t_n complete (positions u_n, mid-step velocities, bond
  /// forces, energy balance if `diagnostics`), then positions to t_{n+1}.
  /// With `diagnostics` the energy balance is checked (run health): |Err| above
  /// [time] energy_warning records energy_warning() once; above energy_limit, a negative
  /// elastic energy, a non-finite state or an energy beyond ten times the input the step
  /// returns false with blow_up() set, before `at_tn`: the state is then not to be written,
  /// and every state that was handed to `at_tn` passed these checks.
  bool advance(bool diagnostics, const std::function<void(const Solver&)>& at_tn = {});

  [[nodiscard]] const Model& model() const { return model_; }
  [[nodiscard]] Model& model() { return model_; }
  [[nodiscard]] const Case& case_data() const { return case_; }
  /// The lattice's body names and boundary sets; its disk and bond arrays are released after
  /// set-up (the model holds them).
  [[nodiscard]] const meshing::Lattice& lattice() const { return lattice_; }
  /// Fingerprint of the lattice the model was built from (disks, bonds, cells), for restarts.
  [[nodiscard]] std::uint64_t lattice_hash() const { return lattice_hash_; }
  [[nodiscard]] double time() const { return time_; }          ///< t_n during at_tn
  [[nodiscard]] std::int64_t step_index() const { return step_; }
  [[nodiscard]] const TimeStepInfo& time_step() const { return dt_info_; }
  [[nodiscard]] const SetupTimes& setup_times() const { return setup_times_; }
  [[nodiscard]] double dt() const { return dt_info_.dt; }
  [[nodiscard]] const EnergyBalance& energy() const { return energy_; }
  [[nodiscard]] const BlowUp& blow_up() const { return blow_up_; }
  /// Largest |Err| of the checked steps so far.
  [[nodiscard]] double max_energy_error() const { return max_energy_error_; }
  /// The warning of the first checked step whose |Err| passed [time] energy_warning (one
  /// line, no prefix), or empty.
  [[nodiscard]] const std::string& energy_warning() const { return energy_warning_; }
  /// Bonds broken so far.
  [[nodiscard]] std::size_t broken_bonds() const { return broken_bonds_; }

  /// A contact between two disks that were never bonded (other bodies, or fragments).
  struct Contact {
    std::int32_t i = 0, j = 0;  ///< disks, i < j
    double f_n = 0, f_s = 0;    ///< normal (compression negative) and tangential force [N]
    double f_v = 0;             ///< the dashpot's part of f_n [N] (trapezoid work)
  };
  /// Contact pairs found by the broad phase (forces zero while apart), sorted by (i, j).
  [[nodiscard]] const std::vector<Contact>& contacts() const { return contacts_; }
  [[nodiscard]] bool contacts_enabled() const { return contacts_on_; }
  /// Wall time spent in the contact broad phase so far [s].
  [[nodiscard]] double detection_seconds() const { return detection_seconds_; }
  /// Largest pressure over the loads and the run, p0 * max|f(t)| [Pa]; 0 without pressure.
  [[nodiscard]] double p_max() const { return p_max_; }
  /// Velocity of disk i at t_n (mean of the half steps), valid during at_tn.
  [[nodiscard]] double vx_mid(std::size_t i) const { return 0.5 * (model_.vx_old[i] + model_.vx[i]); }
  [[nodiscard]] double vy_mid(std::size_t i) const { return 0.5 * (model_.vy_old[i] + model_.vy[i]); }
  [[nodiscard]] double spin_mid(std::size_t i) const { return 0.5 * (model_.omega_old[i] + model_.omega[i]); }
  /// Number of steps to reach the case's end time.
  [[nodiscard]] std::int64_t total_steps() const;
  /// One line per plastic material of the bodies: the plasticity model it uses and why.
  [[nodiscard]] const std::vector<std::string>& plasticity_report() const { return plasticity_report_; }
  /// Unstable choices that [time] allow_unstable let through (one line each, no prefix);
  /// `hexdem run` prints them as warnings.
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }
  /// Per-body Bloch results, in body order.
  [[nodiscard]] const std::vector<BlochResult>& bloch() const { return bloch_; }

  /// Number of boundary sets in `[output] reactions`.
  [[nodiscard]] std::size_t num_reaction_sets() const { return reaction_sets_.size(); }
  /// The force [N; axisymmetric N/rad] that boundary set k of `[output] reactions` exerts on
  /// the body at t_n, x = r, y = z (docs/file-format.md, "<case>.reactions.csv"); valid during
  /// at_tn (a mirror spring's force needs the displacement at t_n). A set with a condition:
  /// the constraint force, the sum over the disks and components its conditions hold of
  /// m a - F, with F the total force of the force pass at t_n (bonds, hoop term, contacts,
  /// walls, loads) and a = (v(t+dt/2) - v(t-dt/2)) / dt the acceleration the leap-frog update
  /// gave the held component (zero for fixed, roller and symmetry components), plus on a
  /// symmetry set the force -k u of its mirror springs. A set with only pressure loads: the
  /// force of those loads at t_n. Serial in disk order: deterministic, allocates nothing.
  [[nodiscard]] std::array<double, 2> reaction(std::size_t k) const;

  /// Largest omega^2 of the finite model, M^-1 K, by Lanczos iteration with the force kernel
  /// on the whole model. Exposed for tests and `hexdem check`.
  [[nodiscard]] double finite_omega2_max(int max_iterations = 200);
  /// The same estimate on the edge band (time_step.cpp, "The edge band"): Lanczos on a model
  /// of the disks within `width` bonds of an irregular disk (an edge, a semi-disk, a held
  /// or mirrored disk, a disk whose cell is not the whole hexagon), with `halo` rings of held
  /// disks around it. Empty when the band does not apply (axisymmetric models, bonds with
  /// their own stiffness) or holds more than half the disks. `band_disks` receives the band's size (disks free to move).
  /// `before_build`, if given, is called with the number of the band's disks (the halo
  /// included) once they are chosen, before the band's model is built.
  [[nodiscard]] std::optional<double> band_omega2_max(int width, int halo, std::size_t* band_disks = nullptr,
                                                      int max_iterations = 200,
                                                      const std::function<void(std::size_t)>& before_build = {});
  /// Disks of the model the critical step's Lanczos estimate ran on (the edge band or all).
  [[nodiscard]] std::size_t finite_estimate_disks() const { return finite_disks_; }

private:
  friend struct CheckpointAccess;  // checkpoint.cpp stores and restores the state

  struct LoadSet {
    const Load* load;
    std::vector<std::int32_t> disks;
    std::vector<double> cx, cy;  ///< force per unit amplitude [N]
    std::vector<double> lx, ly;  ///< lever arm: load point minus disk centre [m]
  };
  struct VelocitySet {
    const BoundaryCondition* bc;
    std::vector<std::int32_t> disks;
  };
  /// A boundary set of `[output] reactions`, resolved once at set-up.
  struct ReactionSet {
    std::vector<std::int32_t> disks;  ///< disks the set's conditions hold, ascending
    std::vector<std::uint8_t> held;   ///< kFixX | kFixY: what the set's conditions hold on each
    std::vector<std::int32_t> spring_disks;   ///< disks tied to the set's mirror plane
    std::vector<std::uint8_t> spring_axis;    ///< 0: x spring (wall_kx), 1: y spring (wall_ky)
    std::vector<std::int32_t> loads;  ///< indices into loads_ (sets without a condition only)
  };
  struct StepSums {  // per-block energy terms of one step
    double kinetic = 0, kinetic_sq = 0, ext_a = 0, ext_b = 0, damp_a = 0, damp_b = 0;
  };

  /// Refuses an unstable choice (InputError: message; remedy), or with [time] allow_unstable
  /// records it as a warning and goes on.
  void refuse_unless_allowed(const std::string& message, const std::string& remedy);
  void setup_materials();
  void setup_nonlocal_strain();
  /// [random] stiffness_cov: multiplies the springs of the breakable bodies' bonds by their
  /// factors (Model::stiffness_scale) and their disks' hoop terms by the field at the disks;
  /// the critical step is divided by the square root of the largest factor
  /// (TimeStepInfo::stiffness_max).
  void apply_random_stiffness();
  void setup_boundaries();
  void setup_mirror_springs(const BoundaryCondition& bc, int set);
  /// Throws an InputError when a part of the set (a separate edge of it) holds no disk.
  void check_every_part_held(const BoundaryCondition& bc, int set) const;
  void setup_loads();
  /// Resolves `[output] reactions` into reaction_sets_ (after the boundaries and loads).
  void setup_reactions();
  void setup_initial_velocities();
  /// Refuses (InputError) a probe that selects no disk (probe_disk) and an `[output] body_history` body without
  /// disks: the checks `hexdem run` makes before its output, made at set-up so that
  /// `hexdem check` makes them too.
  void check_probes() const;
  /// Refuses (InputError) a `[[wall]]` that overlaps a disk at t = 0 (a centre closer than
  /// (1 - 1e-9) r to the wall's line, or behind it).
  void check_walls() const;
  void setup_contacts();
  void contact_forces(double dt);
  void wall_forces(double dt);
  [[nodiscard]] double contact_energy() const;
  /// omega^2 max of the finite model: Lanczos on the edge band where it holds the largest mode,
  /// else on the whole model (time_step.cpp); sets finite_disks_ and the iteration count.
  [[nodiscard]] double finite_estimate();
  /// The time step from the Bloch values, the finite model's omega2 max and the contact
  /// dashpot (needs setup_contacts).
  void choose_time_step(double finite_omega2);
  /// Sets model_.contact_omega2: the contact stiffness cap of every contact.
  void setup_contact_resolution();
  /// Sets energy_.scale (see EnergyBalance::scale).
  void setup_energy_scale();
  /// Run health at a checked step: false (blow_up_ set) for a failure.
  bool check_energy(const StepSums& s, bool diagnostics);
  void apply_external_forces(double t);
  StepSums update_velocities(double t);
  /// Eq. 18 and the energy terms per block of disks into block_sums_ (update_velocities).
  template <bool Damping, bool External>
  void update_velocity_blocks(double c_old, double c_new, std::size_t blocks);

  Case case_;
  meshing::Lattice lattice_;
  std::uint64_t lattice_hash_ = 0;
  Model model_;
  std::vector<BodyMaterial> body_materials_;
  std::vector<BlochResult> bloch_;
  std::vector<std::string> plasticity_report_;
  std::vector<std::string> warnings_;
  std::vector<LoadSet> loads_;
  std::vector<VelocitySet> velocity_sets_;
  std::vector<std::int32_t> loaded_disks_;
  std::vector<ReactionSet> reaction_sets_;
  std::vector<StepSums> block_sums_;
  TimeStepInfo dt_info_;
  std::size_t finite_disks_ = 0;  ///< disks of the critical step's Lanczos model (not state)
  SetupTimes setup_times_;
  EnergyBalance energy_;
  BlowUp blow_up_;
  EnergyBalance last_checked_;  ///< the ledger at the last checked step that passed
  double last_checked_time_ = 0;
  double max_energy_error_ = 0;
  std::string energy_warning_;
  double time_ = 0;
  std::int64_t step_ = 0;
  double p_max_ = 0;
  double ext_b_before_ = 0, damp_b_before_ = 0;  ///< second halves of the trapezoid sums
  double ext_a_ = 0, damp_a_ = 0;
  double initial_energy_ = 0;
  std::size_t broken_bonds_ = 0;
  // Contacts of never-bonded disks (physics.md section 8).
  bool contacts_on_ = false;
  /// Never-bonded disks can meet (several bodies, or bonds that can break): the contacts'
  /// broad phase is set up (setup_contacts) and the time step's estimate plans for it.
  [[nodiscard]] bool contacts_wanted() const { return case_.outline.bodies.size() > 1 || model_.any_breakable; }
  SweepPrune sweep_;
  std::vector<double> px_, py_;                 ///< current centres [m]
  std::vector<Contact> contacts_, contacts_next_;
  std::vector<double> body_kn_, body_kt_, body_mu_;  ///< per body, per unit thickness
  double contact_damping_work_ = 0, contact_friction_work_ = 0;
  double detection_seconds_ = 0;
  std::vector<std::vector<double>> wall_fn_, wall_fs_, wall_fv_;  ///< per wall, per disk [N]
};

/// Meshes a case's outline (per-body radius, angle and origin already resolved).
meshing::Lattice mesh_case(const Case& c, meshing::GeneratorReport* report = nullptr);

}  // namespace hexdem::solver
