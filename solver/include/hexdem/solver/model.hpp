#pragma once
/// \file model.hpp
/// The discrete model in structure-of-arrays form: disks (rigid, with mass and inertia from
/// their cells), bonds (normal and shear springs), adjacency, and the force kernels of
/// physics.md sections 2-4 and 10. SI units: m, s, kg, N, Pa, J. In axisymmetric models every
/// extensive quantity (mass, force, stiffness, energy) is per radian.
///
/// Time integration (Eq. 5 / Eq. 18) lives in solver.hpp; this file holds the state and the
/// kernels that turn displacements into forces.
///
/// The state each law keeps is a group of its own, allocated only when a case uses that law:
/// Model::strain (the disks' local strain, LocalStrain), Model::hoop (the out-of-plane term,
/// OutOfPlane), Model::mirror (MirrorPlanes), Model::bond_plastic (the bilinear springs of
/// Eq. 16, BondPlasticity), Model::cracks and Model::hoop_cracks (softening, BondCracks and
/// HoopCracks), Model::failed_rows (what only failed bonds carry, FailedBond) and Model::j2
/// (disk plasticity, DiskPlasticity). The disks' and bonds' own arrays are Model's.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "hexdem/laws/failure.hpp"
#include "hexdem/laws/softening.hpp"
#include "hexdem/meshing/lattice.hpp"
#include "hexdem/solver/load_balance.hpp"
#include "hexdem/solver/material.hpp"

namespace hexdem::solver {

/// Bond states, as written to the `state` cell array.
enum class BondState : std::uint8_t {
  Intact = 0,
  Yielded = 1,
  BrokenTension = 2,
  BrokenShear = 3,
  BrokenCompression = 4,
};

/// Per-disk constraint bits.
enum ConstraintBits : std::uint8_t {
  kFixX = 1,         ///< velocity x (r) held (zero or prescribed)
  kFixY = 2,         ///< velocity y (z) held
  kFixRotation = 4,  ///< spin held at zero
};

/// Softening failure of one body's material (docs/model.md, "Fracture energy and softening"):
/// on when G_F > 0; otherwise the body's bonds break brittle (the MohrCoulombFailure law).
struct SofteningParams {
  double G_F = 0;           ///< fracture energy [J/m^2]; 0: brittle
  double lambda2 = 0;       ///< in-plane Lame constant of the continuum stress [Pa] (plane
                            ///< stress: 2 lambda mu / (lambda + 2 mu))
  double mu = 0;            ///< shear modulus [Pa]
  double lambda3 = 0;       ///< 3D Lame constant (out-of-plane and hoop terms) [Pa]
  double radial_cracks = 0; ///< axisymmetric: radial cracks that relieve hoop tension [-]
  bool shear = false;       ///< Mohr-Coulomb shear starts a softening crack (shear_softening)
  /// Smeared damage (damage_band w > 0): the criteria's value at failure relative to the
  /// start, k_f = 2 G_F E / (f_t^2 w) [-]; 0: off (docs/model.md, "Smeared damage").
  double damage_kf = 0;
  laws::StressMohrCoulomb mc;  ///< shear and crushing on the continuum stress
};

/// Symmetry planes, per disk: disks on an axis-aligned mirror plane have no shear strain
/// (their local strain and its conjugate are projected on the mirror-symmetric part), and
/// disks one radius off it are tied to it by the normal spring of the bond to their mirror
/// image. Empty without a mirror plane.
struct MirrorPlanes {
  std::vector<std::uint8_t> plane;  ///< 1 if the disk lies on a mirror plane (Model::on_mirror)
  std::vector<double> kx, ky;       ///< spring to a mirror plane [N/m]: F = -k u
  std::vector<double> sx, sy;       ///< +-1: side of the plane (outward normal), 0 none
};

/// The out-of-plane term per disk (physics.md section 10): the hoop term of axisymmetric
/// models and the plane-strain sigma_zz.
struct OutOfPlane {
  /// Lame constants [Pa] of the out-of-plane term (axisymmetric: every disk; plane strain:
  /// the disks of J2 materials, 0 for the others; empty in models without the term).
  std::vector<double> lambda, mu;
  /// Breakable axisymmetric models: 1 once the disk has lost a neighbour (its hoop term keeps
  /// only the square of the hoop stress), and the constant that kept its energy continuous
  /// then [J]; empty otherwise.
  std::vector<std::uint8_t> cut;
  std::vector<double> constant;
  /// Plane strain, isotropic: sigma_zz = nu (sxx + syy) (0 for the other disks); empty in
  /// plane stress, axisymmetry and plane strain without an isotropic material.
  std::vector<double> nu_zz;
};

/// The bilinear hardening springs of the per-spring plasticity (Eq. 16; docs/laws.md), per
/// bond; allocated only when some bond has a yield force (Model::any_plastic).
struct BondPlasticity {
  std::vector<double> f_yield;           ///< yield force sigma_y 2r w [N]; 0: elastic springs
  std::vector<double> kh_n, kh_s;        ///< hardening stiffnesses [N/m]
  std::vector<double> alpha_n, alpha_s;  ///< back-forces of the normal and shear springs [N]
  std::vector<double> work;              ///< cumulative plastic work [J], summed only when reported
};

/// The disks' local strain (physics.md section 4), per disk: the inverse of sum_k a_k a_k^T
/// over the bonds of the fit (a_k reference bond vectors), the strain eps, and the conjugate
/// tensor W. Allocated only when some term needs the strains (Model::uses_strains).
struct LocalStrain {
  std::vector<double> minv_xx, minv_xy, minv_yy;  ///< [1/m^2]; zero if singular
  /// 1 if disk i has a local strain of its own in the initial lattice (two independent bonds
  /// to such disks, found by elimination at build time), else 0. A disk without one (a lone
  /// disk at a sharp tip of a rotated lattice, held by a single bond) enters no neighbour's
  /// strain fit, and its bonds carry no local-strain shear: only their normal springs hold
  /// it. Otherwise, with negative shear springs (nu > 1/4 in plane strain and axisymmetry),
  /// its displacement could lower a neighbour's shear energy more than its one normal spring
  /// raises it, and the lattice became indefinite (measured: the warhead's steel in free
  /// flight at a lattice angle of 30 degrees blew up at step 190).
  std::vector<std::uint8_t> ok;
  std::vector<double> eps_xx, eps_yy, eps_xy;  ///< small strain [-]
  /// Axisymmetric: the hoop strain u_r / b of the last strain pass [-], read by the force
  /// passes that follow it (one division per disk and step instead of one per use); empty in
  /// plane models. Work space: everything outside the force passes computes it from u_r.
  std::vector<double> eps_tt;
  /// Breakable models: the strain carried across changes of a disk's fit,
  /// eps = fit(u) - eps_off (settle_broken_bonds) [-]; empty otherwise.
  std::vector<double> eps_off_xx, eps_off_yy, eps_off_xy;
  std::vector<double> w_xx, w_xy, w_yx, w_yy;  ///< W = S M^-1, S = dE/d(eps) [N/m]
};

/// Nonlocal strain of the softening criteria (docs/model.md, "Nonlocal criterion"): each
/// disk's strain averaged over the disks of its body with a full neighbourhood within the
/// `nonlocal_radius` R of its material, in the reference configuration, with the weight
/// (1 - d^2/R^2)^2. Empty unless some material has a radius; a disk of a body without one
/// averages over itself alone (its local strain).
struct NonlocalStrain {
  /// Largest row and largest number of entries a case may ask for (Solver refuses a radius
  /// beyond them as an input error): a row of 10,000 disks is a radius of about 52 spacings 2r, and
  /// 1e9 entries hold 12 GB (and stay below the 32-bit offsets' 4.29e9).
  static constexpr double kMaxRow = 1e4, kMaxEntries = 1e9;
  std::vector<std::uint32_t> offset;  ///< per disk + 1: its row of nbr and w
  std::vector<std::int32_t> nbr;      ///< the disks averaged over, in index order
  std::vector<double> w;              ///< their weights, summing to 1 per row [-]
  std::vector<double> eps_xx, eps_yy, eps_xy;  ///< the averaged in-plane strain [-]
  std::vector<double> eps_tt;                  ///< axisymmetric: the averaged hoop strain [-]
  /// Where no criterion can be near, the average is not needed: each criterion is convex in
  /// the stress, so at an average it is at most the largest value it takes at the averaged
  /// disks. Cells of size `radius` hold the largest of each disk's criteria, relative to its
  /// material's static strengths times the body's smallest random-field factor; a bond is
  /// checked only if the block of 3 x 3 cells around one of its disks reaches 1 (`hot`), and
  /// averages are computed only for disks next to a hot cell (the same bits as averaging
  /// everywhere: the skipped bonds cannot fail).
  bool skip_far = true;                        ///< false: average and check everywhere (tests)
  std::int64_t cells_x = 0, cells_y = 0;
  std::vector<std::int32_t> cell;              ///< per disk: its cell
  std::vector<double> body_inv_ft, body_inv_fc, body_inv_mc;  ///< per body: 1 / the smallest thresholds [1/Pa] (0: no bound)
  std::vector<double> relative;                ///< per disk: its largest relative criterion [-] (work space)
  std::vector<double> packed;                  ///< per disk: eps_xx, eps_yy, eps_xy and the hoop strain, packed for the averages [-] (work space)
  std::vector<double> cell_max;                ///< per cell: the largest relative criterion [-]
  std::vector<std::uint8_t> hot;               ///< per cell: bit 0, its 3 x 3 block reaches 1; bit 1, a hot cell is in its block
  [[nodiscard]] bool disk_hot(std::size_t i) const { return (hot[static_cast<std::size_t>(cell[i])] & 1) != 0; }
};

/// Where the local criterion of softening bonds (softening_bond) cannot fire: a bond's
/// continuum stress is C : (eps_i + eps_j) / 2 (or one disk's, where only one has a full
/// neighbourhood), and each criterion (Rankine, crushing, Mohr-Coulomb) is convex in the stress,
/// so at the bond it is at most the larger of its values at the two disks. The strain pass
/// classifies each disk by its own stress against its body's smallest static thresholds (the
/// rate factors only raise them); a bond whose disks are all far is not checked: the same bits
/// as checking it. Empty unless a softening material uses the local criterion (no
/// nonlocal_radius); a Model built without the Solver has none and checks every bond.
struct LocalCriterion {
  /// Margin below the thresholds [-], far above the rounding of the few operations between the
  /// disks' stresses and the bond's (1e-15 of the stresses' terms, which far() bounds).
  static constexpr double kMargin = 1e-6;
  /// Per body, what the classification reads: its softening law's continuum constants and the
  /// reciprocals of its smallest static thresholds.
  struct Body {
    double lambda2 = 0, lambda3 = 0, mu = 0;  ///< SofteningParams' [Pa]
    double sin_phi = 0;                       ///< [-]
    double inv_ft = 0, inv_fc = 0, inv_mc = 0;  ///< 1 / the smallest thresholds [1/Pa]
    double inv_max = 0;                         ///< the largest of them [1/Pa]
    double moduli = 0;                          ///< |lambda2| + |lambda3| + 2 |mu| [Pa]
    /// 1 - kMargin where the body has a bound, -infinity where not (its disks are always near).
    double far_below = -std::numeric_limits<double>::infinity();
  };
  std::vector<Body> body;
  /// Per disk (work space of the strain pass): 0 without a full neighbourhood (six bonds in the
  /// initial lattice and a fit), 1 full and far from every criterion, 2 full and near (or not
  /// finite).
  std::vector<std::uint8_t> disk;
  /// Bond (i, j) cannot fire: no disk near and at least one full (two without a full
  /// neighbourhood use the bond criterion of Eq. 19 on their forces).
  [[nodiscard]] bool far(std::size_t i, std::size_t j) const { return (disk[i] | disk[j]) == 1; }
};

/// A bond that the force pass found starting to crack (docs/model.md, "Fracture energy and
/// softening"), until settle_broken_bonds gives it its row of Model::failed_rows with this
/// crack state: the bond, and the driver at the start of cracking and at failure [m].
struct CrackStart {
  std::int64_t bond = 0;
  double delta0 = 0, delta_f = 0;
};

/// The crack state of softening bonds lives in their rows of Model::failed_rows (a bond has
/// one from the pass its crack starts in): per bond it would be 32 bytes on every bond, about
/// 96 bytes per disk, for the few that crack. Here only the force pass's new cracks.
struct BondCracks {
  /// The cracks that the force pass started, in no particular order (the pass's threads add
  /// them); settle_broken_bonds sorts them by bond, reads them and clears them, keeping the
  /// capacity (no allocation once grown).
  std::vector<CrackStart> starts;
};

/// Hoop cracking of the rings of axisymmetric softening models: damage of the hoop stress
/// (radial cracks), per disk.
struct HoopCracks {
  std::vector<double> damage, kappa, e0, ef;  ///< D_h, the largest driver, its start and failure values [-]
  std::vector<double> e_last;                 ///< the hoop driver s / M at the last force pass [-]
  std::vector<double> fracture;               ///< energy dissipated by hoop cracking [J]
  std::vector<double> break_kinetic;          ///< the kinetic half step of hoop damage [J] (as break_kinetic)
};

/// Disk-level plasticity (docs/model.md, "Plasticity per disk" and "Drucker-Prager disks"):
/// von Mises or Drucker-Prager yield with linear kinematic (Prager) hardening per disk. The
/// springs stay elastic; each plastic disk adds V [psi(eps - eps_p) - psi(eps)] to the energy
/// (V = A w, psi the isotropic 3D strain energy, eps its local strain). Components xx, yy, xy
/// (tensor, not engineering shear) and 33 (zz in plane strain, theta-theta in axisymmetry).
/// Per disk; allocated by build_model only when some body uses it, empty otherwise.
struct DiskPlasticity {
  std::vector<double> sigma_y;  ///< yield stress [Pa] (Drucker-Prager: k); 0: not a plastic disk
  /// Drucker-Prager pressure sensitivity alpha [-]: the yield stress is max(sigma_y - alpha p, 0)
  /// with p the mean stress (tension > 0). Allocated only when a material is Drucker-Prager.
  std::vector<double> alpha;
  std::vector<double> h;  ///< Prager modulus H = E E_t / (E - E_t) [Pa]
  std::vector<double> eps_p_xx, eps_p_yy, eps_p_xy, eps_p_33;  ///< plastic strain [-]
  std::vector<double> beta_xx, beta_yy, beta_xy, beta_33;      ///< back stress (2/3) H eps_p [Pa]
  std::vector<double> eps_p_eq;  ///< accumulated equivalent plastic strain [-]
  /// C : (eps - eps_p) at the last force evaluation [Pa], for the trapezoid work of the next
  /// plastic increment.
  std::vector<double> sig_xx, sig_yy, sig_xy, sig_33;
  std::vector<double> work;  ///< work done on eps_p [J]
};

/// The threads' parts of the force passes' parallel loops (LoadBalance), one per loop:
/// work space that follows the machine, not state (the results do not depend on it).
struct KernelBalance {
  LoadBalance classify, strains, nonlocal_strains, nonlocal_check, hoop, j2, bonds, elastic_bonds, conjugates, gather;
};

struct Model {
  Geometry geometry = Geometry::PlaneStress;
  ShearModel shear_model = ShearModel::LocalStrain;
  double thickness = 1.0;  ///< plane geometries [m]

  // ---- disks --------------------------------------------------------------------------
  std::vector<double> x0, y0;          ///< reference centre [m]
  std::vector<double> ux, uy;          ///< displacement at time t [m]
  std::vector<double> vx, vy;          ///< velocity at t - dt/2 (leap-frog) [m/s]
  std::vector<double> theta, omega;    ///< rotation [rad] at t, spin [rad/s] at t - dt/2
  std::vector<double> fx, fy, torque;  ///< total force [N] and moment [N m] at t
  std::vector<double> fx_ext, fy_ext;  ///< external part of the force at t [N]; empty without loads
  std::vector<double> ext_mxx, ext_myy, ext_mxy;  ///< sum sym(x_c (x) F) of the surface loads
                                                  ///< (x_c: lever arm from the centre) [N m]
  std::vector<double> mass;            ///< m = rho A w (w: thickness or b); I = m r^2 / 2 is disk_inertia(i)
  std::vector<double> radius;          ///< [m]
  /// Radius at which disk i touches others ([contact] radius_spread) [m]; empty: radius.
  /// Read through contact_r(i) and contact_radii(); mass, inertia and bonds keep radius.
  std::vector<double> contact_radius;
  std::vector<double> cell_area;       ///< [m^2]
  std::vector<double> weight;          ///< axisymmetric: w = ring radius b [m]; empty in plane models (w = thickness): disk_weight(i)
  std::vector<std::uint8_t> kind;
  std::vector<std::int32_t> body;
  std::vector<std::int32_t> body_material;  ///< per body: its material id (disk_material(i))
  std::vector<std::uint8_t> constraint;  ///< ConstraintBits
  MirrorPlanes mirror;

  /// Some term needs the disks' strains (local-strain shear, hoop, J2, softening): the
  /// strain arrays (strain, g) exist only then, and u_s where a law reads it back
  /// (plasticity, failure, J2: not in an elastic lattice, whose shear force is k_s u_s).
  bool uses_strains = false;
  LocalStrain strain;
  NonlocalStrain nonlocal;
  LocalCriterion local_criterion;
  OutOfPlane hoop;
  std::vector<double> vx_old, vy_old, omega_old;  ///< velocities at t - 3dt/2 after a step

  // ---- bonds --------------------------------------------------------------------------
  std::vector<std::int32_t> bi, bj;    ///< disk indices, bi < bj
  /// Reference geometry, read through ref_ax(b), ref_ay(b), rest(b) and LocalShearView: the
  /// reference vector a from bi to bj, the rest length |a| [m] and g = (|a|/2) sym(s0 (x) n0),
  /// u_s = g : (eps_i + eps_j) [m] (local-strain model). Once per spring kind (kind_*), which
  /// then holds the bond's direction and sense, where every bond's a = x0_j - x0_i is its
  /// kind's to 1e-12 |a| (a regular plane lattice; |a| as the bond pass computes a length,
  /// so that a lattice at rest has no force); otherwise a from the centres and |a|, g per bond.
  /// The other form is empty.
  std::vector<double> rest_length;
  std::vector<double> g_xx, g_yy, g_xy;
  /// Some bond's rest length is not its disks' radii's sum (an irregular lattice, [mesh]
  /// jitter): set by build_model from the reference geometry; read through touch(b).
  bool touch_at_rest = false;
  std::vector<double> kind_ax, kind_ay, kind_rest, kind_g_xx, kind_g_yy, kind_g_xy;
  /// Spring stiffnesses [N/m] (include w), read through kn(b) and ks(b): per bond in
  /// axisymmetric models (w is the bond's ring radius), otherwise once per spring kind (body,
  /// bond direction and sense, edge bond or not: 12 body + 4 direction + 2 sense + edge,
  /// direction 0 along the lattice axis), with the bond's kind in spring_kind; the other form
  /// is empty.
  std::vector<double> k_n, k_s;
  std::vector<std::uint8_t> spring_kind;
  std::vector<double> kind_k_n, kind_k_s;
  /// Normal and shear force [N], tension positive, and the current unit vector from bi to bj.
  /// f_s always (the rotation model's is its history); f_n, nx and ny only where a law reads
  /// them back (plasticity, failure, J2 disks): an elastic lattice (elastic_lattice()) keeps
  /// pair_fx, pair_fy instead, and bond_force(m, b) gives all four in either case.
  std::vector<double> f_n, f_s;
  std::vector<double> nx, ny;
  /// Elastic lattice only: the pair force on disk bi [N], f_n n + f_s s (rotation model) or
  /// f_n n (local-strain model; its shear acts through the strains), written by the bond
  /// pass for the gather (Eq. 3); recomputed every force pass, never history.
  std::vector<double> pair_fx, pair_fy;
  /// Shear displacement [m]: local-strain u_s, or the softening rotation model's accumulated
  /// one; empty in an elastic lattice (elastic_bond_forces does not keep it).
  std::vector<double> u_s;
  std::vector<std::uint8_t> state;     ///< BondState
  /// 1 along the lattice axis, 2 the other directions: read through bond_class_of(b); stored
  /// per bond only where the stiffnesses are (axisymmetric), otherwise the spring kind has it.
  std::vector<std::uint8_t> bond_class;

  // Plasticity, failure and contact of the bonds (physics.md sections 7, 8).
  bool any_plastic = false;              ///< some bond has a yield force
  bool any_breakable = false;            ///< some bond can break
  double contact_damping = 0;            ///< eta of the contact dashpot [-]
  /// Contact stiffness cap per effective mass [1/s^2]: a contact's k_n and k_t are at most
  /// m_eff contact_omega2 (Solver::setup_contact_resolution); infinite: no cap.
  double contact_omega2 = std::numeric_limits<double>::infinity();
  /// [contact] cap_mass = "whole_cell": the cap is reckoned with cap_mass(i), not mass[i].
  bool whole_cell_cap = false;
  /// The most a whole cell's mass may exceed a disk's own in the cap. The cap's omega is at
  /// most beta / dt with beta <= 0.9 (sqrt(1 + eta^2) - eta) (Solver::setup_contact_resolution);
  /// reckoned with masses up to 4 times the disks' own, a contact's true omega dt is at most
  /// 2 beta, still inside the dashpot's stability bound 2 (sqrt(1 + eta^2) - eta).
  static constexpr double kMaxCapMassFactor = 4.0;
  double time = 0;                       ///< time of the current force evaluation [s]
  BondPlasticity bond_plastic;
  std::vector<double> len_prev;          ///< length at the previous force evaluation [m]
  /// Bond section 2r w [m^2] (strength = stress x section), read through bond_section(b):
  /// stored per bond in axisymmetric models (w: the ring radius), recomputed from the disk's
  /// radius and the spring kind's edge flag in plane ones (empty).
  std::vector<double> section;
  /// Per body: the contact friction coefficient [-] and the index into failure_laws (-1:
  /// unbreakable) of its bonds (a bond joins two disks of one body): bond_mu(b),
  /// bond_failure_law(b).
  std::vector<double> body_mu;
  std::vector<std::int32_t> body_failure_law;
  std::vector<laws::MohrCoulombFailure> failure_laws;
  std::vector<double> failure_tan_phi;   ///< tan(phi) of each failure law
  /// A bond that has started to crack or has broken: its fracture energy (what its damage
  /// steps and its break released, >= 0) and the leap-frog kinetic energy that they moved, of
  /// either sign (a change of the force at t_n by dF changes v(t-dt/2).v(t+dt/2)/2 by
  /// (dt/2) v(t-dt/2).dF: O(dt), not energy the bond stored; docs/model.md, "Energy at a
  /// break") [J]; its break time [s] (-1 until it breaks); and once broken, its contact
  /// (state II): the dashpot's part of f_n at the last update [N] and the cumulative dashpot
  /// and friction work [J]; while a shear crack softens, the slip of its closed faces [m]
  /// (docs/model.md, "Shear cracks that soften").
  ///
  /// The crack state of a softening bond (docs/model.md, "Fracture energy and softening"):
  /// its damage D of the springs [-] (0 intact, 1 broken: every broken bond has 1); its
  /// largest driver since cracking started [m] (the elongation of a tension crack, the
  /// energy-equivalent elongation sqrt(<delta>^2 + (k_s / k_n) u_s^2) of a shear crack); the
  /// driver at the start of cracking and at failure [m]; and its kind, crack: kNoCrack, or
  /// kTensionCrack, kShearCrack once it has started one (shear_softening). A cracking bond
  /// keeps its (softening) springs but leaves its disks' strain fits, so that its opening is
  /// not read as strain by its neighbours: an intact bond has a row exactly when it cracks.
  /// All members 8 bytes: no padding in the checkpoint's bytes.
  struct FailedBond {
    double fracture_energy = 0, break_kinetic = 0, break_time = -1;
    double f_damp = 0, damping_work = 0, friction_work = 0;
    double slip = 0;
    double damage = 0, kappa = 0, delta0 = 0, delta_f = 0;
    std::int64_t crack = 0;
    bool operator==(const FailedBond&) const = default;
  };
  /// kDamageCrack: smeared damage (damage_band); its driver is the criteria's value at the
  /// bond's midpoint [-], and the bond stays in its disks' fits until it breaks.
  static constexpr std::int64_t kNoCrack = 0, kTensionCrack = 1, kShearCrack = 2, kDamageCrack = 3;
  /// One row per bond that has cracked or broken, in the order they did (settle_broken_bonds
  /// adds it), and each bond's row, -1 before (allocated if any_breakable): all of it is zero
  /// on every other bond, so it is not stored per bond (failed(b), bond_fracture_energy(b)...).
  std::vector<FailedBond> failed_rows;
  std::vector<std::int32_t> failed_row;
  /// 1 + FailureMode of a bond that the force pass found past its strength (it still acted
  /// intact in that pass), 0 otherwise; settle_broken_bonds breaks it and clears the flag.
  std::vector<std::uint8_t> newly_broken;
  // Softening failure (docs/model.md, "Fracture energy and softening"); per-bond and per-disk
  // arrays allocated only when some material has a fracture energy.
  bool any_softening = false;
  std::vector<SofteningParams> softening;  ///< per failure law (body)
  BondCracks cracks;
  HoopCracks hoop_cracks;  ///< axisymmetric models only
  /// Spatially random strength ([random]): factor on every strength of a bond / a disk's
  /// hoop strength; empty: 1.
  std::vector<double> strength_scale, disk_strength_scale;
  /// Spatially random stiffness ([random] stiffness_cov): the factor by which a bond's
  /// springs (k_n, k_s and hardening springs) were multiplied at set-up, read by the
  /// softening criteria, which see the stress of the bond's stiffness (docs/model.md, "Random
  /// stiffness"); empty: 1. The hoop term's factor is in OutOfPlane::lambda, mu.
  std::vector<double> stiffness_scale;
  /// Forces of the pass before settle_broken_bonds broke bonds [N, N m]: the break's
  /// kinetic-energy term compares them with the forces after it (allocated if any_breakable).
  std::vector<double> fx_intact, fy_intact, torque_intact;

  // Disk-level J2 plasticity (docs/model.md, "Plasticity per disk"): von Mises yield with
  // linear kinematic (Prager) hardening per disk. The springs stay elastic; each J2 disk adds
  // V [psi(eps - eps_p) - psi(eps)] to the energy (V = A w, psi the isotropic 3D strain
  // energy, eps its local strain). Components xx, yy, xy (tensor, not engineering shear) and
  // 33 (zz in plane strain, theta-theta in axisymmetry). Allocated by build_model only when
  // some body uses it; empty otherwise.
  bool any_j2 = false;  ///< some disk has J2 (or Drucker-Prager) plasticity
  DiskPlasticity j2;

  // ---- adjacency (CSR): incident bonds of each disk, in ascending bond order ----------
  std::vector<std::int32_t> adj_offset;  ///< size num_disks + 1 (2 x bonds < 2^31: build_model checks)
  /// The bond of each entry, b where the disk is the bond's bi and ~b (= -1 - b) where it is
  /// its bj: read through adj_bond(k) and adj_sign(k).
  std::vector<std::int32_t> adj_entry;

  mutable std::vector<double> scratch;  ///< block sums of deterministic_sum
  KernelBalance balance;                ///< the force passes' thread parts
  std::vector<double> event_weights;    ///< settle_broken_bonds: each event's stored energy
  std::vector<double> event_half;       ///< settle_broken_bonds: each event's own half step [J]
  std::vector<double> event_d_len;      ///< settle_broken_bonds: each event's length increment [m]

  [[nodiscard]] std::size_t num_disks() const { return x0.size(); }
  [[nodiscard]] std::size_t num_bonds() const { return bi.size(); }
  [[nodiscard]] bool bond_intact(std::size_t b) const { return state[b] <= 1; }
  /// Intact and not cracking: the bond enters its disks' strain fits.
  [[nodiscard]] bool bond_in_fit(std::size_t b) const {
    return state[b] <= 1 && (!any_softening || failed_row[b] < 0 ||
                             failed_rows[static_cast<std::size_t>(failed_row[b])].crack == kDamageCrack);
  }
  /// Reference bond vector x0[bj] - x0[bi] [m], recomputed (the same bits as at build time).
  [[nodiscard]] double ref_ax(std::size_t b) const {
    return kind_ax.empty() ? x0[static_cast<std::size_t>(bj[b])] - x0[static_cast<std::size_t>(bi[b])] : kind_ax[spring_kind[b]];
  }
  [[nodiscard]] double ref_ay(std::size_t b) const {
    return kind_ay.empty() ? y0[static_cast<std::size_t>(bj[b])] - y0[static_cast<std::size_t>(bi[b])] : kind_ay[spring_kind[b]];
  }
  /// The other disk of disk i's adjacency entry k: bi ^ bj ^ i of the entry's bond (read from
  /// the bond's ends, not stored: 24 bytes per disk).
  [[nodiscard]] std::size_t adj_other(std::size_t i, std::int64_t k) const {
    const std::size_t b = adj_bond(k);
    return static_cast<std::size_t>(bi[b] ^ bj[b]) ^ i;
  }
  /// Reference vector from disk i to the other disk of its adjacency entry k, x0[o] - x0[i]
  /// [m], recomputed: the same bits as +-ref_ax of the bond, since a - b = -(b - a) exactly.
  [[nodiscard]] double adj_ax(std::size_t i, std::int64_t k) const { return x0[adj_other(i, k)] - x0[i]; }
  [[nodiscard]] double adj_ay(std::size_t i, std::int64_t k) const { return y0[adj_other(i, k)] - y0[i]; }
  /// The bond of adjacency entry k.
  [[nodiscard]] std::size_t adj_bond(std::int64_t k) const {
    const std::int32_t e = adj_entry[static_cast<std::size_t>(k)];
    return static_cast<std::size_t>(e >= 0 ? e : ~e);
  }
  /// +1 if the disk of adjacency entry k is its bond's bi, -1 if it is its bj.
  [[nodiscard]] double adj_sign(std::int64_t k) const { return adj_entry[static_cast<std::size_t>(k)] >= 0 ? 1.0 : -1.0; }
  /// Bonds of disk i in the initial lattice (the adjacency holds them all, broken or not).
  [[nodiscard]] std::int64_t initial_bonds(std::size_t i) const { return adj_offset[i + 1] - adj_offset[i]; }
  /// w of disk i: the thickness (plane) or the ring radius b (axisymmetric) [m].
  [[nodiscard]] double disk_weight(std::size_t i) const { return weight.empty() ? thickness : weight[i]; }
  /// The mass the contact stiffness cap is reckoned with for disk i [kg; kg/rad in
  /// axisymmetry]: its own, or with whole_cell_cap the mass of its whole hexagonal cell
  /// (2 sqrt(3) r^2 instead of its cell's area: a disk whose cell the outline or the axis cuts),
  /// at most kMaxCapMassFactor times its own. An interior disk's is its own.
  [[nodiscard]] double cap_mass(std::size_t i) const {
    if (!whole_cell_cap) return mass[i];
    const double hexagon = 2.0 * std::numbers::sqrt3 * radius[i] * radius[i];
    return mass[i] * std::clamp(hexagon / cell_area[i], 1.0, kMaxCapMassFactor);
  }
  /// Stiffness cap of a contact between disks i and j [N/m]: m_eff contact_omega2, m_eff of
  /// their cap masses (broken bonds, bodies, fragments: the one cap of forces and energy).
  [[nodiscard]] double contact_cap(std::size_t i, std::size_t j) const {
    const double mi = cap_mass(i), mj = cap_mass(j);
    return mi * mj / (mi + mj) * contact_omega2;
  }
  /// Stiffness cap of a contact of disk i with a rigid wall [N/m]: its cap mass times
  /// contact_omega2 (the wall is the infinite mass of the pair rule above).
  [[nodiscard]] double wall_contact_cap(std::size_t i) const { return cap_mass(i) * contact_omega2; }
  /// Moment of inertia I = m r^2 / 2 [kg m^2] (per radian in axisymmetry).
  [[nodiscard]] double disk_inertia(std::size_t i) const { return 0.5 * mass[i] * radius[i] * radius[i]; }
  [[nodiscard]] double bond_section(std::size_t b) const {
    if (!section.empty()) return section[b];
    const double w = thickness * ((spring_kind[b] & 1) ? 0.5 : 1.0);  // an edge bond has half a section
    return 2.0 * radius[static_cast<std::size_t>(bi[b])] * w;
  }
  [[nodiscard]] double bond_mu(std::size_t b) const { return body_mu[static_cast<std::size_t>(body[static_cast<std::size_t>(bi[b])])]; }
  [[nodiscard]] std::int32_t bond_failure_law(std::size_t b) const {
    return body_failure_law[static_cast<std::size_t>(body[static_cast<std::size_t>(bi[b])])];
  }
  [[nodiscard]] std::uint8_t bond_class_of(std::size_t b) const {
    return bond_class.empty() ? (spring_kind[b] % 12 < 4 ? 1 : 2) : bond_class[b];
  }
  [[nodiscard]] std::int32_t disk_material(std::size_t i) const {
    return body_material[static_cast<std::size_t>(body[i])];
  }
  /// Bond b's row; b must have one (it has cracked or broken: add_failed_row).
  [[nodiscard]] FailedBond& failed(std::size_t b) { return failed_rows[static_cast<std::size_t>(failed_row[b])]; }
  /// Bond b's row, or that of a bond that never cracked (all zero, break time -1).
  [[nodiscard]] const FailedBond& failed_or_none(std::size_t b) const {
    static const FailedBond none;
    return failed_row.empty() || failed_row[b] < 0 ? none : failed_rows[static_cast<std::size_t>(failed_row[b])];
  }
  [[nodiscard]] double bond_fracture_energy(std::size_t b) const { return failed_or_none(b).fracture_energy; }
  /// The crack kind of bond b (FailedBond::crack; kNoCrack if it never cracked) and its
  /// damage D (1 once broken, 0 if it never cracked or broke).
  [[nodiscard]] std::int64_t bond_crack(std::size_t b) const { return failed_or_none(b).crack; }
  [[nodiscard]] double bond_damage(std::size_t b) const { return failed_or_none(b).damage; }
  [[nodiscard]] double bond_break_kinetic(std::size_t b) const { return failed_or_none(b).break_kinetic; }
  [[nodiscard]] double bond_break_time(std::size_t b) const { return failed_or_none(b).break_time; }
  [[nodiscard]] double contact_damping_work(std::size_t b) const { return failed_or_none(b).damping_work; }
  [[nodiscard]] double contact_friction_work(std::size_t b) const { return failed_or_none(b).friction_work; }
  /// No plasticity, failure or J2 disks: the bond pass is elastic_bond_forces, and the bonds
  /// keep their pair force (pair_fx, pair_fy) instead of f_n, nx and ny.
  [[nodiscard]] bool elastic_lattice() const { return !(any_plastic || any_breakable || any_softening || any_j2); }
  /// The radius at which disk i touches others [m] (docs/model.md, "Contact radii").
  [[nodiscard]] double contact_r(std::size_t i) const { return contact_radius.empty() ? radius[i] : contact_radius[i]; }
  /// The contact radii of all disks [m], num_disks() of them.
  [[nodiscard]] const double* contact_radii() const {
    return contact_radius.empty() ? radius.data() : contact_radius.data();
  }
  /// Rest length of bond b [m].
  [[nodiscard]] double rest(std::size_t b) const { return kind_rest.empty() ? rest_length[b] : kind_rest[spring_kind[b]]; }
  /// The length at which bond b's disks touch once it has broken [m]: r_i + r_j, or on an
  /// irregular lattice the smaller of that and the rest length, so that disks moved closer
  /// than r_i + r_j are not pushed apart when their bond breaks (docs/model.md, "Irregular
  /// lattice").
  [[nodiscard]] double touch(std::size_t b) const {
    const double sum = contact_r(static_cast<std::size_t>(bi[b])) + contact_r(static_cast<std::size_t>(bj[b]));
    return touch_at_rest ? std::min(rest(b), sum) : sum;
  }
  [[nodiscard]] double kn(std::size_t b) const { return k_n.empty() ? kind_k_n[spring_kind[b]] : k_n[b]; }
  [[nodiscard]] double ks(std::size_t b) const { return k_s.empty() ? kind_k_s[spring_kind[b]] : k_s[b]; }
  [[nodiscard]] double strength_factor(std::size_t b) const { return strength_scale.empty() ? 1.0 : strength_scale[b]; }
  [[nodiscard]] double stiffness_factor(std::size_t b) const { return stiffness_scale.empty() ? 1.0 : stiffness_scale[b]; }
  /// Bond b has bilinear hardening springs (Eq. 16); the arrays exist only if some do.
  [[nodiscard]] bool yields(std::size_t b) const { return !bond_plastic.f_yield.empty() && bond_plastic.f_yield[b] > 0; }
  [[nodiscard]] bool on_mirror(std::size_t i) const { return !mirror.plane.empty() && mirror.plane[i] != 0; }
  /// Some disk has a spring to a mirror plane (wall_* exist only then).
  [[nodiscard]] bool has_mirror_springs() const { return !mirror.kx.empty(); }
};

/// Per-body material choice and spring constants, ready for Model construction.
struct BodyMaterial {
  const Material* material = nullptr;
  SpringConstants springs;  ///< per unit thickness [Pa]
  /// A plastic material's model as resolved by the solver: J2 per disk if true, else the
  /// bilinear springs of Eq. 16.
  bool j2 = false;
};

/// Builds the model from a lattice: masses from the cell areas (physics.md section 1, not the
/// paper's disk mass), springs from section 3 scaled by the thickness or the bond's ring
/// radius (Eq. 15), adjacency, and the local-strain matrices. `materials[body]` gives each
/// body's material.
Model build_model(const meshing::Lattice& lattice, Geometry geometry, double thickness,
                  ShearModel shear_model, const std::vector<BodyMaterial>& materials);
/// The same, taking the lattice's disk and bond arrays (centres, radii, cell areas, kinds,
/// bodies, materials, bond ends and classes) instead of copying them: the lattice keeps its
/// names, sets and the arrays the model does not hold.
Model build_model(meshing::Lattice&& lattice, Geometry geometry, double thickness,
                  ShearModel shear_model, const std::vector<BodyMaterial>& materials);

/// Recomputes the local-strain matrices (inverse of sum a a^T over intact bonds) of all disks.
void update_strain_matrices(Model& m);
/// The same for disk i.
void update_strain_matrix(Model& m, std::size_t i);

/// Returns every bond to its initial, unloaded and intact state (forces, back-forces,
/// previous lengths, states, cumulative energies), and every J2 disk to its virgin state
/// (plastic strain, back stress, plastic work).
void reset_bond_history(Model& m);

/// The part of reset_bond_history that the forces depend on: the springs' forces and
/// back-forces, previous lengths, states, damage and the J2 disks' plastic state, but not the
/// cumulative energies and break times, which no force reads (the critical-step probes reset
/// this between force passes, and everything once at the end). Every bond is intact after it:
/// the failed bonds' rows go with their states.
void reset_force_history(Model& m);

/// Bond b's FailedBond row, added if it has none (settle_broken_bonds, when a bond starts to
/// crack or breaks).
Model::FailedBond& add_failed_row(Model& m, std::size_t b);
/// Breaks bond b into state `s` (a BondState past Yielded) with a row of its own, as
/// settle_broken_bonds does, without its energy bookkeeping (tests and hand-made states).
void mark_broken(Model& m, std::size_t b, BondState s);

/// Computes internal forces at the current displacements into fx, fy, torque (overwriting),
/// and the bond forces f_n, f_s. For the rotation model the shear force is incremented by
/// k_s du_s with the increments dt*v, dt*omega of the last step (Eq. 2); the local-strain
/// model takes it from the disks' strains. Deterministic: the result does not depend on the
/// number of threads. Bonds found past their strength are broken at the end of the pass
/// (settle_broken_bonds): the returned forces are those without them. Returns the number of
/// bonds that broke.
std::size_t compute_internal_forces(Model& m, double dt);
/// Builds Model::nonlocal with the averaging radius R [m] of each body (0: none), after the
/// strain fits (nonlocal.cpp).
void build_nonlocal_strain(Model& m, const std::vector<double>& body_radius);
/// Builds Model::local_criterion where softening bonds use the local criterion (some material
/// with a fracture energy and no nonlocal radius), after the random field (nonlocal.cpp).
void build_local_criterion(Model& m);

/// The same forces for the critical-step estimate (Solver::finite_omega2_max), on a state
/// whose bonds' history has just been reset: the rotation model's shear increments are the
/// displacements and rotations themselves (dt = 1 and v = u, the same bits as setting the
/// velocities to the displacements), so the velocity arrays are free to hold the estimate's
/// vectors. No bond breaks.
void compute_probe_forces(Model& m);

/// Elastic energy stored in the springs, contacts and out-of-plane (hoop) term, including
/// the locked-in energy of the hardening springs and of the J2 disks' back stress,
/// A w (1/3) H eps_p : eps_p [J], deterministic.
double elastic_energy(const Model& m);

/// Cumulative dissipation of the bonds and disks [J]: plastic work (springs; J2 disks: the
/// work done on eps_p less the stored hardening energy), energy released by breaking,
/// contact dashpot and friction; deterministic.
struct BondDissipation {
  double plastic = 0, fracture = 0, contact_damping = 0, friction = 0;
  double break_kinetic = 0;  ///< the kinetic half step of breaks and damage steps (of either sign)
};
BondDissipation bond_dissipation(const Model& m);

/// After a force pass that found bonds past their strength (newly_broken): breaks them (each
/// becomes a contact, state II), recomputes the local-strain matrices and strains of their
/// disks and the forces of the whole model, and books the drop of the leap-frog energy at t_n,
/// V(with) - V(without) + (dt/2) sum v(t-dt/2).(F(with) - F(without)): each bond's own
/// release (the bilinear form of its springs over the last two steps, >= 0) as its
/// fracture_energy, the new contact's first dashpot half step as contact damping, and the
/// rest, the integrator's share, as break_kinetic (docs/model.md, "Energy at a break").
/// Returns the number of bonds that broke.
std::size_t settle_broken_bonds(Model& m, double dt);

/// Bond b's normal and shear force [N] and current unit vector from bi to bj, at the last
/// force pass: stored, or, in an elastic lattice, f_n = k_n (L - L0) and n from the current
/// positions by the bond pass's own arithmetic (the same bits).
struct BondForce {
  double f_n = 0, f_s = 0, nx = 0, ny = 0;
};
BondForce bond_force(const Model& m, std::size_t b);

/// Love-Weber stress of disk i [Pa]: sigma = 1/(A w) sum sym(x_c (x) f_c), in components
/// xx, yy, xy, and zz (plane strain isotropic: nu(sxx+syy); axisymmetric: the hoop stress;
/// J2 disks: (lambda + 2 mu) e33 + lambda tr(e) of the elastic strain e).
struct Stress {
  double xx = 0, yy = 0, xy = 0, zz = 0;
};
Stress disk_stress(const Model& m, std::size_t i);

/// Sum of f(k) for k in [0, n), in fixed blocks of kSumBlock terms summed in parallel and
/// then in order, so the result does not depend on the thread count. `scratch` holds the
/// block sums (grown once, then reused: no allocation per step).
template <class F>
double deterministic_sum(std::size_t n, F&& f, std::vector<double>& scratch);

}  // namespace hexdem::solver

#include "hexdem/solver/model_inl.hpp"
