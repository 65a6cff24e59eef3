// Force kernels of the bonded lattice.
// Ref: Liu, Gao, Tanimura (2004), Eqs. 1-4 (bond kinematics and forces), Eq. 15
// (axisymmetric scaling) and Eq. 16 (spring plasticity); physics.md sections 2, 4
// (local-strain shear model) and 10 (hoop); docs/model.md for the disk-level J2 plasticity.
//
// All passes are gathers over a fixed adjacency order or independent per-bond updates, so the
// forces are bit-identical whatever the number of OpenMP threads.
#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <cstring>
#include <limits>

#include "hexdem/solver/model.hpp"

#include "hexdem/error.hpp"

#include "hexdem/laws/bilinear_kinematic.hpp"
#include "hexdem/laws/contact.hpp"
#include "hexdem/laws/softening.hpp"

namespace hexdem::solver {
namespace {

/// Two doubles in one SSE register: a packed division is correctly rounded in each lane, as
/// two scalar divisions are (the same bits), and costs the divider one operation.
using Pair = double __attribute__((vector_size(16)));

/// What a loop over a disk's bonds reads of the lattice, as raw pointers taken once per pass:
/// Model::adj_bond, adj_other, bond_in_fit and the reference centres, without reloading the
/// vectors' addresses for every bond (the compiler did, through the loops' other loads).
struct AdjacencyView {
  const std::int32_t* __restrict entry;
  const std::int32_t* __restrict bond_i;
  const std::int32_t* __restrict bond_j;
  const std::uint8_t* __restrict state;
  const std::int32_t* __restrict row;       ///< Model::failed_row; null without softening
  const Model::FailedBond* rows;            ///< Model::failed_rows (a smeared-damage crack stays in the fit)
  const std::uint8_t* __restrict ok;        ///< LocalStrain::ok
  const double* __restrict x0;
  const double* __restrict y0;
  explicit AdjacencyView(const Model& m)
      : entry(m.adj_entry.data()), bond_i(m.bi.data()), bond_j(m.bj.data()), state(m.state.data()),
        row(m.any_softening ? m.failed_row.data() : nullptr), rows(m.failed_rows.data()), ok(m.strain.ok.data()),
        x0(m.x0.data()),
        y0(m.y0.data()) {}
  /// Model::adj_bond: the bond of adjacency entry k.
  [[nodiscard]] std::size_t bond(std::int64_t k) const {
    const std::int32_t e = entry[k];
    return static_cast<std::size_t>(e >= 0 ? e : ~e);
  }
  /// Model::adj_other: the other disk of bond b at disk i.
  [[nodiscard]] std::size_t other(std::size_t b, std::size_t i) const {
    return static_cast<std::size_t>(bond_i[b] ^ bond_j[b]) ^ i;
  }
  /// Model::bond_in_fit.
  [[nodiscard]] bool in_fit(std::size_t b) const {
    return state[b] <= 1 && (row == nullptr || row[b] < 0 || rows[row[b]].crack == Model::kDamageCrack);
  }
};

/// The local-strain model's shear measure of a bond, u_s = (d/2) s0.(eps_i + eps_j).n0 =
/// g : (eps_i + eps_j) (physics.md section 4), read through raw pointers taken once per pass:
/// the one expression of local_shear and of the elastic bond pass.
struct LocalShearView {
  const std::uint8_t* __restrict ok;  ///< LocalStrain::ok: the disk has a strain fit
  const double* __restrict exx;
  const double* __restrict eyy;
  const double* __restrict exy;
  const std::uint8_t* __restrict kind;  ///< Model::spring_kind where g is per kind, else null
  const double* __restrict g_xx;        ///< Model::g_xx or kind_g_xx
  const double* __restrict g_yy;
  const double* __restrict g_xy;
  explicit LocalShearView(const Model& m)
      : ok(m.strain.ok.data()), exx(m.strain.eps_xx.data()), eyy(m.strain.eps_yy.data()), exy(m.strain.eps_xy.data()),
        kind(m.kind_g_xx.empty() ? nullptr : m.spring_kind.data()),
        g_xx(kind ? m.kind_g_xx.data() : m.g_xx.data()), g_yy(kind ? m.kind_g_yy.data() : m.g_yy.data()),
        g_xy(kind ? m.kind_g_xy.data() : m.g_xy.data()) {}
  /// Where bond b's g is: its kind or b.
  [[nodiscard]] std::size_t g_index(std::size_t b) const { return kind ? kind[b] : b; }
  /// u_s [m] of bond b between disks i and j; a lone disk's bond has the normal spring only.
  [[nodiscard]] double operator()(std::size_t b, std::size_t i, std::size_t j) const {
    if (!ok[i] || !ok[j]) return 0.0;
    const std::size_t g = g_index(b);
    return g_xx[g] * (exx[i] + exx[j]) + g_yy[g] * (eyy[i] + eyy[j]) + 2.0 * g_xy[g] * (exy[i] + exy[j]);
  }
};

/// Least-squares symmetric gradient of the field (fx, fy) at disk i over its intact bonds,
/// sym((sum_k (f_k - f_i) a_k^T) (sum_k a_k a_k^T)^-1), with the disk's current fit (M^-1):
/// the strain from the displacements, or its rate from the velocities.
std::array<double, 3> fit_gradient(const Model& m, std::size_t i, const std::vector<double>& fx,
                                   const std::vector<double>& fy) {
  // Disk i's own values read once (the compiler reloaded them per bond).
  const AdjacencyView a(m);
  const double* __restrict f_x = fx.data();
  const double* __restrict f_y = fy.data();
  const double x_i = a.x0[i], y_i = a.y0[i], fx_i = f_x[i], fy_i = f_y[i];
  double gxx = 0, gxy = 0, gyx = 0, gyy = 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
    const std::size_t b = a.bond(k), o = a.other(b, i);
    if (!a.in_fit(b) || !a.ok[o]) continue;  // in the fit, and a neighbour with a fit
    const double ax = a.x0[o] - x_i, ay = a.y0[o] - y_i;  // Model::adj_ax
    const double dux = f_x[o] - fx_i, duy = f_y[o] - fy_i;
    gxx += dux * ax;
    gxy += dux * ay;
    gyx += duy * ax;
    gyy += duy * ay;
  }
  const double mxx = m.strain.minv_xx[i], mxy = m.strain.minv_xy[i], myy = m.strain.minv_yy[i];
  // On a mirror plane the field is mirror-symmetric: no shear.
  return {gxx * mxx + gxy * mxy, gyx * mxy + gyy * myy,
          m.on_mirror(i) ? 0.0 : 0.5 * ((gxx * mxy + gxy * myy) + (gyx * mxx + gyy * mxy))};
}

/// Hoop strain u_r / b of disk i (axisymmetric; 0 in plane geometries).
inline double hoop_strain(const Model& m, std::size_t i) {
  return m.geometry == Geometry::Axisymmetric ? m.ux[i] / m.disk_weight(i) : 0.0;
}

/// The largest of softening_bond's continuum criteria (Rankine, crushing, Mohr-Coulomb) at the
/// stress of the strain (exx, eyy, exy, ett) under the constants lambda2, lambda3, mu of
/// SofteningParams, relative to the thresholds 1 / inv_ft, 1 / inv_fc, 1 / inv_mc [-]: an
/// upper bound of each (the in-plane principal values bracketed by one square root, wider than
/// its rounding; an upper bound is as good a bound as the criterion itself). `out_of_plane` is
/// 0 in plane stress (no s3), else 1. Not finite where the strain is not (the callers decide).
/// The one expression of the nonlocal bound and of the local one (classify_local_criterion).
inline double relative_criterion(double lambda2, double lambda3, double mu, double sin_phi, double inv_ft,
                                 double inv_fc, double inv_mc, double exx, double eyy, double exy, double ett,
                                 double out_of_plane) {
  const double tr = exx + eyy;
  const double iso = lambda2 * tr + lambda3 * ett;
  const double sxx = iso + 2 * mu * exx, syy = iso + 2 * mu * eyy, sxy = 2 * mu * exy;
  const double s3 = out_of_plane * (lambda3 * (tr + ett) + 2 * mu * ett);
  const double c = 0.5 * (sxx + syy), d = 0.5 * (sxx - syy);
  const double r = std::sqrt(d * d + sxy * sxy) * (1 + 1e-12);
  const double s1 = c + r, s2 = c - r;
  const double s_max = std::max(s1, s3), s_min = std::min(s2, s3);
  const double shear = 0.5 * (s_max - s_min) + 0.5 * (s_max + s_min) * sin_phi;
  return std::max(std::max(s1 * inv_ft, -s_min * inv_fc), shear * inv_mc);
}

/// Pass A: least-squares strain of each disk over its intact bonds,
/// grad u_i = (sum_k (u_k - u_i) a_k^T) (sum_k a_k a_k^T)^-1, eps = sym(grad u).
void disk_strain(Model& m, std::size_t i) {
  if (!m.strain.eps_tt.empty()) m.strain.eps_tt[i] = hoop_strain(m, i);  // axisymmetric models only
  const std::array<double, 3> e = fit_gradient(m, i, m.ux, m.uy);
  m.strain.eps_xx[i] = e[0];
  m.strain.eps_yy[i] = e[1];
  m.strain.eps_xy[i] = e[2];
  if (!m.strain.eps_off_xx.empty()) {
    // Strain carried across changes of the fit (settle_broken_bonds): an affine offset.
    m.strain.eps_xx[i] -= m.strain.eps_off_xx[i];
    m.strain.eps_yy[i] -= m.strain.eps_off_yy[i];
    if (!m.on_mirror(i)) m.strain.eps_xy[i] -= m.strain.eps_off_xy[i];
  }
}

/// Model::local_criterion's class of every disk from its strain of this pass: 0 without a full
/// neighbourhood (softening_bond's "full"), 1 where relative_criterion stays below 1 - margin
/// of its body's thresholds and the stress's terms before they cancel are small enough that
/// their rounding (1e-15 of them) stays far below the margin, else 2 (also where not finite). A pass of its own, branch-free over the strain arrays (inside the strain fit's loop,
/// once per disk after the fit's dependent chain, it cost as much as the fit itself; g++ does
/// not vectorise it: the body's constants are a gather).
template <bool Axisym>
void classify_local_criterion(Model& m) {
  const LocalCriterion& lc = m.local_criterion;
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  const double* __restrict exx = m.strain.eps_xx.data();
  const double* __restrict eyy = m.strain.eps_yy.data();
  const double* __restrict exy = m.strain.eps_xy.data();
  const double* __restrict ett = Axisym ? m.strain.eps_tt.data() : nullptr;
  const double out_of_plane = m.geometry == Geometry::PlaneStress ? 0.0 : 1.0;  // s3's factor
  const std::uint8_t* __restrict ok = m.strain.ok.data();
  const std::int32_t* __restrict offset = m.adj_offset.data();
  const std::int32_t* __restrict body = m.body.data();
  const LocalCriterion::Body* __restrict bp = lc.body.data();
  std::uint8_t* __restrict out = m.local_criterion.disk.data();
  m.balance.classify.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      const LocalCriterion::Body& p = bp[body[i]];
      double e_tt = 0.0;
      if constexpr (Axisym) e_tt = ett[i];
      const double e_xx = exx[i], e_yy = eyy[i], e_xy = exy[i];
      const double g = relative_criterion(p.lambda2, p.lambda3, p.mu, p.sin_phi, p.inv_ft, p.inv_fc, p.inv_mc, e_xx,
                                          e_yy, e_xy, e_tt, out_of_plane);
      const double terms = p.moduli * (std::abs(e_xx) + std::abs(e_yy) + 2 * std::abs(e_xy) + std::abs(e_tt));
      const int far = (g < p.far_below) & (terms * p.inv_max < 1e6);  // NaN: not far
      const int full = (ok[i] != 0) & (offset[i + 1] - offset[i] == 6);
      out[i] = static_cast<std::uint8_t>(full * (2 - far));
    }
  });
}

void compute_disk_strains(Model& m) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  m.balance.strains.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) disk_strain(m, static_cast<std::size_t>(i));
  });
  if (!m.local_criterion.disk.empty()) {
    if (m.geometry == Geometry::Axisymmetric) {
      classify_local_criterion<true>(m);
    } else {
      classify_local_criterion<false>(m);
    }
  }
}

/// u_s = (d/2) s0.(eps_i + eps_j).n0 = g : (eps_i + eps_j) of bond b (local-strain model).
inline double local_shear(const Model& m, std::size_t b) {
  return LocalShearView(m)(b, static_cast<std::size_t>(m.bi[b]), static_cast<std::size_t>(m.bj[b]));
}

/// The nonlocal strains (Model::nonlocal), where a criterion can be near: first each averaged
/// disk's largest criterion relative to its body's smallest thresholds, the cells' maxima and
/// the hot cells (NonlocalStrain::hot), then each disk's weighted mean of its neighbours'
/// strains where a hot cell is in its block.
void compute_nonlocal_strains(Model& m) {
  NonlocalStrain& nl = m.nonlocal;
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  const bool axisym = m.geometry == Geometry::Axisymmetric, plane_stress = m.geometry == Geometry::PlaneStress;
  constexpr double kAlways = std::numeric_limits<double>::infinity();
  m.balance.nonlocal_strains.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      const auto iu = static_cast<std::size_t>(i);
      double g = 0;  // not in any average
      if (nl.offset[iu + 1] > nl.offset[iu] && m.strain.ok[iu] && m.initial_bonds(iu) == 6) {
        const auto body = static_cast<std::size_t>(m.body[iu]);
        const std::int32_t l = m.body_failure_law[body];
        if (nl.body_inv_ft[body] > 0 && l >= 0) {
          // The criteria of softening_bond at the disk's own strain (convex in the stress).
          const SofteningParams& sp = m.softening[static_cast<std::size_t>(l)];
          g = relative_criterion(sp.lambda2, sp.lambda3, sp.mu, sp.mc.sin_phi, nl.body_inv_ft[body], nl.body_inv_fc[body],
                                 nl.body_inv_mc[body], m.strain.eps_xx[iu], m.strain.eps_yy[iu], m.strain.eps_xy[iu],
                                 axisym ? hoop_strain(m, iu) : 0.0, plane_stress ? 0.0 : 1.0);
          if (!(g == g)) g = kAlways;  // NaN: let the exact test see it
        } else {
          g = kAlways;  // no bound for this body: always checked
        }
      }
      nl.relative[iu] = g;
      // The strain packed per disk for the averages' gather (one cache line per row entry).
      double* e = nl.packed.data() + 4 * iu;
      e[0] = m.strain.eps_xx[iu];
      e[1] = m.strain.eps_yy[iu];
      e[2] = m.strain.eps_xy[iu];
      e[3] = axisym ? m.strain.eps_tt[iu] : 0.0;  // once per disk, not per row entry
    }
  });
  std::fill(nl.cell_max.begin(), nl.cell_max.end(), 0.0);
  for (std::ptrdiff_t i = 0; i < n; ++i) {  // maxima: the same in any order
    double& c = nl.cell_max[static_cast<std::size_t>(nl.cell[static_cast<std::size_t>(i)])];
    c = std::max(c, nl.relative[static_cast<std::size_t>(i)]);
  }
  // Hot: the 3 x 3 block reaches 1 (less a margin far above the rounding of the averages).
  const std::int64_t cx = nl.cells_x, cy = nl.cells_y;
  const auto block = [&](std::int64_t x, std::int64_t y, auto&& visit) {
    for (std::int64_t v = std::max<std::int64_t>(y - 1, 0); v <= std::min(y + 1, cy - 1); ++v)
      for (std::int64_t u = std::max<std::int64_t>(x - 1, 0); u <= std::min(x + 1, cx - 1); ++u)
        visit(static_cast<std::size_t>(v * cx + u));
  };
  for (std::int64_t y = 0; y < cy; ++y)
    for (std::int64_t x = 0; x < cx; ++x) {
      double g = 0;
      block(x, y, [&](std::size_t c) { g = std::max(g, nl.cell_max[c]); });
      nl.hot[static_cast<std::size_t>(y * cx + x)] = (g >= 1 - 1e-6 || !nl.skip_far) ? 1 : 0;
    }
  for (std::int64_t y = 0; y < cy; ++y)
    for (std::int64_t x = 0; x < cx; ++x) {
      bool near = false;
      block(x, y, [&](std::size_t c) { near = near || (nl.hot[c] & 1) != 0; });
      if (near) nl.hot[static_cast<std::size_t>(y * cx + x)] |= 2;
    }
  m.balance.nonlocal_check.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      const auto iu = static_cast<std::size_t>(i);
      if ((nl.hot[static_cast<std::size_t>(nl.cell[iu])] & 2) == 0) continue;  // no bond of it is checked
      double exx = 0, eyy = 0, exy = 0, ett = 0;
      for (std::uint32_t k = nl.offset[iu]; k < nl.offset[iu + 1]; ++k) {
        const double* e = nl.packed.data() + 4 * static_cast<std::size_t>(nl.nbr[k]);
        const double w = nl.w[k];
        exx += w * e[0];
        eyy += w * e[1];
        exy += w * e[2];
        if (axisym) ett += w * e[3];
      }
      nl.eps_xx[iu] = exx;
      nl.eps_yy[iu] = eyy;
      nl.eps_xy[iu] = exy;
      if (axisym) nl.eps_tt[iu] = ett;
    }
  });
}

/// Axisymmetric hoop term of disk i: A b [(lambda + 2 mu) eps_tt^2 / 2 + lambda eps_tt
/// (eps_rr + eps_zz)] [J] (physics.md section 10).
/// With hoop cracking (damage D_h of a softening material's ring) the term is multiplied by
/// 1 - D_h while the ring is stretched (eps_tt > 0). A disk that has lost a neighbour
/// (hoop.cut) keeps only A b s^2 / (2M), s = M eps_tt + lambda tr the hoop stress,
/// M = lambda + 2 mu, tr = eps_rr + eps_zz, less the constant that kept its energy continuous
/// then (settle_broken_bonds; docs/model.md, "Energy at a break").
double hoop_energy(const Model& m, std::size_t i) {
  const double eps_tt = hoop_strain(m, i);
  const double lam = m.hoop.lambda[i], mu = m.hoop.mu[i];
  const double tr = m.strain.eps_xx[i] + m.strain.eps_yy[i];
  if (!m.hoop.cut.empty() && m.hoop.cut[i]) {
    // A disk that has lost a neighbour: the hoop stress's square only (see hoop_stress).
    const double M = lam + 2 * mu, s = M * eps_tt + lam * tr;
    const double g = !m.hoop_cracks.damage.empty() && s > 0 ? 1 - m.hoop_cracks.damage[i] : 1.0;
    return m.cell_area[i] * m.disk_weight(i) * g * s * s / (2 * M) - m.hoop.constant[i];
  }
  const double g = !m.hoop_cracks.damage.empty() && eps_tt > 0 ? 1 - m.hoop_cracks.damage[i] : 1.0;
  return g * m.cell_area[i] * m.disk_weight(i) * ((lam + 2 * mu) * 0.5 * eps_tt * eps_tt + lam * eps_tt * tr);
}

/// Hoop stress sigma_tt of disk i [Pa] (without a J2 disk's plastic part) and the hoop term's
/// stress on the in-plane strains, dE_h/d(tr) / (A b) [Pa]: lambda eps_tt undamaged.
struct HoopStress {
  double tt = 0, in_plane = 0;
};
inline HoopStress hoop_stress(const Model& m, std::size_t i, double eps_tt) {
  const double lam = m.hoop.lambda[i], M = lam + 2 * m.hoop.mu[i];
  const double tr = m.strain.eps_xx[i] + m.strain.eps_yy[i];
  const double s = M * eps_tt + lam * tr;
  if (!m.hoop.cut.empty() && m.hoop.cut[i]) {
    const double g = !m.hoop_cracks.damage.empty() && s > 0 ? 1 - m.hoop_cracks.damage[i] : 1.0;
    return {g * s, g * s * lam / M};
  }
  const double g = !m.hoop_cracks.damage.empty() && eps_tt > 0 ? 1 - m.hoop_cracks.damage[i] : 1.0;
  return {g * s, g * lam * eps_tt};
}
inline HoopStress hoop_stress(const Model& m, std::size_t i) { return hoop_stress(m, i, hoop_strain(m, i)); }

/// Hoop cracking of the rings of softening materials (axisymmetric): Rankine on the hoop
/// stress s starts it, then the hoop stress softens linearly in e = s / M down to zero at
/// e_f = 2 G_F / (h f_t), with the crack band h = 2 pi b / n of n radial cracks (a radial
/// crack is a meridian half-plane: it cuts every ring once, so n is a property of the body,
/// not of the lattice). Damage grows only while the hoop term is positive; each step books
/// dD (E_h - A b s de / 2), the drop of the term less the half step of the force drop, as
/// fracture energy (its negative part, where s changed sign within the step, as
/// hoop_break_kinetic).
void update_hoop_damage(Model& m) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  m.balance.hoop.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto ii = static_cast<std::ptrdiff_t>(part_lo); ii < static_cast<std::ptrdiff_t>(part_hi); ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      const SofteningParams& sp = m.softening[static_cast<std::size_t>(m.body[i])];
      if (!(sp.G_F > 0) || !m.strain.ok[i] || m.hoop_cracks.damage[i] >= 1.0) continue;
      const double lam = m.hoop.lambda[i], M = lam + 2 * m.hoop.mu[i];
      const double s = M * m.strain.eps_tt[i] + lam * (m.strain.eps_xx[i] + m.strain.eps_yy[i]);
      const double e = s / M;
      const double e_last = m.hoop_cracks.e_last[i];
      m.hoop_cracks.e_last[i] = e;
      if (m.hoop_cracks.ef[i] == 0) {
        const double f_t = m.failure_laws[static_cast<std::size_t>(m.body[i])].f_t *
                           (m.disk_strength_scale.empty() ? 1.0 : m.disk_strength_scale[i]);
        if (!(s > f_t)) continue;
        const double h = 2 * 3.14159265358979323846 * m.disk_weight(i) / sp.radial_cracks;
        m.hoop_cracks.e0[i] = e;
        m.hoop_cracks.ef[i] = std::max(2 * sp.G_F / (h * f_t), e);
        m.hoop_cracks.kappa[i] = e;
      }
      if (e > m.hoop_cracks.kappa[i]) {
        const double d = laws::LinearSoftening::damage(e, m.hoop_cracks.e0[i], m.hoop_cracks.ef[i]);
        // The hoop term E_h = A b [M eps_tt^2 / 2 + lambda eps_tt tr] is multiplied by 1 - D_h
        // while eps_tt > 0; damage grows only while E_h > 0 (a step then releases
        // dD (E_h - half step of the force drop), the half step taken as for the bonds).
        const double eps_tt = m.strain.eps_tt[i], tr = m.strain.eps_xx[i] + m.strain.eps_yy[i];
        const bool cut = !m.hoop.cut.empty() && m.hoop.cut[i];
        const double eh = cut ? m.cell_area[i] * m.disk_weight(i) * s * s / (2 * M)
                              : m.cell_area[i] * m.disk_weight(i) * eps_tt * (0.5 * M * eps_tt + lam * tr);
        if (d > m.hoop_cracks.damage[i] && (cut || eps_tt > 0) && eh > 0) {
          // The half step, A b (s d(eps_tt) + lambda eps_tt d(tr)) / 2, is taken as A b s d(s/M) / 2
          // with the driver of the last step (the hoop share of the in-plane force is small).
          const double half = 0.5 * m.cell_area[i] * m.disk_weight(i) * s * (e - e_last);
          const double released = (d - m.hoop_cracks.damage[i]) * (eh - half);
          m.hoop_cracks.fracture[i] += std::max(released, 0.0);
          m.hoop_cracks.break_kinetic[i] += std::min(released, 0.0);
          m.hoop_cracks.damage[i] = d;
          m.hoop_cracks.kappa[i] = e;
        }
      }
    }
  });
}

/// Plastic correction of J2 disk i [J]: V [psi(eps - eps_p) - psi(eps)] = V mu (eps_p:eps_p -
/// 2 eps:eps_p) with psi the isotropic 3D strain energy, eps the disk's local strain with the
/// out-of-plane component (hoop strain, or 0 in plane strain) and tr(eps_p) = 0. Added to the
/// elastic lattice, it makes the energy of a homogeneous field V psi(eps - eps_p).
double j2_correction_energy(const Model& m, std::size_t i) {
  const double pxx = m.j2.eps_p_xx[i], pyy = m.j2.eps_p_yy[i], pxy = m.j2.eps_p_xy[i], p33 = m.j2.eps_p_33[i];
  const double pp = pxx * pxx + pyy * pyy + p33 * p33 + 2 * pxy * pxy;
  const double ep = m.strain.eps_xx[i] * pxx + m.strain.eps_yy[i] * pyy + hoop_strain(m, i) * p33 + 2 * m.strain.eps_xy[i] * pxy;
  return m.cell_area[i] * m.disk_weight(i) * m.hoop.mu[i] * (pp - 2 * ep);
}

/// Continuum stress C : (eps - eps_p) of J2 disk i [Pa] (3D isotropic; xy the tensor
/// component): the stress conjugate to its plastic strain, -(1/V) dE/d(eps_p).
struct DiskStress {
  double xx = 0, yy = 0, xy = 0, s33 = 0;
};
inline DiskStress j2_stress(const Model& m, std::size_t i) {
  const double lam = m.hoop.lambda[i], mu = m.hoop.mu[i];
  const double exx = m.strain.eps_xx[i] - m.j2.eps_p_xx[i], eyy = m.strain.eps_yy[i] - m.j2.eps_p_yy[i];
  const double exy = m.strain.eps_xy[i] - m.j2.eps_p_xy[i], e33 = hoop_strain(m, i) - m.j2.eps_p_33[i];
  const double lt = lam * (exx + eyy + e33);
  return {lt + 2 * mu * exx, lt + 2 * mu * eyy, 2 * mu * exy, lt + 2 * mu * e33};
}

/// Stores j2_stress of disk i: the "before" value of the next plastic increment's work.
void store_j2_stress(Model& m, std::size_t i) {
  const DiskStress s = j2_stress(m, i);
  m.j2.sig_xx[i] = s.xx;
  m.j2.sig_yy[i] = s.yy;
  m.j2.sig_xy[i] = s.xy;
  m.j2.sig_33[i] = s.s33;
}

/// J2 return mapping of disk i (after the disk strains of pass A, before the bond forces).
/// Trial stress sigma = C : (eps - eps_p), relative stress xi = dev(sigma) - beta, von Mises
/// q = sqrt(3/2 xi:xi); if q > sigma_y (Drucker-Prager: max(k - alpha p, 0), p = tr sigma / 3),
/// radial return with linear kinematic (Prager) hardening, exact for a linear hardening law:
///   d(eps_eq) = (q - sigma_y) / (3 mu + H),   d(eps_p) = d(eps_eq) (3/2) xi / q,
///   d(beta) = (2/3) H d(eps_p).
/// The flow is deviatoric, so tr(eps_p) stays zero; on a mirror plane eps_p_xy stays zero.
/// sigma is exactly the conjugate of eps_p in the model's energy (the springs do not depend
/// on eps_p, the correction j2_correction_energy does, disk by disk), so the return mapping
/// minimises the energy plus dissipation of each disk and plastic flow never does negative
/// work. The work done on eps_p is summed with the trapezoid rule over the step,
/// (1/2) V (sigma before + after) : d(eps_p), as the leap-frog energy balance needs.
void j2_return_mapping(Model& m, std::size_t i) {
  const double mu = m.hoop.mu[i], H = m.j2.h[i], sigma_y = m.j2.sigma_y[i];
  double dxx = 0, dyy = 0, dxy = 0, d33 = 0, deq = 0;
  // Only disks with a complete neighbourhood (six intact bonds) flow: at an edge the
  // least-squares strain's energy V psi(eps) can exceed what the disk's few bonds carry, and
  // relaxing it makes the lattice indefinite (measured: a corner disk with three bonds blew
  // up a block impact). Edge disks, and disks that lose a bond, keep their plastic strain.
  // A disk one radius off a mirror plane counts its spring to the plane (the bond to its
  // mirror image) as a bond.
  int intact = (m.has_mirror_springs() && (m.mirror.kx[i] != 0 || m.mirror.ky[i] != 0)) ? 1 : 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k)
    intact += m.bond_intact(m.adj_bond(k)) ? 1 : 0;
  if (intact == 6) {
    const DiskStress s = j2_stress(m, i);
    const double mean = (s.xx + s.yy + s.s33) / 3.0;
    const double xxx = s.xx - mean - m.j2.beta_xx[i], xyy = s.yy - mean - m.j2.beta_yy[i];
    const double x33 = s.s33 - mean - m.j2.beta_33[i], xxy = s.xy - m.j2.beta_xy[i];
    const double q = std::sqrt(1.5 * (xxx * xxx + xyy * xyy + x33 * x33 + 2 * xxy * xxy));
    // Drucker-Prager (docs/model.md): the yield stress k - alpha p grows with confinement.
    // The flow is deviatoric (non-associated, no dilatancy), so p is the same before and
    // after the return and the radial return stays exact.
    const double alpha = m.j2.alpha.empty() ? 0.0 : m.j2.alpha[i];
    const double yield = alpha != 0 ? std::max(sigma_y - alpha * mean, 0.0) : sigma_y;
    if (q > yield) {
      deq = (q - yield) / (3 * mu + H);
      const double c = 1.5 * deq / q;
      dxx = c * xxx;
      dyy = c * xyy;
      d33 = c * x33;
      dxy = m.on_mirror(i) ? 0.0 : c * xxy;
      const double hb = 2.0 / 3.0 * H;
      m.j2.eps_p_xx[i] += dxx;
      m.j2.eps_p_yy[i] += dyy;
      m.j2.eps_p_xy[i] += dxy;
      m.j2.eps_p_33[i] += d33;
      m.j2.beta_xx[i] += hb * dxx;
      m.j2.beta_yy[i] += hb * dyy;
      m.j2.beta_xy[i] += hb * dxy;
      m.j2.beta_33[i] += hb * d33;
      m.j2.eps_p_eq[i] += deq;
    }
  }
  const double xx = m.j2.sig_xx[i], yy = m.j2.sig_yy[i], xy = m.j2.sig_xy[i], s33 = m.j2.sig_33[i];
  store_j2_stress(m, i);
  if (deq > 0) {
    m.j2.work[i] += 0.5 * m.cell_area[i] * m.disk_weight(i) *
                              ((xx + m.j2.sig_xx[i]) * dxx + (yy + m.j2.sig_yy[i]) * dyy +
                               2 * (xy + m.j2.sig_xy[i]) * dxy + (s33 + m.j2.sig_33[i]) * d33);
  }
}

void return_mapping(Model& m) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  m.balance.j2.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      if (m.j2.sigma_y[static_cast<std::size_t>(i)] > 0) j2_return_mapping(m, static_cast<std::size_t>(i));
    }
  });
}

/// Stored hardening energy of J2 disk i, A w (1/3) H eps_p : eps_p [J]: with Prager's
/// beta = (2/3) H eps_p it is the potential whose eps_p-derivative is beta.
double j2_hardening_energy(const Model& m, std::size_t i) {
  if (!(m.j2.sigma_y[i] > 0)) return 0.0;
  const double pxx = m.j2.eps_p_xx[i], pyy = m.j2.eps_p_yy[i], pxy = m.j2.eps_p_xy[i], p33 = m.j2.eps_p_33[i];
  return m.cell_area[i] * m.disk_weight(i) * m.j2.h[i] / 3.0 * (pxx * pxx + pyy * pyy + p33 * p33 + 2 * pxy * pxy);
}

/// 1 - D of a cracking bond's shear spring, 1 otherwise.
inline double shear_factor(const Model& m, std::size_t b) {
  const Model::FailedBond& f = m.failed_or_none(b);
  return f.crack != Model::kNoCrack ? 1 - f.damage : 1.0;
}

/// Stiffness cap of broken bond b acting as a contact [N/m]: m_eff contact_omega2, m_eff of
/// the two disks' cap masses (Model::cap_mass).
inline double contact_cap(const Model& m, std::size_t b) {
  return m.contact_cap(static_cast<std::size_t>(m.bi[b]), static_cast<std::size_t>(m.bj[b]));
}

/// Normal stiffness of broken bond b acting as a contact [N/m]: its normal spring, capped.
inline double contact_normal_stiffness(const Model& m, std::size_t b) { return std::min(m.kn(b), contact_cap(m, b)); }

/// Tangential stiffness of broken bond b acting as a contact [N/m]: its shear spring, or half
/// the normal one where the shear spring is not positive; capped.
inline double contact_tangential_stiffness(const Model& m, std::size_t b) {
  return std::min(m.ks(b) > 0 ? m.ks(b) : 0.5 * m.kn(b), contact_cap(m, b));
}

/// Normal stiffness of cracking bond b while closed (delta <= 0; open: (1 - D) k_n) [N/m]:
/// (1 - D) k_n + min(D k_n, cap), the damaged part acting as the contact
/// that the bond becomes at D = 1 (contact_normal_stiffness), capped as every contact is
/// (docs/model.md, "Fracture energy and softening"). The closure is a one-sided spring, and
/// central differences integrate a step across its kink with an error of order
/// (omega dt)^2 of its energy (docs/model.md, "Energy at contacts"). Uncapped, the jump
/// D k_n has omega dt = 0.92 and the crushed disks chatter across it: in the compression
/// test at r = 0.5 mm and 20 degrees the cracking bonds crossed it 2.8 million times and
/// created 5.3 mJ (2.3 % of the input, 96 % of the run's energy error).
/// At damage D (a damage step compares the stiffness before and after it).
inline double closed_crack_stiffness(const Model& m, std::size_t b, double D) {
  const double k = m.kn(b), excess = D * k - contact_cap(m, b);
  return excess > 0 ? k - excess : k;  // k - (D k - cap) = (1 - D) k + cap
}

/// FailedBond::crack of a tension crack and of a shear crack (shear_softening).
constexpr std::int64_t kTensionCrack = Model::kTensionCrack;
constexpr std::int64_t kShearCrack = Model::kShearCrack;
constexpr std::int64_t kDamageCrack = Model::kDamageCrack;

/// Current length and unit vector of the bond from disk i to disk j: its reference vector
/// a (Model::ref_ax, ref_ay) plus the relative displacement (no cancellation of the positions).
struct BondGeometry {
  double len, nx, ny;
};
inline BondGeometry bond_geometry(double ax, double ay, const double* __restrict ux, const double* __restrict uy,
                                  std::size_t i, std::size_t j) {
  const double dx = ax + (ux[j] - ux[i]);
  const double dy = ay + (uy[j] - uy[i]);
  const double len = std::sqrt(dx * dx + dy * dy);
  // Both components in one packed division (Pair): the divider bounds the bond pass.
  const Pair n = Pair{dx, dy} / Pair{len, len};
  return {len, n[0], n[1]};
}

/// Energy stored in intact bond b [J]: its springs, f^2 / (2k), and for hardening springs the
/// locked-in energy alpha^2 / (2H), H = k k_h / (k - k_h).
double intact_bond_energy(const Model& m, std::size_t b) {
  if (const Model::FailedBond& f = m.failed_or_none(b); f.crack != Model::kNoCrack) {
    // A cracking bond: (1 - D) on both springs, the normal one while open; closed, the
    // normal spring of closed_crack_stiffness.
    const double D = f.damage, g = 1 - D, delta = m.len_prev[b] - m.rest(b);
    const double us = m.u_s[b];
    // A shear crack: the damaged part of its shear spring is the friction of its faces,
    // D k_s (u_s - slip) (docs/model.md, "Shear cracks that soften").
    const double fr = f.crack == kShearCrack ? us - f.slip : 0.0;
    return 0.5 * (delta > 0 ? m.kn(b) * delta * delta * g : closed_crack_stiffness(m, b, D) * delta * delta) +
           g * 0.5 * m.ks(b) * us * us + D * 0.5 * m.ks(b) * fr * fr;
  }
  const double f_n = bond_force(m, b).f_n;  // stored, or from the positions in an elastic lattice
  double e = m.kn(b) != 0 ? 0.5 * f_n * f_n / m.kn(b) : 0.0;
  if (m.ks(b) != 0) e += 0.5 * m.f_s[b] * m.f_s[b] / m.ks(b);
  if (m.yields(b)) {
    const double hn = m.kn(b) * m.bond_plastic.kh_n[b] / (m.kn(b) - m.bond_plastic.kh_n[b]);
    if (hn > 0) e += 0.5 * m.bond_plastic.alpha_n[b] * m.bond_plastic.alpha_n[b] / hn;
    if (m.ks(b) > 0) {
      const double hs = m.ks(b) * m.bond_plastic.kh_s[b] / (m.ks(b) - m.bond_plastic.kh_s[b]);
      if (hs > 0) e += 0.5 * m.bond_plastic.alpha_s[b] * m.bond_plastic.alpha_s[b] / hs;
    }
  }
  return e;
}

/// Energy stored in broken bond b acting as a contact [J]: its normal spring k_n delta^2 / 2
/// at the overlap of the last update (not f_n^2 / (2 k_n): f_n includes the dashpot) and its
/// tangential spring.
double contact_bond_energy(const Model& m, std::size_t b) {
  const double delta = std::max(m.touch(b) - m.len_prev[b], 0.0);
  return 0.5 * contact_normal_stiffness(m, b) * delta * delta +
         0.5 * m.f_s[b] * m.f_s[b] / contact_tangential_stiffness(m, b);
}

/// State II of bond b (physics.md section 8): a contact between its two disks, with their
/// spins, at the current length `len` and direction n: compression only, Coulomb friction,
/// a dashpot at a fraction of critical damping. `dt` is the step (its dashpot work), and
/// `dt_shear` scales the tangential increment (0 for a contact that starts now).
void broken_bond_contact(Model& m, std::size_t b, double len, double nx, double ny, double dt, double dt_shear) {
  const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
  const double sx = -ny, sy = nx;
  const double dvx = m.vx[j] - m.vx[i], dvy = m.vy[j] - m.vy[i];
  const double delta = m.touch(b) - len;
  const double du_s =
      dt_shear * (dvx * sx + dvy * sy - (m.contact_r(i) * m.omega[i] + m.contact_r(j) * m.omega[j]));
  const laws::LinearContact law{contact_normal_stiffness(m, b), contact_tangential_stiffness(m, b), m.bond_mu(b),
                                m.contact_damping};
  const double m_eff = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]);
  Model::FailedBond& c = m.failed(b);
  laws::ContactState cs{m.f_n[b], m.f_s[b], c.f_damp};
  const laws::ContactStep st = law.update(cs, delta, -(dvx * nx + dvy * ny), du_s, law.damping_coefficient(m_eff));
  m.f_n[b] = cs.f_n;
  m.f_s[b] = cs.f_s;
  c.f_damp = cs.f_v;
  c.damping_work += st.damping_work(dt);
  c.friction_work += st.friction_dissipation_mid;
  m.len_prev[b] = len;
}

/// newly_broken code of a bond that starts to crack (it stays intact, leaves its disks' fits).
constexpr std::uint8_t kStartsCracking = 8;
/// newly_broken: the bond starts a shear crack (shear_softening; FailedBond::crack = kShearCrack).
constexpr std::uint8_t kStartsShearCracking = 9;
/// newly_broken: the bond starts smeared damage (damage_band; FailedBond::crack = kDamageCrack).
constexpr std::uint8_t kStartsDamage = 10;

/// The criteria of softening_bond (Rankine, crushing, Mohr-Coulomb) at the continuum stress of
/// bond b's midpoint, relative to the static strengths times `scale` [-], from the disks'
/// nonlocal strains (nonlocal_radius) or their own; the weights wi, wj of the two disks (a disk
/// without a full neighbourhood has none). The driver of smeared damage (docs/model.md,
/// "Smeared damage"): it grows with the strain whatever the bond's direction.
inline double midpoint_criterion(const Model& m, const SofteningParams& sp, const laws::MohrCoulombFailure& law,
                                 std::size_t b, std::size_t i, std::size_t j, double wi, double wj, double scale) {
  const bool nonlocal = !m.nonlocal.offset.empty();
  const std::vector<double>& gxx = nonlocal ? m.nonlocal.eps_xx : m.strain.eps_xx;
  const std::vector<double>& gyy = nonlocal ? m.nonlocal.eps_yy : m.strain.eps_yy;
  const std::vector<double>& gxy = nonlocal ? m.nonlocal.eps_xy : m.strain.eps_xy;
  const bool axisym = m.geometry == Geometry::Axisymmetric;
  const std::vector<double>& gtt = nonlocal ? m.nonlocal.eps_tt : m.strain.eps_tt;
  const double ett = axisym ? wi * gtt[i] + wj * gtt[j] : 0.0;
  const double fs = m.stiffness_factor(b);
  return relative_criterion(fs * sp.lambda2, fs * sp.lambda3, fs * sp.mu, sp.mc.sin_phi, 1 / (law.f_t * scale),
                            1 / (law.f_c * scale), 1 / (sp.mc.c * sp.mc.cos_phi * scale), wi * gxx[i] + wj * gxx[j],
                            wi * gyy[i] + wj * gyy[j], wi * gxy[i] + wj * gxy[j], ett,
                            m.geometry == Geometry::PlaneStress ? 0.0 : 1.0);
}

/// Eq. 19: the strengths of a bond of failure law l with section `sec` [m^2] (times the
/// random field's factor) at the rate factors rf, with tan(phi) precomputed per law.
inline laws::BondStrength bond_strength(const Model& m, std::size_t l, const laws::RateFactors& rf, double sec) {
  const laws::MohrCoulombFailure& law = m.failure_laws[l];
  return {law.f_t * rf.tension * sec, law.f_c * rf.compression * sec, law.c * rf.cohesion * sec, m.failure_tan_phi[l]};
}

/// Keeps a crack that the force pass starts at bond b, driver d0, failure at delta_f, for
/// settle_broken_bonds (BondCracks::starts): the pass's threads add them one at a time.
inline void add_crack_start(Model& m, std::size_t b, double d0, double delta_f) {
#pragma omp critical(hexdem_crack_starts)
  m.cracks.starts.push_back({static_cast<std::int64_t>(b), d0, delta_f});  // amortised: no allocation once grown
}

/// Bond b starts to crack at elongation delta, to fail at delta_f; a bond whose share of the
/// opening is not above its elastic stretch cannot soften: it breaks in tension at once.
inline void start_cracking(Model& m, std::size_t b, double delta, double delta_f) {
  if (delta_f > delta) {
    add_crack_start(m, b, delta, delta_f);
    m.newly_broken[b] = kStartsCracking;
  } else {
    m.newly_broken[b] = 1 + static_cast<std::uint8_t>(laws::FailureMode::Tension);
  }
}

/// The driver of a shear crack [m]: the springs' energy as an elongation of the normal spring,
/// sqrt(<delta>^2 + (k_s / k_n) u_s^2), so that 1/2 k_n d^2 is the energy of the springs that
/// the damage scales (the normal one only while open).
inline double shear_crack_driver(double kn, double ks, double delta, double us) {
  const double open = delta > 0 ? delta : 0.0;
  return std::sqrt(open * open + (ks / kn) * us * us);
}

/// Starts a shear crack at driver d0 (docs/model.md, "Shear cracks that soften"): linear
/// softening in the driver from d0 to delta_f = 2 G_F A / (k_n d0), so that the bond
/// dissipates G_F times its section A (as a tension crack along its bond does); a bond whose
/// delta_f would not exceed d0 breaks in shear at once.
inline void start_shear_cracking(Model& m, std::size_t b, double G_F, double d0) {
  const double delta_f = d0 > 0 ? 2.0 * G_F * m.bond_section(b) / (m.kn(b) * d0) : 0.0;
  if (delta_f > d0) {
    add_crack_start(m, b, d0, delta_f);
    m.newly_broken[b] = kStartsShearCracking;
  } else {
    m.newly_broken[b] = 1 + static_cast<std::uint8_t>(laws::FailureMode::Shear);
  }
}

/// Whether disk i gives the midpoint criteria its strain: with the nonlocal average, a disk
/// that has one (NonlocalStrain::offset); else a disk with a local strain and a full
/// neighbourhood (six bonds in the initial lattice). See softening_bond for why edge disks
/// are left out.
inline bool criterion_disk(const Model& m, std::size_t i) {
  if (!m.nonlocal.offset.empty()) return m.nonlocal.offset[i + 1] > m.nonlocal.offset[i];
  return m.strain.ok[i] && m.initial_bonds(i) == 6;
}

/// No tensile strength to check (a closing bond does not start to crack).
constexpr double kNoTension = std::numeric_limits<double>::infinity();

/// Pass B for a bond of a softening material (docs/model.md, "Fracture energy and
/// softening"); the shear measure u_s is already updated (rotation model: accumulated).
/// Forces (1 - D) k_n delta (delta > 0; a closed crack carries compression with the stiffness of
/// closed_crack_stiffness) and
/// (1 - D) k_s u_s. Damage grows with the elongation past its largest value, by the linear
/// law between delta0 and delta_f, only while the springs' energy e is positive, and books
/// dD (e - half step of the force drop) as fracture energy (a negative part as break_kinetic).
/// An intact bond checks the
/// continuum stress at its midpoint: Rankine in
/// tension starts cracking with delta_f = w_c |n . n1|; Mohr-Coulomb shear and crushing on the
/// principal stresses break it (brittle); a bond of a disk without a local strain uses the
/// bond criterion of Eq. 19.
void softening_bond(Model& m, std::size_t b, double len, double du_n, double du_s, double dt) {
  const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
  const auto l = static_cast<std::size_t>(m.bond_failure_law(b));
  const SofteningParams& sp = m.softening[l];
  const double delta = len - m.rest(b);
  const double us = m.u_s[b];
  // An intact bond has its row exactly when it cracks (settle_broken_bonds adds it).
  const std::int32_t row = m.failed_row[b];
  Model::FailedBond* const crack = row >= 0 ? &m.failed_rows[static_cast<std::size_t>(row)] : nullptr;
  if (crack != nullptr && crack->crack == kDamageCrack) {
    // Smeared damage (docs/model.md, "Smeared damage"): D grows with the criteria's value g at
    // the bond's midpoint by the linear law from g0 (the start) to g0 k_f, and each increment
    // books the springs' energy drop less the half step of the force drop, as a tension crack.
    Model::FailedBond& f = *crack;
    const bool nonlocal = !m.nonlocal.offset.empty();
    const bool full_i = criterion_disk(m, i);
    const bool full_j = criterion_disk(m, j);
    // Away from the hot cells every criterion is below 1 <= kappa (NonlocalStrain::hot).
    const bool hot = !nonlocal || m.nonlocal.disk_hot(i) || m.nonlocal.disk_hot(j);
    if ((full_i || full_j) && hot) {
      const double wi = full_i ? (full_j ? 0.5 : 1.0) : 0.0;
      const double g = midpoint_criterion(m, sp, m.failure_laws[l], b, i, j, wi, 1.0 - wi, m.strength_factor(b));
      if (g > f.kappa) {
        const double d_old = f.damage, d = laws::LinearSoftening::damage(g, f.delta0, f.delta_f);
        if (d > d_old) {
          const double kn = m.kn(b), ks = m.ks(b);
          const auto kn_of = [&](double dmg) { return delta > 0 ? (1 - dmg) * kn : closed_crack_stiffness(m, b, dmg); };
          const auto energy = [&](double dmg) { return 0.5 * (kn_of(dmg) * delta * delta + (1 - dmg) * ks * us * us); };
          const double half = 0.5 * ((kn_of(d_old) - kn_of(d)) * delta * du_n + (d - d_old) * ks * us * du_s);
          const double released = (energy(d_old) - energy(d)) - half;
          f.fracture_energy += std::max(released, 0.0);
          f.break_kinetic += std::min(released, 0.0);
          f.damage = d;
        }
        f.kappa = g;
      }
    }
  } else if (crack != nullptr && crack->crack == kShearCrack) {
    // A shear crack (docs/model.md, "Shear cracks that soften"): the springs soften with D,
    // and the damaged part of the shear spring is the friction of the closed faces,
    // D k_s (u_s - slip), at most mu |f_n| (nothing while the crack is open). f_s =
    // (1 - D) k_s u_s + D k_s (u_s - slip) = k_s (u_s - D slip). Each update books the drop
    // of the springs' energy at the present displacement less the half step of the force
    // drop that leap-frog's kinetic energy holds: the slip's as friction, the damage step's
    // as fracture energy (a negative part as break_kinetic), as for a tension crack.
    const double kn = m.kn(b), ks = m.ks(b);
    Model::FailedBond& f = *crack;
    const double d_old = f.damage;
    // The normal spring at damage D: open, (1 - D) k_n; closed, closed_crack_stiffness.
    const auto kn_of = [&](double dmg) { return delta > 0 ? (1 - dmg) * kn : closed_crack_stiffness(m, b, dmg); };
    if (d_old > 0) {
      const double limit = delta > 0 ? 0.0 : m.bond_mu(b) * kn_of(d_old) * (-delta);
      const double trial = d_old * ks * (us - f.slip);
      if (std::abs(trial) > limit) {
        const double slip = us - std::copysign(limit, trial) / (d_old * ks);
        const double a = us - f.slip, c = us - slip;
        const double dissipated = 0.5 * d_old * ks * (a * a - c * c) - 0.5 * d_old * ks * (slip - f.slip) * du_s;
        f.friction_work += dissipated;
        f.slip = slip;
      }
    }
    const double drv = shear_crack_driver(kn, ks, delta, us);
    if (drv > f.kappa) {
      const double d = laws::LinearSoftening::damage(drv, f.delta0, f.delta_f);
      if (d > d_old) {
        const double fr = us - f.slip;
        const auto energy = [&](double dmg) {
          return 0.5 * (kn_of(dmg) * delta * delta + (1 - dmg) * ks * us * us + dmg * ks * fr * fr);
        };
        const double half = 0.5 * ((kn_of(d_old) - kn_of(d)) * delta * du_n + (d - d_old) * ks * f.slip * du_s);
        const double released = (energy(d_old) - energy(d)) - half;
        f.fracture_energy += std::max(released, 0.0);
        f.break_kinetic += std::min(released, 0.0);
        f.damage = d;
      }
      f.kappa = drv;
    }
  } else if (crack != nullptr && delta > crack->kappa) {
    Model::FailedBond& f = *crack;
    const double d = laws::LinearSoftening::damage(delta, f.delta0, f.delta_f);
    const double e = 0.5 * (m.kn(b) * delta * delta + m.ks(b) * us * us);
    if (d > f.damage && e > 0) {
      // What the damage step releases at t_n, as for a break (docs/model.md, "Energy at a
      // break"): the drop of the springs' energy, dD e, less the half step of the force drop
      // that leap-frog's kinetic energy holds, (dt/2) v.dF = dD (k_n delta du_n + k_s u_s du_s) / 2
      // with the increments of the last step. Together dD (k_n delta delta_prev + k_s u_s
      // u_s_prev) / 2: the springs' energy in the bilinear form of the two steps, second-order
      // accurate. It is >= 0 unless a measure changed sign within the step; then the spring's
      // energy passed through 0 and the negative part is the integrator's (break_kinetic).
      const double half = 0.5 * (m.kn(b) * delta * du_n + m.ks(b) * us * du_s);
      const double released = (d - f.damage) * (e - half);
      f.fracture_energy += std::max(released, 0.0);
      f.break_kinetic += std::min(released, 0.0);
      f.damage = d;
      f.kappa = delta;
    }
  }
  m.len_prev[b] = len;
  if (crack != nullptr) {
    const double D = crack->damage, g = 1 - D;
    // A closed crack carries compression with the normal spring of closed_crack_stiffness.
    m.f_n[b] = delta > 0 ? m.kn(b) * delta * g : closed_crack_stiffness(m, b, D) * delta;
    m.f_s[b] = crack->crack == kShearCrack ? m.ks(b) * (us - D * crack->slip) : g * m.ks(b) * us;
    if (D >= 1.0) {
      const auto mode = crack->crack == kShearCrack ? laws::FailureMode::Shear : laws::FailureMode::Tension;
      m.newly_broken[b] = 1 + static_cast<std::uint8_t>(mode);
    }
    return;
  }
  m.f_n[b] = m.kn(b) * delta;  // intact: D = 0
  m.f_s[b] = m.ks(b) * us;
  // No criterion can fire where both disks' stresses are far from them (LocalCriterion).
  if (!m.local_criterion.disk.empty() && m.local_criterion.far(i, j)) return;
  // Eq. 20: the rate factors at the bond's strain rate; the random field's factor. The
  // factors are >= 1 and only raise the strengths: each criterion is checked at the static
  // strengths first, and the factors (two logarithms) are computed only when it fails there.
  // The strain rate (a division) is taken only when a criterion needs the factors: below
  // 1/s they are 1.
  const laws::MohrCoulombFailure& law = m.failure_laws[l];
  laws::RateFactors rf;
  bool rf_known = false;
  const auto rate_factors = [&]() -> const laws::RateFactors& {
    if (!rf_known) {
      const double edot = dt > 0 ? std::abs(du_n) / (dt * m.rest(b)) : 0.0;
      if (edot > 1.0) rf = law.rate_factors(edot);
      rf_known = true;
    }
    return rf;
  };
  const double scale = m.strength_factor(b);
  // The continuum stress is taken from the local strain of disks with a full neighbourhood
  // (six bonds in the initial lattice): at an edge the least-squares strain of a disk with
  // three or four bonds is a poor estimate of the stress (a Brazilian disc cracked at its free
  // rim with it). A bond between two edge disks uses Eq. 19 on its own forces: along a free
  // edge its normal force is the edge-parallel stress.
  // A disk that has lost its fit gives its frozen strain (settle_broken_bonds): excluding it
  // (Eq. 19 on the bond's own forces instead) made a rotated bar's crack dissipate 0.86 G_F A.
  const bool nonlocal = !m.nonlocal.offset.empty();
  const bool full_i = criterion_disk(m, i);
  const bool full_j = criterion_disk(m, j);
  if (!full_i && !full_j) {
    const double sec = m.bond_section(b) * scale;
    if (laws::MohrCoulombFailure::mode(m.f_n[b], m.f_s[b], bond_strength(m, l, {}, sec)) == laws::FailureMode::None)
      return;  // holds at the static strengths, so at the dynamic ones
    const laws::BondStrength st = bond_strength(m, l, rate_factors(), sec);
    const laws::FailureMode mode = laws::MohrCoulombFailure::mode(m.f_n[b], m.f_s[b], st);
    if (mode == laws::FailureMode::Tension && delta > 0) {
      // Cracking starts as for the continuum criterion, with the bond as the crack normal.
      start_cracking(m, b, delta, laws::LinearSoftening::crack_opening(sp.G_F, st.F_t / sec));
    } else if (mode == laws::FailureMode::Shear && sp.shear) {
      start_shear_cracking(m, b, sp.G_F, shear_crack_driver(m.kn(b), m.ks(b), delta, us));
    } else if (mode != laws::FailureMode::None) {
      m.newly_broken[b] = static_cast<std::uint8_t>(1 + static_cast<int>(mode));
    }
    return;
  }
  // Nonlocal: a bond far from every criterion is not checked (NonlocalStrain::hot).
  if (nonlocal && !m.nonlocal.disk_hot(i) && !m.nonlocal.disk_hot(j)) return;
  // The continuum stress at the midpoint: C : (eps_i + eps_j) / 2 (with the hoop strain).
  const double wi = full_i ? (full_j ? 0.5 : 1.0) : 0.0, wj = 1.0 - wi;
  const std::vector<double>& gxx = nonlocal ? m.nonlocal.eps_xx : m.strain.eps_xx;
  const std::vector<double>& gyy = nonlocal ? m.nonlocal.eps_yy : m.strain.eps_yy;
  const std::vector<double>& gxy = nonlocal ? m.nonlocal.eps_xy : m.strain.eps_xy;
  const double exx = wi * gxx[i] + wj * gxx[j], eyy = wi * gyy[i] + wj * gyy[j];
  const double exy = wi * gxy[i] + wj * gxy[j], tr = exx + eyy;
  const bool axisym = m.geometry == Geometry::Axisymmetric;
  const std::vector<double>& gtt = nonlocal ? m.nonlocal.eps_tt : m.strain.eps_tt;  // hoop_strain, of this pass
  const double ett = axisym ? wi * gtt[i] + wj * gtt[j] : 0.0;
  // The material's stress times the bond's stiffness factor ([random] stiffness_cov; docs/model.md,
  // "Random stiffness"): a stiffer bond carries more stress at the same strain.
  const double fs = m.stiffness_factor(b), lambda2 = fs * sp.lambda2, lambda3 = fs * sp.lambda3, mu = fs * sp.mu;
  const double iso = lambda2 * tr + lambda3 * ett;
  const double sxx = iso + 2 * mu * exx, syy = iso + 2 * mu * eyy, sxy = 2 * mu * exy;
  // The out-of-plane principal stress: plane strain lambda tr, axisymmetric the hoop stress.
  const double s3 = m.geometry == Geometry::PlaneStress ? 0.0 : lambda3 * (tr + ett) + 2 * mu * ett;
  if (sp.damage_kf > 0) {
    // Smeared damage starts where any criterion is reached at the midpoint (at the rate
    // factors' strengths), whatever the bond's own stretch; D = 0 at its value there.
    if (!laws::near_a_criterion(sxx, syy, sxy, s3, law.f_t * scale, sp.mc, scale)) return;
    const double g0 = midpoint_criterion(m, sp, law, b, i, j, wi, wj, scale);
    if (!(g0 >= 1)) return;
    const laws::RateFactors& r = rate_factors();
    if (r.tension != 1 || r.compression != 1 || r.cohesion != 1) {
      laws::MohrCoulombFailure dyn = law;
      dyn.f_t *= r.tension;
      dyn.f_c *= r.compression;
      SofteningParams sr = sp;
      sr.mc.c *= r.cohesion;
      if (!(midpoint_criterion(m, sr, dyn, b, i, j, wi, wj, scale) >= 1)) return;
    }
    if (sp.damage_kf > 1) {
      add_crack_start(m, b, g0, g0 * sp.damage_kf);
      m.newly_broken[b] = kStartsDamage;
    } else {
      m.newly_broken[b] = 1 + static_cast<std::uint8_t>(laws::FailureMode::Tension);
    }
    return;
  }
  if (!laws::near_a_criterion(sxx, syy, sxy, s3, delta > 0 ? law.f_t * scale : kNoTension, sp.mc, scale)) return;
  const laws::Principal2D p = laws::principal_values_2d(sxx, syy, sxy);
  if (delta > 0 && p.s1 > law.f_t * scale) {
    const double f_t = law.f_t * rate_factors().tension * scale;
    if (p.s1 > f_t) {
      const laws::Principal2D d = laws::principal_2d(sxx, syy, sxy);
      const double cosine = std::abs(m.nx[b] * d.n1x + m.ny[b] * d.n1y);
      start_cracking(m, b, delta, laws::LinearSoftening::crack_opening(sp.G_F, f_t) * cosine);
      return;
    }
  }
  const double s_max = std::max(p.s1, s3), s_min = std::min(p.s2, s3);
  if (sp.mc.mode(s_max, s_min, scale) == 0) return;  // holds at the static strengths
  laws::StressMohrCoulomb mc = sp.mc;
  mc.c *= rate_factors().cohesion;
  mc.f_c *= rf.compression;
  const int mode = mc.mode(s_max, s_min, scale);
  if (mode == static_cast<int>(laws::FailureMode::Shear) && sp.shear) {
    start_shear_cracking(m, b, sp.G_F, shear_crack_driver(m.kn(b), m.ks(b), delta, us));
    return;
  }
  if (mode != 0) m.newly_broken[b] = static_cast<std::uint8_t>(1 + mode);
}

/// Eq. 2, rotation model: the shear displacement over the last step, dt [(v_j - v_i).s -
/// (r_i omega_i + r_j omega_j)] with s = (-n_y, n_x) [m].
inline double rotation_shear_increment(double dt, const double* __restrict vx, const double* __restrict vy,
                                       const double* __restrict om, const double* __restrict radius,
                                       std::size_t i, std::size_t j, double nx, double ny) {
  const double sx = -ny, sy = nx;
  return dt * ((vx[j] - vx[i]) * sx + (vy[j] - vy[i]) * sy - (radius[i] * om[i] + radius[j] * om[j]));
}

/// Pass B: bond forces. Normal: f_n = k_n (L - L0) with the current length (objective).
/// Shear, rotation model (Eq. 1-2): f_s += k_s [(du_j - du_i).s - (r_i dtheta_i + r_j dtheta_j)]
/// with the increments of the last step. Shear, local-strain model: u_s = d s.(eps_i+eps_j)/2.n
/// in the reference directions, f_s = k_s u_s.
/// Plastic bonds (Eq. 16) take the same increments through the bilinear kinematic law (the
/// bonds of J2 disks stay elastic: their plasticity acts through the disks' strains);
/// breakable bonds are checked against Eqs. 17, 19, 20 and, once broken (state II), act as
/// contacts: compression only, Coulomb friction, a dashpot at a fraction of critical damping.
template <bool Rotation, bool Plastic, bool Breakable, bool Softening, bool J2>
void bond_forces(Model& m, double dt, const double* __restrict vx, const double* __restrict vy,
                 const double* __restrict om) {
  const auto nb = static_cast<std::ptrdiff_t>(m.num_bonds());
  // The stiffnesses per kind or per bond (Model::kn), decided once for the pass.
  const bool per_kind = m.k_n.empty();
  const double* __restrict kn_of = per_kind ? m.kind_k_n.data() : m.k_n.data();
  const double* __restrict ks_of = per_kind ? m.kind_k_s.data() : m.k_s.data();
  const std::uint8_t* __restrict kind = m.spring_kind.data();
  const LocalShearView local_shear_of(m);  // the local-strain model's (empty in the rotation model)
  // Softening: bonds that no criterion can break take softening_bond's forces here.
  const bool far = Softening && !m.local_criterion.disk.empty();
  const std::int32_t* __restrict row = Softening ? m.failed_row.data() : nullptr;  // cracking: a row
  m.balance.bonds.run(static_cast<std::size_t>(nb), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto b = static_cast<std::ptrdiff_t>(part_lo); b < static_cast<std::ptrdiff_t>(part_hi); ++b) {
      const std::size_t kb = per_kind ? kind[b] : static_cast<std::size_t>(b);
      const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
      const auto [len, nx, ny] = bond_geometry(m.ref_ax(static_cast<std::size_t>(b)), m.ref_ay(static_cast<std::size_t>(b)), m.ux.data(), m.uy.data(), i, j);
      m.nx[b] = nx;
      m.ny[b] = ny;
      if constexpr (Breakable) {
        if (!m.bond_intact(static_cast<std::size_t>(b))) {
          broken_bond_contact(m, static_cast<std::size_t>(b), len, nx, ny, dt, dt);
          continue;
        }
      }
      // Eq. 2: the shear increment from the relative velocity and the spins (rotation model),
      // or u_s from the disks' strains (local-strain model).
      double du_s = 0.0;
      if constexpr (Rotation) {
        du_s = rotation_shear_increment(dt, vx, vy, om, m.radius.data(), i, j, nx, ny);
      } else {
        const double u_s = local_shear_of(static_cast<std::size_t>(b), i, j);
        du_s = u_s - m.u_s[b];
        m.u_s[b] = u_s;
      }
      double du_n = 0.0;  // the stretch over the last step (hardening, softening, strain rate)
      if constexpr (Plastic || Breakable) du_n = len - m.len_prev[b];
      if constexpr (Softening) {
        const std::int32_t law_b = m.bond_failure_law(static_cast<std::size_t>(b));
        if (law_b >= 0 && m.softening[static_cast<std::size_t>(law_b)].G_F > 0) {
          // The rotation model's shear displacement is accumulated: the force is (1 - D) k_s u_s.
          if constexpr (Rotation) m.u_s[b] += du_s;
          if (far && row[b] < 0 && m.local_criterion.far(i, j)) {
            // softening_bond's forces of an intact bond (D = 0) that no criterion can break.
            m.f_n[b] = kn_of[kb] * (len - m.rest(static_cast<std::size_t>(b)));
            m.f_s[b] = ks_of[kb] * m.u_s[b];
            m.len_prev[b] = len;
            continue;
          }
          softening_bond(m, static_cast<std::size_t>(b), len, du_n, du_s, dt);
          continue;
        }
      }
      bool hardening = false;
      if constexpr (Plastic) hardening = m.bond_plastic.f_yield[b] > 0;
      if (hardening) {
        // Eq. 16: bilinear kinematic hardening, incrementally (exact for any increment).
        laws::BilinearState sn{m.f_n[b], m.bond_plastic.alpha_n[b]};
        const laws::BilinearKinematic normal{kn_of[kb], m.bond_plastic.kh_n[b], m.bond_plastic.f_yield[b]};
        double work = normal.update(sn, du_n).dissipation_trapezoid;
        m.f_n[b] = sn.f;
        m.bond_plastic.alpha_n[b] = sn.alpha;
        if (ks_of[kb] > 0) {
          laws::BilinearState ss{m.f_s[b], m.bond_plastic.alpha_s[b]};
          const laws::BilinearKinematic shear{ks_of[kb], m.bond_plastic.kh_s[b], m.bond_plastic.f_yield[b]};
          work += shear.update(ss, du_s).dissipation_trapezoid;
          m.f_s[b] = ss.f;
          m.bond_plastic.alpha_s[b] = ss.alpha;
        } else {
          m.f_s[b] += ks_of[kb] * du_s;
        }
        m.bond_plastic.work[b] += work;
        if (m.bond_plastic.alpha_n[b] != 0.0 || m.bond_plastic.alpha_s[b] != 0.0) m.state[b] = static_cast<std::uint8_t>(BondState::Yielded);
      } else {
        // Eq. 2 (normal spring on the current length, objective) and the shear spring.
        m.f_n[b] = kn_of[kb] * (len - m.rest(b));
        if constexpr (Rotation) {
          m.f_s[b] += ks_of[kb] * du_s;
        } else {
          m.f_s[b] = ks_of[kb] * m.u_s[b];
        }
        // Bonds of J2 disks are elastic; they report the disks' yielding (bonds join the disks
        // of one body).
        if constexpr (J2) {
          if (m.j2.eps_p_eq[i] > 0 || m.j2.eps_p_eq[j] > 0) m.state[b] = static_cast<std::uint8_t>(BondState::Yielded);
        }
      }
      if constexpr (Plastic || Breakable) m.len_prev[b] = len;
      if constexpr (Breakable) {
        const std::int32_t law_b = m.bond_failure_law(static_cast<std::size_t>(b));
        if (law_b >= 0) {
          // Eqs. 17, 19, 20: the strengths of the bond's section, with the rate factors of the
          // bond's strain rate over the last step. The factors are >= 1 and only raise the
          // strengths, so a bond that holds at its static strengths holds: they (two logarithms)
          // are computed only for the bonds that do not.
          const auto l = static_cast<std::size_t>(law_b);
          const double sec = m.bond_section(b) * m.strength_factor(static_cast<std::size_t>(b));
          laws::FailureMode mode = laws::MohrCoulombFailure::mode(m.f_n[b], m.f_s[b], bond_strength(m, l, {}, sec));
          if (mode != laws::FailureMode::None) {  // the strain rate (a division) only then
            const double edot = dt > 0 ? std::abs(du_n) / (dt * m.rest(b)) : 0.0;
            if (edot > 1.0) {
              const laws::RateFactors rf = m.failure_laws[l].rate_factors(edot);
              mode = laws::MohrCoulombFailure::mode(m.f_n[b], m.f_s[b], bond_strength(m, l, rf, sec));
            }
          }
          // The bond still acts, intact, in this evaluation; settle_broken_bonds turns it into
          // a contact and books what the break releases.
          if (mode != laws::FailureMode::None) m.newly_broken[b] = static_cast<std::uint8_t>(1 + static_cast<int>(mode));
        }
      }
    }
  });
}

/// Pass B for an elastic lattice (no plasticity, failure or J2 disks): the paper's Eq. 2.
/// Normal spring on the current length, f_n = k_n (L - L0); shear spring, rotation model:
/// f_s += k_s dt [(v_j - v_i).s - (r_i omega_i + r_j omega_j)], local-strain model:
/// f_s = k_s u_s with u_s = g : (eps_i + eps_j). The same arithmetic as bond_forces (the
/// same helpers), without its laws' branches.
template <bool Rotation, bool PerKind>
void elastic_bond_forces(Model& m, double dt, const double* __restrict vx, const double* __restrict vy,
                         const double* __restrict om) {
  const auto nb = static_cast<std::ptrdiff_t>(m.num_bonds());
  const std::int32_t* __restrict bi = m.bi.data();
  const std::int32_t* __restrict bj = m.bj.data();
  const std::uint8_t* __restrict kind = m.spring_kind.data();
  const double* __restrict kn = PerKind ? m.kind_k_n.data() : m.k_n.data();
  const double* __restrict ks = PerKind ? m.kind_k_s.data() : m.k_s.data();
  const double* __restrict x0 = m.x0.data();
  const double* __restrict y0 = m.y0.data();
  const double* __restrict ux = m.ux.data();
  const double* __restrict uy = m.uy.data();
  const double* __restrict radius = m.radius.data();
  // The reference geometry per kind (a regular lattice's; implies PerKind) or per bond.
  const bool geometry_per_kind = !m.kind_rest.empty();
  const double* __restrict kind_ax = m.kind_ax.data();
  const double* __restrict kind_ay = m.kind_ay.data();
  const double* __restrict kind_rest = m.kind_rest.data();
  const double* __restrict rest = m.rest_length.data();
  double* __restrict f_s = m.f_s.data();
  double* __restrict pair_fx = m.pair_fx.data();
  double* __restrict pair_fy = m.pair_fy.data();
  const LocalShearView local_shear_of(m);  // the local-strain model's (empty in the rotation model)
  m.balance.elastic_bonds.run(static_cast<std::size_t>(nb), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto b = static_cast<std::ptrdiff_t>(part_lo); b < static_cast<std::ptrdiff_t>(part_hi); ++b) {
      const std::size_t kb = PerKind ? kind[b] : static_cast<std::size_t>(b);
      const auto i = static_cast<std::size_t>(bi[b]), j = static_cast<std::size_t>(bj[b]);
      double ax, ay, rest_b;
      if (geometry_per_kind) {
        const std::size_t k = kind[b];
        ax = kind_ax[k], ay = kind_ay[k], rest_b = kind_rest[k];
      } else {
        ax = x0[j] - x0[i], ay = y0[j] - y0[i], rest_b = rest[b];
      }
      const auto [len, nx, ny] = bond_geometry(ax, ay, ux, uy, i, j);
      const double f_n = kn[kb] * (len - rest_b);
      // The pair force on bi (Eq. 3), for the gather: f_n n, and in the rotation model + f_s s.
      double f_x = f_n * nx, f_y = f_n * ny;
      if constexpr (Rotation) {
        const double fs = f_s[b] + ks[kb] * rotation_shear_increment(dt, vx, vy, om, radius, i, j, nx, ny);
        f_s[b] = fs;
        f_x -= fs * ny;
        f_y += fs * nx;
      } else {
        f_s[b] = ks[kb] * local_shear_of(static_cast<std::size_t>(b), i, j);  // u_s is not kept (Model::u_s)
      }
      pair_fx[b] = f_x;
      pair_fy[b] = f_y;
    }
  });
}

/// The bond pass for each combination of laws, chosen once per pass instead of per bond; an
/// elastic lattice (K < 2: no plasticity, failure or J2) takes elastic_bond_forces.
using BondKernel = void (*)(Model&, double, const double*, const double*, const double*);
template <std::size_t K>
void bond_forces_of(Model& m, double dt, const double* vx, const double* vy, const double* om) {
  constexpr bool rotation = (K & 1) != 0;
  if constexpr (K < 2) {
    if (m.k_n.empty()) {
      elastic_bond_forces<rotation, true>(m, dt, vx, vy, om);  // stiffnesses per spring kind
    } else {
      elastic_bond_forces<rotation, false>(m, dt, vx, vy, om);
    }
  } else {
    bond_forces<rotation, (K & 2) != 0, (K & 4) != 0, (K & 8) != 0, (K & 16) != 0>(m, dt, vx, vy, om);
  }
}
template <std::size_t... K>
constexpr std::array<BondKernel, sizeof...(K)> bond_kernels(std::index_sequence<K...>) {
  return {&bond_forces_of<K>...};
}

/// (vx, vy, om): the velocities whose dt-multiple is the rotation model's shear increment.
void compute_bond_forces(Model& m, double dt, const double* vx, const double* vy, const double* om) {
  static constexpr std::array<BondKernel, 32> kernels = bond_kernels(std::make_index_sequence<32>{});
  const std::size_t k = (m.shear_model == ShearModel::Rotation ? 1U : 0U) | (m.any_plastic ? 2U : 0U) |
                        (m.any_breakable ? 4U : 0U) | (m.any_softening ? 8U : 0U) | (m.any_j2 ? 16U : 0U);
  kernels[k](m, dt, vx, vy, om);
}

/// Pass C: W_i = S_i M_i^-1 with S_i = dE/d(eps_i): the local-strain shear springs
/// (sum over bonds of f_s (d/2) sym(s0 (x) n0)), in axisymmetric models the hoop term
/// E_h = A b [(lambda + 2 mu) eps_tt^2 / 2 + lambda eps_tt (eps_rr + eps_zz)], eps_tt = u_r / b,
/// and for J2 disks the plastic correction, -2 mu A w eps_p.
void compute_strain_conjugates(Model& m, bool shear_springs, bool hoop) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  const std::int32_t* __restrict adj_offset = m.adj_offset.data();
  const AdjacencyView a(m);
  const double* __restrict f_s = m.f_s.data();
  const LocalShearView g(m);  // its g, per bond or per kind
  m.balance.conjugates.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      double sxx = 0, syy = 0, sxy = 0;
      if (shear_springs) {
        for (auto k = adj_offset[i]; k < adj_offset[i + 1]; ++k) {
          const std::size_t b = a.bond(k);
          if (a.state[b] > 1) continue;  // !Model::bond_intact
          const double fs = f_s[b];
          const std::size_t gb = g.g_index(b);
          sxx += fs * g.g_xx[gb];
          syy += fs * g.g_yy[gb];
          sxy += fs * g.g_xy[gb];
        }
      }
      if (hoop) {
        const double c = m.cell_area[i] * m.disk_weight(i) * hoop_stress(m, i, m.strain.eps_tt[i]).in_plane;
        sxx += c;
        syy += c;
      }
      if (m.any_j2 && m.j2.sigma_y[i] > 0) {
        const double c = -2 * m.hoop.mu[i] * m.cell_area[i] * m.disk_weight(i);
        sxx += c * m.j2.eps_p_xx[i];
        syy += c * m.j2.eps_p_yy[i];
        sxy += c * m.j2.eps_p_xy[i];
      }
      if (m.on_mirror(i)) sxy = 0.0;  // the projection's adjoint (energy consistency)
      const double mxx = m.strain.minv_xx[i], mxy = m.strain.minv_xy[i], myy = m.strain.minv_yy[i];
      m.strain.w_xx[i] = sxx * mxx + sxy * mxy;
      m.strain.w_xy[i] = sxx * mxy + sxy * myy;
      m.strain.w_yx[i] = sxy * mxx + syy * mxy;
      m.strain.w_yy[i] = sxy * mxy + syy * myy;
    }
  });
}

/// Pass D: gather the forces on each disk. Pair forces (Eq. 3): the force on bi is
/// f_n n + f_s s (rotation model; local strain: f_n n only), the moment on both ends +r f_s.
/// Local-strain and hoop terms: F_i = sum_k (W_i + W_k) a_ik, the gradient of the energy
/// through the strains of i and of its neighbours ("stress divergence"); hoop: -A sigma_tt.
template <bool PairShear, bool StrainTerms, bool Hoop, bool Breakable, bool Mirror, bool J2, bool Elastic>
void gather_forces(Model& m) {
  static_assert(!(Elastic && (Breakable || J2)), "an elastic lattice has neither failure nor J2 disks");
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
  // Raw arrays: the loop writes only fx, fy, torque, which nothing in it reads. The disk's
  // own values are read once, outside its bonds' loop (the same arithmetic: the compiler
  // could not keep them in registers through the loop's loads).
  const std::int32_t* __restrict offset = m.adj_offset.data();
  const AdjacencyView a(m);
  const double* __restrict w_xx = m.strain.w_xx.data();
  const double* __restrict w_xy = m.strain.w_xy.data();
  const double* __restrict w_yx = m.strain.w_yx.data();
  const double* __restrict w_yy = m.strain.w_yy.data();
  const double* __restrict bnx = m.nx.data();
  const double* __restrict bny = m.ny.data();
  const double* __restrict f_n = m.f_n.data();
  const double* __restrict f_s = m.f_s.data();
  const double* __restrict pair_fx = m.pair_fx.data();
  const double* __restrict pair_fy = m.pair_fy.data();
  const double* __restrict radius = m.radius.data();
  const double* __restrict contact_radius = m.contact_radii();
  double* __restrict out_fx = m.fx.data();
  double* __restrict out_fy = m.fy.data();
  double* __restrict out_tq = m.torque.data();
  m.balance.gather.run(static_cast<std::size_t>(n), [&](std::size_t part_lo, std::size_t part_hi) {
    for (auto i = static_cast<std::ptrdiff_t>(part_lo); i < static_cast<std::ptrdiff_t>(part_hi); ++i) {
      const auto iu = static_cast<std::size_t>(i);
      double fx = 0, fy = 0, tq = 0;
      const double r_i = radius[i];
      // The lever arm of a broken bond's contact: the contact radius ([contact] radius_spread).
      double rc_i = 0;
      if constexpr (Breakable) rc_i = contact_radius[i];
      // Disk i's terms of the strain forces (StrainTerms): its centre, its W and whether it has a fit.
      double x_i = 0, y_i = 0, wi_xx = 0, wi_xy = 0, wi_yx = 0, wi_yy = 0, co = 0;
      if constexpr (StrainTerms) {
        x_i = a.x0[i], y_i = a.y0[i];
        wi_xx = w_xx[i], wi_xy = w_xy[i], wi_yx = w_yx[i], wi_yy = w_yy[i];
        co = a.ok[i] ? 1.0 : 0.0;
      }
      for (auto k = offset[i]; k < offset[i + 1]; ++k) {
        // Model::adj_bond and adj_sign: the entry is b where i is the bond's bi, ~b where bj.
        const std::size_t b = a.bond(k);
        const double s = a.entry[k] >= 0 ? 1.0 : -1.0;
        if constexpr (Elastic) {
          // The bond pass's pair force (f_n n, + f_s s in the rotation model) and its moment.
          fx += s * pair_fx[b];
          fy += s * pair_fy[b];
          if constexpr (PairShear) tq += r_i * f_s[b];
        } else {
          const double nx = bnx[b], ny = bny[b];
          double f_x = f_n[b] * nx, f_y = f_n[b] * ny;
          if constexpr (Breakable) {
            if (a.state[b] > 1) {  // !Model::bond_intact
              // A broken bond in contact: pair force with friction and its moment.
              f_x -= f_s[b] * ny;
              f_y += f_s[b] * nx;
              fx += s * f_x;
              fy += s * f_y;
              tq += rc_i * f_s[b];
              continue;
            }
          }
          if constexpr (PairShear) {
            f_x -= f_s[b] * ny;
            f_y += f_s[b] * nx;
            tq += r_i * f_s[b];
          }
          fx += s * f_x;
          fy += s * f_y;
        }
        if constexpr (StrainTerms) {
          if (a.in_fit(b)) {
            // d(eps_i)/d(u_i) through o, if o is in i's fit, and d(eps_o)/d(u_i), if i is in o's.
            // The other disk, from the bond's ends; Model::adj_ax.
            const std::size_t o = a.other(b, iu);
            const double ax = a.x0[o] - x_i, ay = a.y0[o] - y_i;
            const double ci = a.ok[o] ? 1.0 : 0.0;
            const double wxx = ci * wi_xx + co * w_xx[o], wxy = ci * wi_xy + co * w_xy[o];
            const double wyx = ci * wi_yx + co * w_yx[o], wyy = ci * wi_yy + co * w_yy[o];
            fx += wxx * ax + wxy * ay;
            fy += wyx * ax + wyy * ay;
          }
        }
      }
      if constexpr (Hoop) {
        // dE_h/du_r = A b sigma_tt / b; a J2 disk's correction adds -2 mu eps_p_tt to sigma_tt.
        double sigma_tt = hoop_stress(m, iu, m.strain.eps_tt[iu]).tt;
        if constexpr (J2) sigma_tt -= 2 * m.hoop.mu[iu] * m.j2.eps_p_33[iu];
        fx -= m.cell_area[iu] * sigma_tt;
      }
      if constexpr (Mirror) {
        fx -= m.mirror.kx[iu] * m.ux[iu];
        fy -= m.mirror.ky[iu] * m.uy[iu];
      }
      out_fx[i] = fx;
      out_fy[i] = fy;
      out_tq[i] = tq;
    }
  });
}

/// The gather pass for each combination of terms, chosen once per pass.
using GatherKernel = void (*)(Model&);
template <std::size_t K>
void gather_forces_of(Model& m) {
  constexpr bool elastic = (K & 64) != 0, breakable = (K & 8) != 0, j2 = (K & 32) != 0;
  if constexpr (!(elastic && (breakable || j2))) {  // never dispatched: no code for it
    gather_forces<(K & 1) != 0, (K & 2) != 0, (K & 4) != 0, breakable, (K & 16) != 0, j2, elastic>(m);
  }
}
template <std::size_t... K>
constexpr std::array<GatherKernel, sizeof...(K)> gather_kernels(std::index_sequence<K...>) {
  return {&gather_forces_of<K>...};
}

void gather_forces(Model& m, bool pair_shear, bool strain_terms, bool hoop) {
  static constexpr std::array<GatherKernel, 128> kernels = gather_kernels(std::make_index_sequence<128>{});
  const std::size_t k = (pair_shear ? 1U : 0U) | (strain_terms ? 2U : 0U) | (hoop ? 4U : 0U) |
                        (m.any_breakable ? 8U : 0U) | (m.has_mirror_springs() ? 16U : 0U) | (m.any_j2 ? 32U : 0U) |
                        (m.elastic_lattice() ? 64U : 0U);
  kernels[k](m);
}

}  // namespace

namespace {

/// The passes of compute_internal_forces up to the gather, with the shear increments
/// dt (vx, vy, om) of the rotation model; `criteria`: the failure criteria will be checked
/// (the nonlocal strains are needed).
void force_passes(Model& m, double dt, const double* vx, const double* vy, const double* om, bool criteria) {
  const bool local = m.shear_model == ShearModel::LocalStrain;
  const bool hoop = m.geometry == Geometry::Axisymmetric;
  const bool strains = local || hoop || m.any_j2;
  // Softening needs the strains for its criteria even where the energy does not.
  if (strains || m.any_softening) compute_disk_strains(m);
  if (criteria && !m.nonlocal.offset.empty()) compute_nonlocal_strains(m);
  if (m.any_j2) return_mapping(m);
  if (hoop && m.any_softening) update_hoop_damage(m);
  compute_bond_forces(m, dt, vx, vy, om);
  if (strains) compute_strain_conjugates(m, local, hoop);
  gather_forces(m, !local, strains, hoop);
}

}  // namespace

std::size_t compute_internal_forces(Model& m, double dt) {
  force_passes(m, dt, m.vx.data(), m.vy.data(), m.omega.data(), true);
  return m.any_breakable ? settle_broken_bonds(m, dt) : 0;
}

void compute_probe_forces(Model& m) {
  // The probe checks no criterion: its nonlocal strains are not updated.
  force_passes(m, 1.0, m.ux.data(), m.uy.data(), m.theta.data(), false);
  // The probe is the linear operator: no bond breaks in it (it is far below any strength,
  // and a break would not be linear).
  std::fill(m.newly_broken.begin(), m.newly_broken.end(), 0);
  m.cracks.starts.clear();
}

BondForce bond_force(const Model& m, std::size_t b) {
  if (!m.elastic_lattice()) return {m.f_n[b], m.f_s[b], m.nx[b], m.ny[b]};
  // elastic_bond_forces' arithmetic at the positions of the last force pass.
  const auto [len, nx, ny] = bond_geometry(m.ref_ax(b), m.ref_ay(b), m.ux.data(), m.uy.data(),
                                           static_cast<std::size_t>(m.bi[b]), static_cast<std::size_t>(m.bj[b]));
  return {m.kn(b) * (len - m.rest(b)), m.f_s[b], nx, ny};
}

double elastic_energy(const Model& m) {
  double e = deterministic_sum(
      m.num_bonds(),
      [&](std::size_t b) {
        if (m.bond_intact(b)) return intact_bond_energy(m, b);
        return contact_bond_energy(m, b);
      },
      m.scratch);
  if (m.has_mirror_springs()) {
    e += deterministic_sum(
        m.num_disks(),
        [&](std::size_t i) { return 0.5 * (m.mirror.kx[i] * m.ux[i] * m.ux[i] + m.mirror.ky[i] * m.uy[i] * m.uy[i]); },
        m.scratch);
  }
  if (m.geometry == Geometry::Axisymmetric) {
    e += deterministic_sum(
        m.num_disks(),
        [&](std::size_t i) { return hoop_energy(m, i); },
        m.scratch);
  }
  if (m.any_j2) {
    e += deterministic_sum(
        m.num_disks(),
        [&](std::size_t i) {
          return m.j2.sigma_y[i] > 0 ? j2_correction_energy(m, i) + j2_hardening_energy(m, i) : 0.0;
        },
        m.scratch);
  }
  return e;
}

BondDissipation bond_dissipation(const Model& m) {
  BondDissipation d;
  const std::size_t nb = m.num_bonds();
  if (!m.bond_plastic.work.empty()) d.plastic = deterministic_sum(nb, [&](std::size_t b) { return m.bond_plastic.work[b]; }, m.scratch);
  if (m.any_j2) {
    // J2 disks: the work done on eps_p (bonds above, out-of-plane term here) less what the
    // back stress holds (booked as stored energy in elastic_energy).
    d.plastic += deterministic_sum(
        m.num_disks(), [&](std::size_t i) { return m.j2.work[i] - j2_hardening_energy(m, i); }, m.scratch);
  }
  if (!m.any_breakable) return d;  // the failure arrays exist only for breakable models
  // Over the bonds in their order, as every sum of the ledger (the rows are in failure order).
  d.fracture = deterministic_sum(nb, [&](std::size_t b) { return m.bond_fracture_energy(b); }, m.scratch);
  if (!m.hoop_cracks.fracture.empty())
    d.fracture += deterministic_sum(m.num_disks(), [&](std::size_t i) { return m.hoop_cracks.fracture[i]; }, m.scratch);
  d.break_kinetic = deterministic_sum(nb, [&](std::size_t b) { return m.bond_break_kinetic(b); }, m.scratch);
  if (!m.hoop_cracks.break_kinetic.empty())
    d.break_kinetic +=
        deterministic_sum(m.num_disks(), [&](std::size_t i) { return m.hoop_cracks.break_kinetic[i]; }, m.scratch);
  d.contact_damping = deterministic_sum(nb, [&](std::size_t b) { return m.contact_damping_work(b); }, m.scratch);
  d.friction = deterministic_sum(nb, [&](std::size_t b) { return m.contact_friction_work(b); }, m.scratch);
  return d;
}

namespace {

/// Half the work of bond b's own springs over the last step, (f_n d(delta) + f_s d(u_s)) / 2
/// [J], with the increments from the velocities: x(t_n - dt) = x(t_n) - dt v(t - dt/2). This is
/// the bond's part of the break's kinetic half step, (dt/2) v.dF_own (docs/model.md, "Energy
/// at a break"); its stored energy less it is the bilinear form of the two steps. Also
/// returns the length increment d(L) [m].
struct HalfStep {
  double half = 0, d_len = 0;
};
HalfStep own_half_step(const Model& m, std::size_t b, double dt, bool local) {
  if (dt == 0) return {};
  const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
  const double dvx = m.vx[j] - m.vx[i], dvy = m.vy[j] - m.vy[i];
  const double dx = m.ref_ax(b) + (m.ux[j] - m.ux[i]) - dt * dvx;
  const double dy = m.ref_ay(b) + (m.uy[j] - m.uy[i]) - dt * dvy;
  const double d_delta = m.len_prev[b] - std::sqrt(dx * dx + dy * dy);
  double d_us = 0.0;
  if (!local) {
    d_us = dt * (-dvx * m.ny[b] + dvy * m.nx[b] - (m.radius[i] * m.omega[i] + m.radius[j] * m.omega[j]));
  } else if (m.strain.ok[i] && m.strain.ok[j]) {
    const std::array<double, 3> ri = fit_gradient(m, i, m.vx, m.vy), rj = fit_gradient(m, j, m.vx, m.vy);
    const LocalShearView g(m);
    const std::size_t gb = g.g_index(b);
    d_us = dt * (g.g_xx[gb] * (ri[0] + rj[0]) + g.g_yy[gb] * (ri[1] + rj[1]) + 2.0 * g.g_xy[gb] * (ri[2] + rj[2]));
  }
  return {0.5 * (m.f_n[b] * d_delta + m.f_s[b] * d_us), d_delta};
}

}  // namespace

std::size_t settle_broken_bonds(Model& m, double dt) {
  const bool local = m.shear_model == ShearModel::LocalStrain;
  const bool hoop = m.geometry == Geometry::Axisymmetric;
  const bool energy_strains = local || hoop || m.any_j2;
  const bool strains = energy_strains || m.any_softening;
  // The bonds found past their strength, in ascending order (a fixed order: deterministic).
  // Most steps have none: the flags are scanned 8 at a time up to the first one.
  const std::size_t nb = m.num_bonds();
  const std::uint8_t* flags = m.newly_broken.data();
  std::size_t first = 0;
  for (std::uint64_t word = 0; first + 8 <= nb; first += 8) {
    std::memcpy(&word, flags + first, 8);
    if (word != 0) break;
  }
  while (first < nb && flags[first] == 0) ++first;
  if (first == nb) return 0;
  std::size_t broken = 0;
  for (std::size_t b = first; b < nb; ++b) broken += flags[b] != 0 ? 1 : 0;
  // The cracks the pass started, in bond order (its threads added them in any order).
  std::sort(m.cracks.starts.begin(), m.cracks.starts.end(),
            [](const CrackStart& a, const CrackStart& c) { return a.bond < c.bond; });
  // Smeared damage that starts: the bond keeps its springs and its place in the fits, so
  // nothing changes but its row (in bond order).
  for (std::size_t b = first; b < nb; ++b) {
    if (flags[b] != kStartsDamage) continue;
    const auto start = std::lower_bound(m.cracks.starts.begin(), m.cracks.starts.end(), static_cast<std::int64_t>(b),
                                        [](const CrackStart& c, std::int64_t bond) { return c.bond < bond; });
    HEXDEM_VERIFY(start != m.cracks.starts.end() && start->bond == static_cast<std::int64_t>(b),
                  "settle_broken_bonds: a damage start the force pass kept");
    Model::FailedBond& f = add_failed_row(m, b);
    f.crack = kDamageCrack;
    f.delta0 = f.kappa = start->delta0;
    f.delta_f = start->delta_f;
    m.newly_broken[b] = 0;
    --broken;
    // Its disks' hoop terms keep only the hoop stress's square from now on, as at a break (the
    // full term is bounded below only by undamaged in-plane springs), with the constant that
    // keeps their energy continuous.
    if (!m.hoop.cut.empty())
      for (const auto i : {static_cast<std::size_t>(m.bi[b]), static_cast<std::size_t>(m.bj[b])})
        if (!m.hoop.cut[i]) {
          const double before = hoop_energy(m, i);
          m.hoop.cut[i] = 1;
          m.hoop.constant[i] += hoop_energy(m, i) - before;
        }
  }
  if (broken == 0) {
    m.cracks.starts.clear();
    return 0;
  }
  // Forces with the bonds still intact, as the pass computed them.
  std::copy(m.fx.begin(), m.fx.end(), m.fx_intact.begin());
  std::copy(m.fy.begin(), m.fy.end(), m.fy_intact.begin());
  std::copy(m.torque.begin(), m.torque.end(), m.torque_intact.begin());

  // Each breaking bond's own half step and length increment, before any break of the pass
  // changes a fit.
  for (std::size_t b = first; b < m.num_bonds(); ++b)
    if (m.newly_broken[b]) {
      const HalfStep h = own_half_step(m, b, dt, local);
      m.event_half.push_back(h.half);
      m.event_d_len.push_back(h.d_len);
    }

  std::array<std::size_t, 64> touched{};  // intact bonds whose shear depends on the two disks
  double coupled = 0, weights = 0, dashpot = 0;
  std::size_t ev = 0;
  for (std::size_t b = first; b < m.num_bonds(); ++b) {
    if (!m.newly_broken[b]) continue;
    const double own_half = m.event_half[ev], d_len = m.event_d_len[ev];
    ++ev;
    const std::array<std::size_t, 2> disks{static_cast<std::size_t>(m.bi[b]), static_cast<std::size_t>(m.bj[b])};
    // The potential part of the release: every energy term that the break changes, before
    // and after. The two disks lose a neighbour, so their least-squares strain changes, and
    // with it the local-strain shear energy of their other bonds and their hoop and J2 terms.
    std::size_t count = 0;
    if (strains) {
      for (std::size_t i : disks)
        for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1] && count < touched.size(); ++k) {
          const auto c = m.adj_bond(k);
          if (c != b && m.bond_intact(c) &&
              std::find(touched.begin(), touched.begin() + count, c) == touched.begin() + count)
            touched[count++] = c;
        }
    }
    const auto own_energy = [&]() { return m.bond_intact(b) ? intact_bond_energy(m, b) : contact_bond_energy(m, b); };
    auto energy = [&]() {
      double e = own_energy();
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t c = touched[k];
        if (local && !m.yields(c) && m.ks(c) != 0) e += 0.5 * shear_factor(m, c) * m.ks(c) * m.u_s[c] * m.u_s[c];
      }
      for (std::size_t i : disks) {
        if (hoop) e += hoop_energy(m, i);
        if (m.any_j2 && m.j2.sigma_y[i] > 0) e += j2_correction_energy(m, i);
      }
      return e;
    };
    const double before = energy();
    const double own = intact_bond_energy(m, b);
    const bool starts_cracking = m.newly_broken[b] == kStartsCracking || m.newly_broken[b] == kStartsShearCracking;
    if (starts_cracking) {
      // It keeps its springs (they soften from now on) and leaves its disks' strain fits: its
      // row holds the crack that the pass started (BondCracks::starts, sorted by bond).
      const auto start = std::lower_bound(m.cracks.starts.begin(), m.cracks.starts.end(), static_cast<std::int64_t>(b),
                                          [](const CrackStart& c, std::int64_t bond) { return c.bond < bond; });
      HEXDEM_VERIFY(start != m.cracks.starts.end() && start->bond == static_cast<std::int64_t>(b),
                    "settle_broken_bonds: a crack start the force pass kept");
      Model::FailedBond& f = add_failed_row(m, b);
      f.crack = m.newly_broken[b] == kStartsShearCracking ? kShearCrack : kTensionCrack;
      f.delta0 = f.kappa = start->delta0;
      f.delta_f = start->delta_f;
    } else {
      // BondState = 1 + FailureMode; the contact's row starts at zero.
      mark_broken(m, b, static_cast<BondState>(m.newly_broken[b]));
      m.failed(b).break_time = m.time;
      m.failed(b).damage = 1.0;
      // The bond becomes a contact that starts now: no shear history, the normal force of
      // its overlap (a bond that breaks in compression keeps pushing).
      m.f_n[b] = m.f_s[b] = 0.0;
      if (!m.bond_plastic.alpha_n.empty()) m.bond_plastic.alpha_n[b] = m.bond_plastic.alpha_s[b] = 0.0;
      if (!m.u_s.empty()) m.u_s[b] = 0.0;  // the local-strain or softening shear measure
      broken_bond_contact(m, b, m.len_prev[b], m.nx[b], m.ny[b], dt, 0.0);
    }
    if (strains) {
      // The disks lose a neighbour: their fit (M^-1) changes, but not their strain. The fit
      // maps displacement increments to strain increments from now on; the strain the disk
      // has is carried over by an offset, eps = fit(u) - eps_off (docs/model.md, "Energy at
      // a break"). Re-fitting the strain to the remaining neighbours instead would change the
      // shear energy of the disks' other bonds by an amount of either sign, and a break
      // could release negative energy.
      for (std::size_t i : disks) {
        const double exx = m.strain.eps_xx[i], eyy = m.strain.eps_yy[i], exy = m.strain.eps_xy[i];
        const double hoop_before = hoop ? hoop_energy(m, i) : 0.0;
        // Its hoop term keeps only the square of the hoop stress from now on, A b s^2 / (2M)
        // (s = M eps_tt + lambda tr), less a constant that keeps the energy continuous. The
        // full term adds -A b lambda^2 tr^2 / (2M), which only a complete neighbourhood's
        // in-plane springs make up for: without them it is unbounded below (measured: a
        // rotated warhead's run stopped with a negative elastic energy when disks under the
        // nose that had lost bonds reached -1 J/rad of hoop energy).
        const auto restore_hoop = [&] {
          if (!hoop) return;
          m.hoop.cut[i] = 1;
          m.hoop.constant[i] += hoop_energy(m, i) - hoop_before;
        };
        // With no fit left (fewer than two independent bonds: M^-1 = 0) the same rule keeps
        // the strain frozen at its last value, eps = -eps_off. Clearing it instead changed the
        // shear energy of the disk's last bonds by an amount of either sign (a negative
        // release). A frozen strain is bounded below in every term: the shear springs are
        // squares, and the hoop term is cut to the hoop stress's square (restore_hoop); the
        // full term's coupling lambda eps_tt tr with a frozen tr was not (a detached disk
        // under a rotated warhead's nose reached -0.44 J/rad). The failure criteria read the
        // frozen strain as the disk's stress (softening_bond).
        update_strain_matrix(m, i);
        disk_strain(m, i);
        m.strain.eps_off_xx[i] += m.strain.eps_xx[i] - exx;
        m.strain.eps_off_yy[i] += m.strain.eps_yy[i] - eyy;
        m.strain.eps_off_xy[i] += m.strain.eps_xy[i] - exy;
        m.strain.eps_xx[i] = exx;
        m.strain.eps_yy[i] = eyy;
        m.strain.eps_xy[i] = exy;
        restore_hoop();
      }
      for (std::size_t k = 0; k < count && local; ++k) {
        const std::size_t c = touched[k];
        m.u_s[c] = local_shear(m, c);  // plastic springs keep their force: only the measure moves
        if (!m.yields(c)) m.f_s[c] = shear_factor(m, c) * m.ks(c) * m.u_s[c];
      }
      if (starts_cracking && local) {
        m.u_s[b] = local_shear(m, b);
        m.f_s[b] = m.ks(b) * m.u_s[b];
      }
      // J2 disks keep their plastic strain; the stress that the next plastic increment's work
      // starts from is the one after the break.
      if (m.any_j2)
        for (std::size_t i : disks)
          if (m.j2.sigma_y[i] > 0) store_j2_stress(m, i);
    }
    // The bond's own release: what its springs stored less their half step, the bilinear
    // form of the energy over the two steps (as for a damage step; >= 0 unless a measure
    // changed sign within the step), less what its contact keeps. The rest of the change is
    // the integrator's: the kinetic half step of the force changes of the other bonds (the
    // disks' fits change their gradients, not their energy) and the round-off of their energy.
    // The contact that replaces a bond broken in compression keeps the overlap's energy, in
    // the same form: its spring's energy less its half step, E_c - (dE_c/dL) dL / 2 with
    // dE_c/dL = -k_c overlap (its shear starts at 0).
    // A bond that starts to crack keeps its springs and releases nothing.
    double own_release = 0.0;
    if (!starts_cracking) {
      const double overlap = m.touch(b) - m.len_prev[b];
      const double kept = own_energy() + (overlap > 0 ? 0.5 * contact_normal_stiffness(m, b) * overlap * d_len : 0.0);
      own_release = std::max(own - own_half - kept, 0.0);
      // The new contact's dashpot force acts from t_n: its half step before t_n is dashpot
      // work (f_v, the dashpot's part of f_n, opposes the approach: >= 0).
      Model::FailedBond& c = m.failed(b);
      const double half_v = 0.5 * c.f_damp * d_len;
      c.damping_work += half_v;
      dashpot += half_v;
    }
    m.failed(b).fracture_energy += own_release;  // every event has its row (above)
    coupled += before - energy() - own_release;
    // The event's weight: the energy its springs stored (kept in order, one per event).
    m.event_weights.push_back(own);
    weights += own;
  }
  // The forces without the broken bonds, and the kinetic part of the release: leap-frog's
  // kinetic energy at t_n, v(t-dt/2).v(t+dt/2) / 2, holds half a step of the force at t_n,
  // so changing that force by dF changes it by (dt/2) v(t-dt/2).dF.
  if (energy_strains) compute_strain_conjugates(m, local, hoop);
  gather_forces(m, !local, energy_strains, hoop);
  const double kinetic = 0.5 * dt * deterministic_sum(
      m.num_disks(),
      [&](std::size_t i) {
        return m.vx[i] * (m.fx_intact[i] - m.fx[i]) + m.vy[i] * (m.fy_intact[i] - m.fy[i]) +
               m.omega[i] * (m.torque_intact[i] - m.torque[i]);
      },
      m.scratch);
  // The integrator's share of the pass's breaks (and the round-off of the neighbours' terms),
  // of either sign and O(dt), shared by the bonds in proportion to the energy each stored
  // (equally if none stored any): it is the pass's total only that is a property of the breaks.
  const double released = coupled + kinetic - dashpot;
  std::size_t event = 0, breaks = 0;
  for (std::size_t b = first; b < m.num_bonds(); ++b) {
    if (!m.newly_broken[b]) continue;
    breaks += m.newly_broken[b] != kStartsCracking && m.newly_broken[b] != kStartsShearCracking;
    m.newly_broken[b] = 0;
    const double w = m.event_weights[event++];
    m.failed(b).break_kinetic += weights > 0 ? released * (w / weights) : released / static_cast<double>(broken);
  }
  m.event_weights.clear();  // keep their capacity: no allocation once grown
  m.cracks.starts.clear();
  m.event_half.clear();
  m.event_d_len.clear();
  return breaks;
}

Stress disk_stress(const Model& m, std::size_t i) {
  // Love-Weber: sigma = 1/(A w) sum_c sym(x_c (x) f_c) with x_c = r n and f_c the force on i
  // (physics.md section 6); for either end of a bond this is r [f_n n n + f_s sym(n s)].
  Stress st;
  double sxx = 0, syy = 0, sxy = 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
    const auto b = m.adj_bond(k);
    const BondForce f = bond_force(m, b);
    if (f.f_n == 0.0 && f.f_s == 0.0) continue;
    const double nx = f.nx, ny = f.ny, sx = -ny, sy = nx;
    const double fn = f.f_n, fs = f.f_s;
    sxx += fn * nx * nx + fs * nx * sx;
    syy += fn * ny * ny + fs * ny * sy;
    sxy += fn * nx * ny + fs * 0.5 * (nx * sy + ny * sx);
  }
  // The bond to the mirror image (symmetry planes): tension -k u.N along N.
  if (m.has_mirror_springs()) {
    sxx -= m.mirror.kx[i] * m.ux[i] * m.mirror.sx[i];
    syy -= m.mirror.ky[i] * m.uy[i] * m.mirror.sy[i];
  }
  const double scale = m.radius[i] / (m.cell_area[i] * m.disk_weight(i));
  // Surface loads act on the disk at their own lever arms.
  const double ext = 1.0 / (m.cell_area[i] * m.disk_weight(i));
  st.xx = sxx * scale;
  st.yy = syy * scale;
  st.xy = sxy * scale;
  if (!m.ext_mxx.empty()) {  // allocated when the case has surface loads
    st.xx += m.ext_mxx[i] * ext;
    st.yy += m.ext_myy[i] * ext;
    st.xy += m.ext_mxy[i] * ext;
  }
  st.zz = m.hoop.nu_zz.empty() ? 0.0 : m.hoop.nu_zz[i] * (st.xx + st.yy);  // plane strain, isotropic only
  if (m.geometry == Geometry::Axisymmetric) {
    const HoopStress h = hoop_stress(m, i);
    st.zz = h.tt;
    // The hoop term's share of the in-plane stresses: d/d(eps_rr) of lambda eps_tt eps_rr.
    st.xx += h.in_plane;
    st.yy += h.in_plane;
  }
  if (m.any_j2 && m.j2.sigma_y[i] > 0) {
    // The plastic correction's share: -2 mu eps_p (tr(eps_p) = 0).
    const double c = -2 * m.hoop.mu[i];
    st.xx += c * m.j2.eps_p_xx[i];
    st.yy += c * m.j2.eps_p_yy[i];
    st.xy += c * m.j2.eps_p_xy[i];
    st.zz += c * m.j2.eps_p_33[i];
  }
  return st;
}

}  // namespace hexdem::solver
