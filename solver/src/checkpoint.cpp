// Checkpoint and restart: the complete state of a run in one file, written atomically
// (layout: checkpoint.hpp). One list of members per class (visit_model, visit_solver) drives
// writing, reading and the coverage check: adding a state vector is one line there.
#include "hexdem/solver/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"

namespace hexdem::solver {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'H', 'E', 'X', 'D', 'E', 'M', 'C', 'K'};

template <class T>
struct is_vector : std::false_type {};
template <class T, class A>
struct is_vector<std::vector<T, A>> : std::true_type {};

/// The members of Model, in declaration order. `v.state(name, member)` for state the
/// checkpoint stores (everything that may change during a run, and the constants built with
/// it: restoring them is exact and cheap to reason about); `v.rebuilt(name, member)` for
/// what the constructor rebuilds from the case (or work space a step overwrites).
template <class M, class V>
void visit_model(M& m, V& v) {
  v.rebuilt("geometry", m.geometry);
  v.rebuilt("shear_model", m.shear_model);
  v.rebuilt("uses_strains", m.uses_strains);
  v.state("thickness", m.thickness);
  // disks
  v.state("x0", m.x0); v.state("y0", m.y0);
  v.state("ux", m.ux); v.state("uy", m.uy);
  v.state("vx", m.vx); v.state("vy", m.vy);
  v.state("theta", m.theta); v.state("omega", m.omega);
  v.state("fx", m.fx); v.state("fy", m.fy); v.state("torque", m.torque);
  v.state("fx_ext", m.fx_ext); v.state("fy_ext", m.fy_ext);
  v.state("ext_mxx", m.ext_mxx); v.state("ext_myy", m.ext_myy); v.state("ext_mxy", m.ext_mxy);
  v.state("mass", m.mass);
  v.state("radius", m.radius);
  v.rebuilt("contact_radius", m.contact_radius);  // from the lattice and [contact] radius_spread
  v.state("cell_area", m.cell_area);
  v.state("weight", m.weight);
  v.state("kind", m.kind);
  v.state("body", m.body); v.state("body_material", m.body_material);
  v.state("constraint", m.constraint);
  v.state("mirror_plane", m.mirror.plane);
  v.state("wall_kx", m.mirror.kx); v.state("wall_ky", m.mirror.ky);
  v.state("wall_sx", m.mirror.sx); v.state("wall_sy", m.mirror.sy);
  v.state("minv_xx", m.strain.minv_xx); v.state("minv_xy", m.strain.minv_xy); v.state("minv_yy", m.strain.minv_yy);
  v.state("strain_ok", m.strain.ok);
  v.state("eps_xx", m.strain.eps_xx); v.state("eps_yy", m.strain.eps_yy); v.state("eps_xy", m.strain.eps_xy);
  v.rebuilt("eps_tt", m.strain.eps_tt);  // the hoop strain of the force passes, from u_r
  v.state("eps_off_xx", m.strain.eps_off_xx); v.state("eps_off_yy", m.strain.eps_off_yy); v.state("eps_off_xy", m.strain.eps_off_xy);
  v.state("hoop_cut", m.hoop.cut); v.state("hoop_const", m.hoop.constant);
  v.state("w_xx", m.strain.w_xx); v.state("w_xy", m.strain.w_xy); v.state("w_yx", m.strain.w_yx); v.state("w_yy", m.strain.w_yy);
  // The nonlocal criterion's rows (from the case and the reference lattice) and its averages
  // (recomputed from the strains before every use).
  v.rebuilt("nonlocal_offset", m.nonlocal.offset); v.rebuilt("nonlocal_nbr", m.nonlocal.nbr);
  v.rebuilt("nonlocal_w", m.nonlocal.w);
  v.rebuilt("nonlocal_eps_xx", m.nonlocal.eps_xx); v.rebuilt("nonlocal_eps_yy", m.nonlocal.eps_yy);
  v.rebuilt("nonlocal_eps_xy", m.nonlocal.eps_xy); v.rebuilt("nonlocal_eps_tt", m.nonlocal.eps_tt);
  v.rebuilt("nonlocal_skip_far", m.nonlocal.skip_far);
  v.rebuilt("nonlocal_cells_x", m.nonlocal.cells_x); v.rebuilt("nonlocal_cells_y", m.nonlocal.cells_y);
  v.rebuilt("nonlocal_cell", m.nonlocal.cell);
  v.rebuilt("nonlocal_body_inv_ft", m.nonlocal.body_inv_ft); v.rebuilt("nonlocal_body_inv_fc", m.nonlocal.body_inv_fc);
  v.rebuilt("nonlocal_body_inv_mc", m.nonlocal.body_inv_mc);
  v.rebuilt("nonlocal_relative", m.nonlocal.relative); v.rebuilt("nonlocal_packed", m.nonlocal.packed);
  v.rebuilt("nonlocal_cell_max", m.nonlocal.cell_max);
  v.rebuilt("nonlocal_hot", m.nonlocal.hot);
  // The local criterion's bound (from the case) and its classes (recomputed every strain pass).
  v.rebuilt("local_criterion_body", m.local_criterion.body);
  v.rebuilt("local_criterion_disk", m.local_criterion.disk);
  v.state("hoop_lambda", m.hoop.lambda); v.state("hoop_mu", m.hoop.mu);
  v.state("nu_zz", m.hoop.nu_zz);
  v.state("vx_old", m.vx_old); v.state("vy_old", m.vy_old); v.state("omega_old", m.omega_old);
  // bonds
  v.state("bi", m.bi); v.state("bj", m.bj);
  v.state("rest_length", m.rest_length);
  v.state("g_xx", m.g_xx); v.state("g_yy", m.g_yy); v.state("g_xy", m.g_xy);
  v.rebuilt("touch_at_rest", m.touch_at_rest);  // from the reference geometry (build_model)
  v.rebuilt("kind_ax", m.kind_ax); v.rebuilt("kind_ay", m.kind_ay);  // per kind: from the lattice
  v.rebuilt("kind_rest", m.kind_rest);
  v.rebuilt("kind_g_xx", m.kind_g_xx); v.rebuilt("kind_g_yy", m.kind_g_yy); v.rebuilt("kind_g_xy", m.kind_g_xy);
  v.state("k_n", m.k_n); v.state("k_s", m.k_s);
  v.rebuilt("spring_kind", m.spring_kind);  // per-kind stiffnesses: from the lattice and materials
  v.rebuilt("kind_k_n", m.kind_k_n); v.rebuilt("kind_k_s", m.kind_k_s);
  v.state("f_n", m.f_n); v.state("f_s", m.f_s);
  v.state("nx", m.nx); v.state("ny", m.ny);  // empty in an elastic lattice
  v.rebuilt("pair_fx", m.pair_fx); v.rebuilt("pair_fy", m.pair_fy);  // from the positions, every force pass
  v.state("u_s", m.u_s);
  v.state("state", m.state);
  v.state("bond_class", m.bond_class);
  // plasticity, failure, contact of the bonds
  v.state("any_plastic", m.any_plastic);
  v.state("any_breakable", m.any_breakable);
  v.state("contact_damping", m.contact_damping);
  v.state("contact_omega2", m.contact_omega2);
  v.rebuilt("whole_cell_cap", m.whole_cell_cap);  // from [contact] cap_mass
  v.state("time", m.time);
  v.state("f_yield", m.bond_plastic.f_yield);
  v.state("kh_n", m.bond_plastic.kh_n); v.state("kh_s", m.bond_plastic.kh_s);
  v.state("alpha_n", m.bond_plastic.alpha_n); v.state("alpha_s", m.bond_plastic.alpha_s);
  v.state("len_prev", m.len_prev);
  v.state("section", m.section);
  v.rebuilt("body_mu", m.body_mu);  // per body, from the materials
  v.rebuilt("body_failure_law", m.body_failure_law);
  v.rebuilt("failure_laws", m.failure_laws);
  v.state("failure_tan_phi", m.failure_tan_phi);
  v.state("plastic_work", m.bond_plastic.work);
  v.state("failed_rows", m.failed_rows);
  v.state("failed_row", m.failed_row);
  v.state("newly_broken", m.newly_broken);
  // softening failure
  v.state("any_softening", m.any_softening);
  v.rebuilt("softening", m.softening);
  v.rebuilt("crack_starts", m.cracks.starts);  // work space of a force pass and settle_broken_bonds: empty between steps
  v.state("hoop_damage", m.hoop_cracks.damage); v.state("hoop_kappa", m.hoop_cracks.kappa);
  v.state("hoop_e0", m.hoop_cracks.e0); v.state("hoop_ef", m.hoop_cracks.ef);
  v.state("hoop_e_last", m.hoop_cracks.e_last);
  v.state("hoop_fracture", m.hoop_cracks.fracture);
  v.state("hoop_break_kinetic", m.hoop_cracks.break_kinetic);
  v.state("strength_scale", m.strength_scale); v.state("disk_strength_scale", m.disk_strength_scale);
  v.state("stiffness_scale", m.stiffness_scale);
  v.rebuilt("fx_intact", m.fx_intact);  // work space of settle_broken_bonds
  v.rebuilt("fy_intact", m.fy_intact);
  v.rebuilt("torque_intact", m.torque_intact);
  // J2 disks
  v.state("any_j2", m.any_j2);
  v.state("j2_sigma_y", m.j2.sigma_y); v.state("j2_alpha", m.j2.alpha);
  v.state("j2_h", m.j2.h);
  v.state("eps_p_xx", m.j2.eps_p_xx); v.state("eps_p_yy", m.j2.eps_p_yy);
  v.state("eps_p_xy", m.j2.eps_p_xy); v.state("eps_p_33", m.j2.eps_p_33);
  v.state("beta_xx", m.j2.beta_xx); v.state("beta_yy", m.j2.beta_yy);
  v.state("beta_xy", m.j2.beta_xy); v.state("beta_33", m.j2.beta_33);
  v.state("eps_p_eq", m.j2.eps_p_eq);
  v.state("sig_xx", m.j2.sig_xx); v.state("sig_yy", m.j2.sig_yy);
  v.state("sig_xy", m.j2.sig_xy); v.state("sig_33", m.j2.sig_33);
  v.state("disk_plastic_work", m.j2.work);
  // adjacency
  v.state("adj_offset", m.adj_offset); v.state("adj_entry", m.adj_entry);
  v.rebuilt("scratch", m.scratch);  // work space of deterministic_sum
  v.rebuilt("balance", m.balance);  // the threads' parts of the force passes' loops
  v.rebuilt("event_weights", m.event_weights);  // work space of settle_broken_bonds
  v.rebuilt("event_half", m.event_half);  // work space of settle_broken_bonds
  v.rebuilt("event_d_len", m.event_d_len);
}

/// The one refusal of a damaged checkpoint: the file, what is wrong, exit code 2.
[[noreturn]] void damaged(const std::string& path, const std::string& what) {
  throw InputError(path + ": damaged checkpoint: " + what);
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

/// Consistency of a restored state (read_checkpoint): a checksum proves only that the file is
/// the one written, not that what was written describes this model. Every index must point
/// into the arrays it indexes, every enumerated value must be one of its values, every
/// scalar must be finite and in the run's range, and the constants built with the model
/// (bond ends, adjacency, kinds, bodies, reference centres, masses) must be the ones the
/// case builds, before anything reads them.
///
/// The parts of a freshly built solver that its restored state must match.
struct Built {
  std::map<std::string, std::size_t> sizes;  ///< every stored vector's length, by record name
  std::vector<std::int32_t> bi, bj, adj_offset, adj_entry, body, body_material;
  std::vector<std::uint8_t> kind, bond_class;
  std::vector<double> x0, y0, radius, cell_area, mass;
  bool any_plastic = false, any_breakable = false, any_softening = false, any_j2 = false, contacts_on = false;
};

class Check {
 public:
  explicit Check(std::string path) : path_(std::move(path)) {}
  [[noreturn]] void fail(const std::string& what) const { damaged(path_, what); }

  /// Every element of record `name` in [lo, hi]; `what` says what the values index.
  template <class T>
  void range(const std::string& name, const std::vector<T>& v, std::int64_t lo, std::int64_t hi,
             const std::string& what) const {
    for (std::size_t k = 0; k < v.size(); ++k) {
      const auto x = static_cast<std::int64_t>(v[k]);
      if (x < lo || x > hi)
        fail("record '" + name + "' element " + std::to_string(k) + " is " + std::to_string(x) + ", outside " +
             std::to_string(lo) + ".." + std::to_string(hi) + " (" + what + ")");
    }
  }
  /// A restored constant of the model equals the one the case builds.
  template <class T>
  void same(const std::string& name, const std::vector<T>& got, const std::vector<T>& built) const {
    if (got.size() != built.size())
      fail("record '" + name + "' has " + std::to_string(got.size()) + " elements, the case builds " +
           std::to_string(built.size()));
    for (std::size_t k = 0; k < got.size(); ++k)
      if (std::memcmp(&got[k], &built[k], sizeof(T)) != 0) {
        const auto show = [](T x) {
          if constexpr (std::is_floating_point_v<T>) return number(x);
          else return std::to_string(static_cast<std::int64_t>(x));
        };
        fail("record '" + name + "' element " + std::to_string(k) + " is " + show(got[k]) + ", the case builds " +
             show(built[k]));
      }
  }
  void same(const std::string& name, bool got, bool built) const {
    if (got != built)
      fail("record '" + name + "' is " + (got ? "true" : "false") + ", the case builds " + (built ? "true" : "false"));
  }
  /// A scalar record is finite and within [lo, hi].
  void scalar(const std::string& name, double v, double lo, double hi) const {
    if (!std::isfinite(v) || v < lo || v > hi)
      fail("record '" + name + "' is " + number(v) + ", expected a finite value in [" + number(lo) + ", " + number(hi) +
           "]");
  }
  void finite(const std::string& name, double v) const {
    if (!std::isfinite(v)) fail("record '" + name + "' is " + number(v) + ", not finite");
  }

 private:
  std::string path_;
};

}  // namespace

/// The Solver's members, in declaration order (see visit_model).
struct CheckpointAccess {
  template <class S, class V>
  static void visit_solver(S& s, V& v) {
    v.rebuilt("case", s.case_);
    v.rebuilt("lattice", s.lattice_);
    v.rebuilt("lattice_hash", s.lattice_hash_);
    v.model("model", s.model_);
    v.rebuilt("body_materials", s.body_materials_);
    v.rebuilt("bloch", s.bloch_);
    v.rebuilt("plasticity_report", s.plasticity_report_);
    v.rebuilt("warnings", s.warnings_);
    v.rebuilt("loads", s.loads_);
    v.rebuilt("velocity_sets", s.velocity_sets_);
    v.rebuilt("loaded_disks", s.loaded_disks_);
    v.rebuilt("reaction_sets", s.reaction_sets_);
    v.rebuilt("block_sums", s.block_sums_);  // work space of update_velocities
    v.state("dt_info", s.dt_info_);
    v.rebuilt("finite_disks", s.finite_disks_);  // the size of the set-up's estimate, not state
    v.rebuilt("setup_times", s.setup_times_);  // timing of the set-up, not state
    v.state("energy", s.energy_);
    v.rebuilt("blow_up", s.blow_up_);
    v.state("last_checked", s.last_checked_);
    v.state("last_checked_time", s.last_checked_time_);
    v.state("max_energy_error", s.max_energy_error_);
    v.state("energy_warning", s.energy_warning_);
    v.state("time", s.time_);
    v.state("step", s.step_);
    v.state("p_max", s.p_max_);
    v.state("ext_b_before", s.ext_b_before_);
    v.state("damp_b_before", s.damp_b_before_);
    v.state("ext_a", s.ext_a_);
    v.state("damp_a", s.damp_a_);
    v.state("initial_energy", s.initial_energy_);
    v.state("broken_bonds", s.broken_bonds_);
    v.state("contacts_on", s.contacts_on_);
    v.rebuilt("sweep", s.sweep_);  // rebuilt from the centres by rebuild_broad_phase
    v.state("px", s.px_);
    v.state("py", s.py_);
    v.state("contacts", s.contacts_);
    v.rebuilt("contacts_next", s.contacts_next_);  // work space of contact_forces
    v.rebuilt("body_kn", s.body_kn_);
    v.rebuilt("body_kt", s.body_kt_);
    v.rebuilt("body_mu", s.body_mu_);
    v.state("contact_damping_work", s.contact_damping_work_);
    v.state("contact_friction_work", s.contact_friction_work_);
    v.rebuilt("detection_seconds", s.detection_seconds_);  // wall time of this process, not state
    v.state("wall_fn", s.wall_fn_);
    v.state("wall_fs", s.wall_fs_);
    v.state("wall_fv", s.wall_fv_);
  }

  /// The sizes and constants of a freshly built solver that its restored state must match.
  static Built built(const Solver& s);
  /// Refuses (InputError naming the file, the record and the value) a restored state that
  /// does not fit the model `b` describes and the case's run.
  static void check_restored(const Solver& s, const Built& b, const RunState& run, const Check& c);

  /// After the stored state is in place: the broad phase from the restored centres, and the
  /// contact list as its candidate pairs with the stored forces carried over.
  static void rebuild_broad_phase(Solver& s, const std::string& path) {
    if (!s.contacts_on_) return;
    const Model& m = s.model_;
    const std::size_t n = m.num_disks();
    if (s.px_.size() != n || s.py_.size() != n)
      throw InputError(path + ": damaged checkpoint: contact centres for " + std::to_string(s.px_.size()) +
                       " disks, the model has " + std::to_string(n));
    s.sweep_.build(s.px_.data(), s.py_.data(), m.radius.data(), n, s.sweep_.margin());
    std::vector<Solver::Contact> stored;
    stored.swap(s.contacts_);
    std::size_t k = 0, carried = 0;
    for (const auto& [i, j] : s.sweep_.pairs()) {
      while (k < stored.size() && (stored[k].i < i || (stored[k].i == i && stored[k].j < j))) ++k;
      Solver::Contact c{i, j, 0.0, 0.0};
      if (k < stored.size() && stored[k].i == i && stored[k].j == j) {
        c = stored[k];
        carried += c.f_n != 0 || c.f_s != 0;
      }
      s.contacts_.push_back(c);
    }
    std::size_t loaded = 0;
    for (const Solver::Contact& c : stored) loaded += c.f_n != 0 || c.f_s != 0;
    // A pair that carries force touches: it is a candidate of any broad phase of these centres.
    HEXDEM_VERIFY(carried == loaded, "a loaded contact is missing from the rebuilt broad phase");
  }
};

namespace {

// ---- writing ------------------------------------------------------------------------

/// The visitors' record names: a nested model's members are "<name>.<member>" (visit_solver
/// calls v.model("model", ...)).
template <class Derived>
class Prefixed {
 public:
  template <class M>
  void model(const char* name, M& m) {
    const std::string saved = prefix_;
    prefix_ = saved + name + ".";
    visit_model(m, static_cast<Derived&>(*this));
    prefix_ = saved;
  }

 protected:
  std::string prefix_;
};

class Writer : public Prefixed<Writer> {
 public:
  template <class T>
  void state(const char* name, const T& value) {
    const std::string key = prefix_ + name;
    if constexpr (std::is_same_v<T, std::string>) {
      raw(key, value.data(), 1, value.size());
    } else if constexpr (is_vector<T>::value) {
      using E = typename T::value_type;
      if constexpr (is_vector<E>::value) {
        // A vector of vectors (per wall, per disk): the count, then each row.
        const std::uint64_t rows = value.size();
        raw(key + ".rows", &rows, sizeof rows, 1);
        for (std::size_t r = 0; r < value.size(); ++r) state((std::string(name) + "." + std::to_string(r)).c_str(), value[r]);
      } else {
        static_assert(std::is_trivially_copyable_v<E>);
        raw(key, value.data(), sizeof(E), value.size());
      }
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      raw(key, &value, sizeof(T), 1);
    }
  }
  template <class T>
  void rebuilt(const char*, const T&) {}
  void text(const std::string& name, const std::string& value) { raw(name, value.data(), 1, value.size()); }

  void raw(const std::string& name, const void* data, std::size_t elem, std::size_t count) {
    put<std::uint32_t>(static_cast<std::uint32_t>(name.size()));
    buf_.append(name);
    put<std::uint32_t>(static_cast<std::uint32_t>(elem));
    put<std::uint64_t>(count);
    buf_.append(static_cast<const char*>(data), elem * count);
    names_.push_back(name);
  }
  template <class T>
  void put(T v) {
    buf_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }

  std::string buf_;
  std::vector<std::string> names_;
};

void save_run(Writer& w, const RunState& run) {
  w.state("run.next_frame", run.next_frame);
  w.state("run.next_probe", run.next_probe);
  w.state("run.next_checkpoint", run.next_checkpoint);
  w.state("run.max_error", run.max_error);
  std::vector<double> times;
  std::string files;
  for (const io::PvdEntry& e : run.frames) {
    times.push_back(e.time);
    files += e.file + '\n';
  }
  w.state("run.frame_times", times);
  w.text("run.frame_files", files);
  w.text("run.last_frame", run.last_frame);
  w.state("run.energy_bytes", run.energy_bytes);
  w.state("run.probes_bytes", run.probes_bytes);
  w.state("run.bodies_bytes", run.bodies_bytes);
  w.state("run.energy_hash", run.energy_hash);
  w.state("run.probes_hash", run.probes_hash);
  w.state("run.bodies_hash", run.bodies_hash);
  w.state("run.reactions_bytes", run.reactions_bytes);
  w.state("run.reactions_hash", run.reactions_hash);
}

// ---- reading ------------------------------------------------------------------------

struct Record {
  std::size_t elem = 0, count = 0;
  const char* data = nullptr;
};

class Reader : public Prefixed<Reader> {
 public:
  Reader(std::string path, std::map<std::string, Record> records)
      : path_(std::move(path)), records_(std::move(records)) {}

  template <class T>
  void state(const char* name, T& value) {
    const std::string key = prefix_ + name;
    if constexpr (std::is_same_v<T, std::string>) {
      const Record& r = find(key, 1);
      value.assign(static_cast<const char*>(static_cast<const void*>(r.data)), r.count);
    } else if constexpr (is_vector<T>::value) {
      using E = typename T::value_type;
      if constexpr (is_vector<E>::value) {
        std::uint64_t rows = 0;
        const Record& r = find(key + ".rows", sizeof rows);
        expect_count(key + ".rows", r, 1);
        std::memcpy(&rows, r.data, sizeof rows);
        if (rows > (1u << 20)) fail("record '" + key + ".rows' holds " + std::to_string(rows) + " rows");
        value.resize(rows);
        for (std::size_t k = 0; k < rows; ++k) state((std::string(name) + "." + std::to_string(k)).c_str(), value[k]);
      } else {
        const Record& r = find(key, sizeof(E));
        value.resize(r.count);
        if (r.count > 0) std::memcpy(static_cast<void*>(value.data()), r.data, sizeof(E) * r.count);
      }
    } else {
      const Record& r = find(key, sizeof(T));
      expect_count(key, r, 1);
      std::memcpy(static_cast<void*>(&value), r.data, sizeof(T));
    }
  }
  template <class T>
  void rebuilt(const char*, T&) {}
  std::string text(const std::string& name) {
    const Record& r = find(name, 1);
    return std::string(r.data, r.count);
  }

  [[noreturn]] void fail(const std::string& what) const { damaged(path_, what); }

 private:
  const Record& find(const std::string& name, std::size_t elem) const {
    const auto it = records_.find(name);
    if (it == records_.end()) fail("record '" + name + "' is missing");
    if (it->second.elem != elem)
      fail("record '" + name + "' has " + std::to_string(it->second.elem) + "-byte elements, expected " +
           std::to_string(elem));
    return it->second;
  }
  void expect_count(const std::string& name, const Record& r, std::size_t count) const {
    if (r.count != count)
      fail("record '" + name + "' has " + std::to_string(r.count) + " elements, expected " + std::to_string(count));
  }

  std::string path_;
  std::map<std::string, Record> records_;
};

void load_run(Reader& r, RunState& run) {
  r.state("run.next_frame", run.next_frame);
  r.state("run.next_probe", run.next_probe);
  r.state("run.next_checkpoint", run.next_checkpoint);
  r.state("run.max_error", run.max_error);
  std::vector<double> times;
  r.state("run.frame_times", times);
  const std::string files = r.text("run.frame_files");
  run.frames.clear();
  std::size_t at = 0;
  for (double t : times) {
    const std::size_t end = files.find('\n', at);
    if (end == std::string::npos) r.fail("fewer frame names than frame times");
    run.frames.push_back({t, files.substr(at, end - at)});
    at = end + 1;
  }
  if (at != files.size()) r.fail("more frame names than frame times");
  run.last_frame = r.text("run.last_frame");
  r.state("run.energy_bytes", run.energy_bytes);
  r.state("run.probes_bytes", run.probes_bytes);
  r.state("run.bodies_bytes", run.bodies_bytes);
  r.state("run.energy_hash", run.energy_hash);
  r.state("run.probes_hash", run.probes_hash);
  r.state("run.bodies_hash", run.bodies_hash);
  r.state("run.reactions_bytes", run.reactions_bytes);
  r.state("run.reactions_hash", run.reactions_hash);
}

// ---- consistency --------------------------------------------------------------------

/// The length of every vector the checkpoint stores, by record name (a vector of vectors: its
/// row count as "<name>.rows" and each row as "<name>.<k>", as the Writer names them).
class Shapes : public Prefixed<Shapes> {
 public:
  template <class T>
  void state(const char* name, const T& value) {
    if constexpr (is_vector<T>::value) {
      if constexpr (is_vector<typename T::value_type>::value) {
        sizes[prefix_ + name + ".rows"] = value.size();
        for (std::size_t r = 0; r < value.size(); ++r) state((std::string(name) + "." + std::to_string(r)).c_str(), value[r]);
      } else {
        sizes[prefix_ + name] = value.size();
      }
    }
  }
  template <class T>
  void rebuilt(const char*, const T&) {}
  std::map<std::string, std::size_t> sizes;
};

/// The first value of a stored vector of doubles (a state record) that is not finite: the
/// state of a run that passed its run-health checks has none (positions, velocities, forces,
/// strains, the laws' history and energies), so a forged one is a damaged checkpoint, not a
/// blow-up of the restarted run.
class NonFinite : public Prefixed<NonFinite> {
 public:
  template <class T>
  void state(const char* name, const T& value) {
    if constexpr (is_vector<T>::value) {
      if constexpr (is_vector<typename T::value_type>::value) {
        for (std::size_t r = 0; r < value.size(); ++r) state((std::string(name) + "." + std::to_string(r)).c_str(), value[r]);
      } else if constexpr (std::is_same_v<typename T::value_type, double>) {
        for (std::size_t k = 0; k < value.size() && found.empty(); ++k)
          if (!std::isfinite(value[k]))
            found = "record '" + prefix_ + name + "' element " + std::to_string(k) + " is " + number(value[k]) +
                    ", not finite";
      }
    }
  }
  template <class T>
  void rebuilt(const char*, const T&) {}
  std::string found;
};

/// Records whose length changes during a run: not compared with the fresh solver's.
bool variable_length(const std::string& name) { return name == "contacts" || name == "model.failed_rows"; }

/// The frame names `hexdem run` writes: "<case>/<case>_<step, 9+ digits>.vtu", relative to the
/// output folder.
bool frame_file_ok(const std::string& file, const std::string& name) {
  const std::string head = name + "/" + name + "_", tail = ".vtu";
  if (name.empty() || file.size() < head.size() + 9 + tail.size()) return false;
  if (file.compare(0, head.size(), head) != 0 || file.compare(file.size() - tail.size(), tail.size(), tail) != 0)
    return false;
  for (std::size_t k = head.size(); k < file.size() - tail.size(); ++k)
    if (file[k] < '0' || file[k] > '9') return false;
  return true;
}

}  // namespace

Built CheckpointAccess::built(const Solver& s) {
  Built b;
  Shapes shapes;
  visit_solver(s, shapes);
  b.sizes = std::move(shapes.sizes);
  const Model& m = s.model_;
  b.bi = m.bi;
  b.bj = m.bj;
  b.adj_offset = m.adj_offset;
  b.adj_entry = m.adj_entry;
  b.body = m.body;
  b.body_material = m.body_material;
  b.kind = m.kind;
  b.bond_class = m.bond_class;
  b.x0 = m.x0;
  b.y0 = m.y0;
  b.radius = m.radius;
  b.cell_area = m.cell_area;
  b.mass = m.mass;
  b.any_plastic = m.any_plastic;
  b.any_breakable = m.any_breakable;
  b.any_softening = m.any_softening;
  b.any_j2 = m.any_j2;
  b.contacts_on = s.contacts_on_;
  return b;
}

void CheckpointAccess::check_restored(const Solver& s, const Built& b, const RunState& run, const Check& c) {
  const Model& m = s.model_;
  // Lengths first: every check below indexes the arrays.
  Shapes shapes;
  visit_solver(s, shapes);
  for (const auto& [name, size] : b.sizes) {
    if (variable_length(name)) continue;
    const auto it = shapes.sizes.find(name);
    const std::size_t got = it == shapes.sizes.end() ? 0 : it->second;
    if (got != size)
      c.fail("record '" + name + "' has " + std::to_string(got) + " elements, the case's model has " + std::to_string(size));
  }
  for (const auto& [name, size] : shapes.sizes)
    if (b.sizes.count(name) == 0) c.fail("record '" + name + "' is not a record of this case's model");
  for (const auto& [name, got, built] : {std::tuple{"model.any_plastic", m.any_plastic, b.any_plastic},
                                         std::tuple{"model.any_breakable", m.any_breakable, b.any_breakable},
                                         std::tuple{"model.any_softening", m.any_softening, b.any_softening},
                                         std::tuple{"model.any_j2", m.any_j2, b.any_j2},
                                         std::tuple{"contacts_on", s.contacts_on_, b.contacts_on}})
    c.same(name, got, built);

  // Values: every stored vector of doubles finite.
  NonFinite non_finite;
  visit_solver(s, non_finite);
  if (!non_finite.found.empty()) c.fail(non_finite.found);

  // Indices and enumerated values.
  const auto n = static_cast<std::int64_t>(m.num_disks()), nb = static_cast<std::int64_t>(m.num_bonds());
  const auto bodies = static_cast<std::int64_t>(m.body_material.size());
  c.range("model.bi", m.bi, 0, n - 1, "a disk index");
  c.range("model.bj", m.bj, 0, n - 1, "a disk index");
  for (std::int64_t k = 0; k < nb; ++k)
    if (m.bi[k] >= m.bj[k])
      c.fail("record 'model.bj' element " + std::to_string(k) + " is " + std::to_string(m.bj[k]) +
             ", not above the bond's model.bi " + std::to_string(m.bi[k]));
  c.range("model.adj_offset", m.adj_offset, 0, static_cast<std::int64_t>(m.adj_entry.size()), "an adjacency entry");
  if (!m.adj_offset.empty() && (m.adj_offset.front() != 0 || m.adj_offset.back() != static_cast<std::int64_t>(m.adj_entry.size())))
    c.fail("record 'model.adj_offset' runs from " + std::to_string(m.adj_offset.front()) + " to " +
           std::to_string(m.adj_offset.back()) + ", expected 0 to " + std::to_string(m.adj_entry.size()));
  for (std::size_t k = 1; k < m.adj_offset.size(); ++k)
    if (m.adj_offset[k] < m.adj_offset[k - 1])
      c.fail("record 'model.adj_offset' element " + std::to_string(k) + " is " + std::to_string(m.adj_offset[k]) +
             ", below element " + std::to_string(k - 1) + " (" + std::to_string(m.adj_offset[k - 1]) + ")");
  for (std::size_t k = 0; k < m.adj_entry.size(); ++k) {
    const std::int64_t e = m.adj_entry[k], bond = e >= 0 ? e : -1 - e;
    if (bond >= nb)
      c.fail("record 'model.adj_entry' element " + std::to_string(k) + " is " + std::to_string(e) +
             ", not a bond (b or ~b of the " + std::to_string(nb) + " bonds)");
  }
  for (std::size_t i = 0; i + 1 < m.adj_offset.size(); ++i)
    for (std::int64_t k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
      const std::int32_t e = m.adj_entry[static_cast<std::size_t>(k)];
      const std::size_t bond = m.adj_bond(k);
      if (static_cast<std::size_t>(e >= 0 ? m.bi[bond] : m.bj[bond]) != i)
        c.fail("record 'model.adj_entry' element " + std::to_string(k) + " is " + std::to_string(e) + ", a bond of disk " +
               std::to_string(i) + " that does not end there");
    }
  c.range("model.state", m.state, 0, static_cast<std::int64_t>(BondState::BrokenCompression), "a bond state");
  c.range("model.kind", m.kind, 0, static_cast<std::int64_t>(meshing::DiskKind::SemiDisk), "a disk kind");
  c.range("model.body", m.body, 0, bodies - 1, "a body index");
  c.range("model.constraint", m.constraint, 0, kFixX | kFixY | kFixRotation, "constraint bits");
  c.range("model.mirror_plane", m.mirror.plane, 0, 1, "a flag");
  c.range("model.strain_ok", m.strain.ok, 0, 1, "a flag");
  c.range("model.hoop_cut", m.hoop.cut, 0, 1, "a flag");
  // Every double of a row (a member added to FailedBond must be added here: the size checks it).
  static_assert(sizeof(Model::FailedBond) == 11 * sizeof(double) + sizeof(std::int64_t));
  for (std::size_t r = 0; r < m.failed_rows.size(); ++r) {
    const Model::FailedBond& f = m.failed_rows[r];
    const std::string row = "record 'model.failed_rows' row " + std::to_string(r);
    for (const auto& [name, value] : {std::pair{"fracture_energy", f.fracture_energy}, {"break_kinetic", f.break_kinetic},
                                      {"break_time", f.break_time}, {"f_damp", f.f_damp}, {"damping_work", f.damping_work},
                                      {"friction_work", f.friction_work}, {"slip", f.slip}, {"damage", f.damage},
                                      {"kappa", f.kappa}, {"delta0", f.delta0}, {"delta_f", f.delta_f}})
      if (!std::isfinite(value)) c.fail(row + " " + name + " is " + number(value) + ", not finite");
    if (f.crack < Model::kNoCrack || f.crack > Model::kDamageCrack)
      c.fail(row + " crack is " + std::to_string(f.crack) + ", not 0, 1, 2 or 3 (none, tension, shear or damage crack)");
  }
  c.range("model.failed_row", m.failed_row, -1, static_cast<std::int64_t>(m.failed_rows.size()) - 1,
          "a row of model.failed_rows or -1");
  if (m.failed_rows.size() > m.num_bonds())
    c.fail("record 'model.failed_rows' has " + std::to_string(m.failed_rows.size()) + " rows, the model has " +
           std::to_string(m.num_bonds()) + " bonds");
  // An intact bond has a row exactly when it cracks (softening), and then its crack's kind.
  for (std::size_t b = 0; b < m.failed_row.size(); ++b)
    if (m.bond_intact(b) && m.failed_row[b] >= 0 && (!m.any_softening || m.bond_crack(b) == Model::kNoCrack))
      c.fail("record 'model.failed_row' element " + std::to_string(b) + " gives intact bond " + std::to_string(b) +
             " a row that holds no crack");
  if (s.broken_bonds_ > m.num_bonds())
    c.fail("record 'broken_bonds' is " + std::to_string(s.broken_bonds_) + ", the model has " +
           std::to_string(m.num_bonds()) + " bonds");
  for (std::size_t k = 0; k < s.contacts_.size(); ++k) {
    const Solver::Contact& ct = s.contacts_[k];
    if (ct.i < 0 || ct.i >= ct.j || ct.j >= n)
      c.fail("record 'contacts' element " + std::to_string(k) + " joins disks " + std::to_string(ct.i) + " and " +
             std::to_string(ct.j) + ", expected 0 <= i < j < " + std::to_string(n));
    if (k > 0 && std::pair(s.contacts_[k - 1].i, s.contacts_[k - 1].j) >= std::pair(ct.i, ct.j))
      c.fail("record 'contacts' element " + std::to_string(k) + " (disks " + std::to_string(ct.i) + ", " +
             std::to_string(ct.j) + ") is not after the one before it");
    if (!std::isfinite(ct.f_n) || !std::isfinite(ct.f_s) || !std::isfinite(ct.f_v))
      c.fail("record 'contacts' element " + std::to_string(k) + " has a force that is not finite");
  }
  // The constants built with the model: those the case builds.
  c.same("model.bi", m.bi, b.bi);
  c.same("model.bj", m.bj, b.bj);
  c.same("model.adj_offset", m.adj_offset, b.adj_offset);
  c.same("model.adj_entry", m.adj_entry, b.adj_entry);
  c.same("model.kind", m.kind, b.kind);
  c.same("model.body", m.body, b.body);
  c.same("model.body_material", m.body_material, b.body_material);
  c.same("model.x0", m.x0, b.x0);
  c.same("model.y0", m.y0, b.y0);
  c.same("model.radius", m.radius, b.radius);
  c.same("model.cell_area", m.cell_area, b.cell_area);
  c.same("model.mass", m.mass, b.mass);
  c.same("model.bond_class", m.bond_class, b.bond_class);

  // Scalars: the time step, the time and step within the run, the ledgers finite.
  const TimeStepInfo& ts = s.dt_info_;
  const double end = s.case_.time.end;
  if (!(std::isfinite(ts.dt) && ts.dt > 0 && end / ts.dt <= kMaxSteps))
    c.fail("record 'dt_info' holds the time step " + number(ts.dt) + " s, expected a finite step above " +
           number(end / kMaxSteps) + " s");
  for (const auto& [field, v] : {std::pair{"dt_critical", ts.dt_critical}, std::pair{"dt_bloch", ts.dt_bloch},
                                 std::pair{"dt_finite", ts.dt_finite}, std::pair{"dt_eq24", ts.dt_eq24}})
    if (!(v >= 0))  // infinite where nothing bounds it (finite_model_step of 0)
      c.fail(std::string("record 'dt_info' holds ") + field + " = " + number(v) + ", expected >= 0");
  if (ts.finite_iterations < 0)
    c.fail("record 'dt_info' holds finite_iterations = " + std::to_string(ts.finite_iterations) + ", expected >= 0");
  const double dt = ts.dt;
  const double steps = std::ceil(end / dt - 1e-9);
  c.scalar("time", s.time_, 0, steps * dt);
  if (s.step_ < 0 || static_cast<double>(s.step_) > steps)
    c.fail("record 'step' is " + std::to_string(s.step_) + ", outside 0.." + number(steps) + " (the run's steps)");
  if (std::abs(static_cast<double>(s.step_) * dt - s.time_) > 1e-9 * std::max(s.time_, dt))
    c.fail("record 'time' is " + number(s.time_) + " s, but step " + std::to_string(s.step_) + " at dt = " + number(dt) +
           " s is t = " + number(static_cast<double>(s.step_) * dt) + " s");
  c.scalar("model.time", m.time, 0, s.time_);
  c.scalar("last_checked_time", s.last_checked_time_, 0, s.time_);
  for (const auto& [name, e] : {std::pair{std::string("energy"), &s.energy_}, std::pair{std::string("last_checked"), &s.last_checked_}})
    for (const auto& [field, v] :
         {std::pair{"kinetic", e->kinetic}, std::pair{"elastic", e->elastic}, std::pair{"external_work", e->external_work},
          std::pair{"damping", e->damping}, std::pair{"plastic", e->plastic}, std::pair{"fracture", e->fracture},
          std::pair{"contact_damping", e->contact_damping}, std::pair{"friction", e->friction},
          std::pair{"break_kinetic", e->break_kinetic}, std::pair{"initial", e->initial}, std::pair{"scale", e->scale}})
      c.finite(name + "." + field, v);
  for (const auto& [name, v] :
       {std::pair{"max_energy_error", s.max_energy_error_}, std::pair{"p_max", s.p_max_},
        std::pair{"ext_b_before", s.ext_b_before_}, std::pair{"damp_b_before", s.damp_b_before_},
        std::pair{"ext_a", s.ext_a_}, std::pair{"damp_a", s.damp_a_}, std::pair{"initial_energy", s.initial_energy_},
        std::pair{"contact_damping_work", s.contact_damping_work_},
        std::pair{"contact_friction_work", s.contact_friction_work_}, std::pair{"model.thickness", m.thickness}})
    c.finite(name, v);

  // The run loop's state: output times finite and not negative, frames in time order and
  // named as `hexdem run` names them, inside the output folder.
  for (const auto& [name, v] : {std::pair{"run.next_frame", run.next_frame}, std::pair{"run.next_probe", run.next_probe},
                                std::pair{"run.next_checkpoint", run.next_checkpoint}, std::pair{"run.max_error", run.max_error}})
    c.scalar(name, v, 0, std::numeric_limits<double>::max());
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    const double t = run.frames[k].time;
    const double before = k > 0 ? run.frames[k - 1].time : 0.0;
    if (!std::isfinite(t) || t < before || t > steps * dt)
      c.fail("record 'run.frame_times' element " + std::to_string(k) + " is " + number(t) + ", expected a time in [" +
             number(before) + ", " + number(steps * dt) + "] s");
    if (!frame_file_ok(run.frames[k].file, s.case_.name))
      c.fail("record 'run.frame_files' line " + std::to_string(k + 1) + " is '" + run.frames[k].file + "', not a frame '" +
             s.case_.name + "/" + s.case_.name + "_<step>.vtu' of the output folder");
  }
}

namespace {

// ---- coverage -----------------------------------------------------------------------

class Coverage {
 public:
  Coverage(const void* base, std::size_t size, std::size_t align, std::string what)
      : base_(static_cast<const char*>(base)), size_(size), align_(align), what_(std::move(what)) {}

  template <class T>
  void state(const char* name, const T& member) { add(name, member); }
  template <class T>
  void rebuilt(const char* name, const T& member) { add(name, member); }
  template <class M>
  void model(const char* name, const M& member) { add(name, member); }

  void gaps(std::vector<std::string>& out) {
    std::sort(entries_.begin(), entries_.end(),
              [](const Entry& a, const Entry& b) { return a.offset < b.offset; });
    std::size_t end = 0;
    std::string after = "(start)";
    auto align_up = [](std::size_t x, std::size_t a) { return (x + a - 1) / a * a; };
    for (const Entry& e : entries_) {
      if (e.offset < end) {
        out.push_back(what_ + ": '" + e.name + "' listed twice or overlapping '" + after + "'");
      } else if (e.offset != align_up(end, e.align)) {
        out.push_back(what_ + ": " + std::to_string(e.offset - end) + " bytes at offset " + std::to_string(end) +
                      " after '" + after + "' are not in the checkpoint's member list");
      }
      end = std::max(end, e.offset + e.size);
      after = e.name;
    }
    if (align_up(end, align_) != size_)
      out.push_back(what_ + ": " + std::to_string(size_ - end) + " bytes at offset " + std::to_string(end) +
                    " after '" + after + "' are not in the checkpoint's member list");
  }

 private:
  struct Entry {
    std::string name;
    std::size_t offset, size, align;
  };
  template <class T>
  void add(const char* name, const T& member) {
    const auto offset = static_cast<std::size_t>(reinterpret_cast<const char*>(&member) - base_);
    entries_.push_back({name, offset, sizeof(T), alignof(T)});
  }
  const char* base_;
  std::size_t size_, align_;
  std::string what_;
  std::vector<Entry> entries_;
};

std::string error_text() { return std::strerror(errno); }

void write_all(int fd, const std::string& data, const std::string& path) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t k = ::write(fd, data.data() + done, data.size() - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      throw InputError(path + ": cannot write checkpoint (" + error_text() + ")");
    }
    done += static_cast<std::size_t>(k);
  }
}

}  // namespace

std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < size; ++k) {
    h ^= p[k];
    h *= 1099511628211ull;
  }
  return h;
}

std::uint64_t hash_words(const void* data, std::size_t size, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t k = 0;
  for (; k + 8 <= size; k += 8) {
    std::uint64_t w = 0;
    std::memcpy(&w, p + k, 8);
    h = (h ^ w) * 0x9e3779b97f4a7c15ull;
    h ^= h >> 32;
  }
  return fnv1a(p + k, size - k, h);  // the last size mod 8 bytes
}

std::uint64_t case_hash(const Case& c) {
  if (!c.effective_toml.empty()) return fnv1a(c.effective_toml.data(), c.effective_toml.size());
  const std::string id = c.name + '\n' + c.source;
  return fnv1a(id.data(), id.size());
}

std::uint64_t lattice_hash(const meshing::Lattice& l) {
  std::uint64_t h = hash_words(nullptr, 0);
  auto add = [&h](const auto& v) { h = hash_words(v.data(), v.size() * sizeof(v[0]), h); };
  add(l.x);
  add(l.y);
  add(l.radius);
  add(l.body);
  add(l.material);
  add(l.bond_i);
  add(l.bond_j);
  add(l.cell_area);
  // The boundary sets: names and members (an outline whose set names were swapped meshes to
  // the same disks, but the run's conditions and the frames' set arrays follow the sets).
  for (const std::string& name : l.set_names) h = hash_words(name.data(), name.size() + 1, h);  // with its NUL: no run-on
  add(l.set_offset);
  add(l.set_disk);
  return h;
}

void write_checkpoint(const std::string& path, const Solver& s, const RunState& run) {
  Writer w;
  CheckpointAccess::visit_solver(s, w);
  save_run(w, run);
  std::string out(kMagic, sizeof kMagic);
  auto put = [&out](auto v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(kCheckpointVersion);
  put(case_hash(s.case_data()));
  put(s.lattice_hash());
  put(static_cast<std::uint64_t>(w.names_.size()));
  out += w.buf_;
  put(hash_words(out.data(), out.size()));

  // Temporary file, fsync, rename, fsync of the folder: the old checkpoint stays valid
  // until the new one is complete on disk.
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(tmp + ": cannot write checkpoint (" + error_text() + ")");
  try {
    write_all(fd, out, tmp);
    if (::fsync(fd) != 0) throw std::runtime_error(tmp + ": cannot sync checkpoint (" + error_text() + ")");
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    ::unlink(tmp.c_str());
    throw InputError(tmp + ": cannot write checkpoint (" + error_text() + ")");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = error_text();
    ::unlink(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the new checkpoint into place (" + why + ")");
  }
  std::string dir = fs::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void read_checkpoint(const std::string& path, Solver& s, RunState& run) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open checkpoint");
  std::ostringstream content;
  content << in.rdbuf();
  const std::string data = content.str();
  constexpr std::size_t header = sizeof kMagic + 4 + 8 + 8 + 8;
  if (data.size() < sizeof kMagic || std::memcmp(data.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(path + ": not a hexdem checkpoint (no HEXDEMCK header)");
  std::uint32_t version = 0;
  if (data.size() >= sizeof kMagic + 4) std::memcpy(&version, data.data() + sizeof kMagic, 4);
  if (data.size() >= sizeof kMagic + 4 && version != kCheckpointVersion)
    throw InputError(path + ": checkpoint format version " + std::to_string(version) + ", this hexdem reads version " +
                     std::to_string(kCheckpointVersion));
  if (data.size() < header + 8) throw InputError(path + ": truncated checkpoint (" + std::to_string(data.size()) + " bytes)");
  std::uint64_t checksum = 0;
  std::memcpy(&checksum, data.data() + data.size() - 8, 8);
  if (hash_words(data.data(), data.size() - 8) != checksum)
    throw InputError(path + ": damaged or truncated checkpoint (checksum mismatch)");
  std::uint64_t chash = 0, lhash = 0, count = 0;
  std::memcpy(&chash, data.data() + sizeof kMagic + 4, 8);
  std::memcpy(&lhash, data.data() + sizeof kMagic + 12, 8);
  std::memcpy(&count, data.data() + sizeof kMagic + 20, 8);
  if (chash != case_hash(s.case_data()))
    throw InputError(path + ": checkpoint of another case (the effective case differs from " + s.case_data().source +
                     " with these --set values; restart with the case and overrides it was written with)");
  if (lhash != s.lattice_hash())
    throw InputError(path + ": checkpoint of another lattice or other boundary sets than " + s.case_data().source + " meshes to");

  std::map<std::string, Record> records;
  std::size_t at = header;
  const std::size_t end = data.size() - 8;
  auto take = [&](std::size_t n) {
    if (n > end - at) throw InputError(path + ": damaged checkpoint: record runs past the end of the file");
    const char* p = data.data() + at;
    at += n;
    return p;
  };
  for (std::uint64_t k = 0; k < count; ++k) {
    std::uint32_t len = 0, elem = 0;
    std::uint64_t n = 0;
    std::memcpy(&len, take(4), 4);
    const std::string name(take(len), len);
    std::memcpy(&elem, take(4), 4);
    std::memcpy(&n, take(8), 8);
    if (elem == 0 || n > (end - at) / elem)
      throw InputError(path + ": damaged checkpoint: record '" + name + "' runs past the end of the file");
    if (!records.emplace(name, Record{elem, static_cast<std::size_t>(n), take(static_cast<std::size_t>(elem * n))}).second)
      throw InputError(path + ": damaged checkpoint: record '" + name + "' appears twice");
  }
  if (at != end) throw InputError(path + ": damaged checkpoint: " + std::to_string(end - at) + " bytes after the last record");

  const Built built = CheckpointAccess::built(s);
  Reader r(path, std::move(records));
  CheckpointAccess::visit_solver(s, r);
  load_run(r, run);
  CheckpointAccess::check_restored(s, built, run, Check(path));
  // Every per-disk and per-bond vector must match the lattice the case meshes to.
  const Model& m = s.model();
  if (m.ux.size() != m.num_disks() || m.f_s.size() != m.num_bonds() || m.x0.size() != s.model().num_disks())
    r.fail("disk or bond counts differ from the lattice");
  CheckpointAccess::rebuild_broad_phase(s, path);
}

namespace {

/// Heap bytes of each member the lists name: a vector's capacity (and its rows'), and the
/// broad phase's own count.
class Census : public Prefixed<Census> {
 public:
  template <class T>
  void state(const char* name, const T& member) { add(name, member); }
  template <class T>
  void rebuilt(const char* name, const T& member) { add(name, member); }
  std::vector<std::pair<std::string, std::size_t>> entries;

 private:
  template <class T>
  static std::size_t heap(const T& value) {
    if constexpr (is_vector<T>::value) {
      std::size_t bytes = value.capacity() * sizeof(typename T::value_type);
      if constexpr (is_vector<typename T::value_type>::value)
        for (const auto& row : value) bytes += heap(row);
      return bytes;
    } else if constexpr (requires { value.memory_bytes(); }) {
      return value.memory_bytes();
    } else {
      return 0;
    }
  }
  template <class T>
  void add(const char* name, const T& member) {
    const std::size_t bytes = heap(member);
    if (bytes > 0) entries.emplace_back(prefix_ + name, bytes);
  }
};

}  // namespace

std::vector<std::pair<std::string, std::size_t>> memory_census(const Solver& s) {
  Census c;
  CheckpointAccess::visit_solver(s, c);
  std::sort(c.entries.begin(), c.entries.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first < b.first;
  });
  return c.entries;
}

std::vector<std::string> checkpoint_coverage_gaps(const Solver& s) {
  std::vector<std::string> out;
  Coverage solver(&s, sizeof(Solver), alignof(Solver), "Solver");
  CheckpointAccess::visit_solver(s, solver);
  solver.gaps(out);
  Coverage model(&s.model(), sizeof(Model), alignof(Model), "Model");
  visit_model(s.model(), model);
  model.gaps(out);
  return out;
}

std::vector<std::string> checkpoint_record_names(const Solver& s) {
  Writer w;
  CheckpointAccess::visit_solver(s, w);
  save_run(w, RunState{});
  return w.names_;
}

}  // namespace hexdem::solver
