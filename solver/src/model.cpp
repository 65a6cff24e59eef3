// Model construction: masses, springs and adjacency from a lattice.
// Ref: Liu, Gao, Tanimura (2004), Eqs. 6-15; physics.md sections 1, 3, 4, 10.
#include "hexdem/solver/model.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <type_traits>
#include <utility>

#include "hexdem/error.hpp"

namespace hexdem::solver {
namespace {

/// A bond's reference geometry from its reference vector a and its length |a|: the unit
/// vector n0 and g = (|a|/2) sym(s0 (x) n0), s0 = (-n0_y, n0_x) (physics.md section 4).
struct BondReference {
  double rest, g_xx, g_yy, g_xy;
};
BondReference bond_reference(double ax, double ay, double rest) {
  const double nx = ax / rest, ny = ay / rest;
  const double sx = -ny, sy = nx, half = 0.5 * rest;
  return {rest, half * sx * nx, half * sy * ny, half * 0.5 * (sx * ny + sy * nx)};
}

/// The model from the lattice's other arrays, with its disk and bond arrays already in m (the
/// centres, radii, cell areas, kinds, bodies, materials, bond ends and classes: copied or taken).
Model build(const meshing::Lattice& lat, Model m, Geometry geometry, double thickness, ShearModel shear_model,
            const std::vector<BodyMaterial>& materials) {
  const bool axisym = geometry == Geometry::Axisymmetric;
  HEXDEM_VERIFY(axisym == (lat.mode == meshing::GeometryMode::Axisymmetric),
                "lattice and case disagree on axisymmetry");
  m.geometry = geometry;
  m.shear_model = shear_model;
  m.thickness = thickness;

  const std::size_t n = m.x0.size();
  // Arrays of the features a case uses only (docs/benchmarks.md, "Memory"): the surface
  // loads' forces and lever arms and the mirror springs are allocated by the Solver when the case has
  // them, the local-strain arrays below when some term needs the disks' strains, and the
  // bonds' plasticity and failure arrays when a material yields or breaks.
  for (auto* v : {&m.ux, &m.uy, &m.vx, &m.vy, &m.theta, &m.omega, &m.fx, &m.fy, &m.torque,
                  &m.mass, &m.vx_old, &m.vy_old, &m.omega_old}) {
    v->assign(n, 0.0);
  }
  if (axisym) m.weight.assign(n, 0.0);  // plane models: w = thickness (Model::disk_weight)
  // The out-of-plane constants only for the geometries and materials that have the term: the
  // hoop strain of every ring (axisymmetric), the J2 disks' zz eigenstrain (plane strain), and
  // sigma_zz = nu (sxx + syy) of the isotropic materials in plane strain.
  bool out_of_plane = axisym, plane_strain_nu = false;
  for (const BodyMaterial& bm : materials) {
    const bool ps = geometry == Geometry::PlaneStrain;
    out_of_plane = out_of_plane || (ps && bm.j2 && bm.material->plastic());
    plane_strain_nu = plane_strain_nu || (ps && bm.material->isotropic);
  }
  if (out_of_plane) {
    m.hoop.lambda.assign(n, 0.0);
    m.hoop.mu.assign(n, 0.0);
  }
  if (plane_strain_nu) m.hoop.nu_zz.assign(n, 0.0);
  m.constraint.assign(n, 0);
  // mirror.plane: allocated by the Solver if the case has a mirror plane (Model::on_mirror).

  // Mass from the cell area (physics.md section 1): m = rho A w, w = thickness (plane) or the
  // ring radius b of the cell centroid (axisymmetric, per radian); I = m r^2 / 2 is
  // recomputed where it is needed (Model::disk_inertia).
  for (std::size_t i = 0; i < n; ++i) {
    const BodyMaterial& bm = materials.at(static_cast<std::size_t>(m.body[i]));
    const double w = axisym ? lat.cell_cx[i] : thickness;
    if (axisym) m.weight[i] = w;
    m.mass[i] = bm.material->density * m.cell_area[i] * w;
    if (geometry == Geometry::PlaneStrain && bm.material->isotropic) m.hoop.nu_zz[i] = bm.material->nu;
    // The out-of-plane term: the hoop strain of every ring (axisymmetric), and in plane
    // strain the J2 disks, whose plastic eigenstrain has a zz component.
    const bool j2 = bm.j2 && bm.material->plastic();
    if (axisym || (j2 && geometry == Geometry::PlaneStrain)) {
      m.hoop.lambda[i] = bm.material->lame_lambda();
      m.hoop.mu[i] = bm.material->lame_mu();
    }
    if (j2) {
      HEXDEM_VERIFY(geometry != Geometry::PlaneStress && shear_model == ShearModel::LocalStrain,
                    "J2 plasticity needs plane strain or axisymmetry and the local-strain shear model");
      if (!m.any_j2) {
        m.any_j2 = true;
        for (auto* v : {&m.j2.sigma_y, &m.j2.h, &m.j2.eps_p_xx, &m.j2.eps_p_yy, &m.j2.eps_p_xy, &m.j2.eps_p_33, &m.j2.beta_xx,
                        &m.j2.beta_yy, &m.j2.beta_xy, &m.j2.beta_33, 
                        &m.j2.eps_p_eq, &m.j2.sig_xx, &m.j2.sig_yy, &m.j2.sig_xy, &m.j2.sig_33, &m.j2.work}) {
          v->assign(n, 0.0);
        }
      }
      // Prager's rule beta = (2/3) H eps_p with H the plastic modulus of the uniaxial
      // stress-strain curve of tangent E_t: 1/E_t = 1/E + 1/H.
      const double E = bm.material->E, Et = bm.material->tangent_modulus;
      if (bm.material->plasticity == PlasticityModel::DruckerPrager) {
        const Material::DruckerPragerCone dp = bm.material->drucker_prager();
        if (m.j2.alpha.empty()) m.j2.alpha.assign(n, 0.0);  // only with a Drucker-Prager material
        m.j2.sigma_y[i] = dp.k;
        m.j2.alpha[i] = dp.alpha;
      } else {
        m.j2.sigma_y[i] = bm.material->yield_stress;
      }
      m.j2.h[i] = E * Et / (E - Et);
    }
  }

  // Bonds: Eqs. 12-14 per unit thickness, times the thickness or, in axisymmetric mode, the
  // bond midpoint's distance from the axis (Eq. 15).
  const std::size_t nb = m.bi.size();
  m.f_s.assign(nb, 0.0);
  // Spring stiffnesses once per kind (body, bond direction, edge) where w is uniform (plane
  // geometries, and at most 256 kinds); per bond where it is the ring radius.
  const std::size_t kinds = 12 * materials.size();
  const bool per_kind = !axisym && kinds <= 256;
  if (per_kind) {
    m.spring_kind.assign(nb, 0);
    m.kind_k_n.assign(kinds, 0.0);
    m.kind_k_s.assign(kinds, 0.0);
  } else {
    m.k_n.assign(nb, 0.0);
    m.k_s.assign(nb, 0.0);
  }
  bool plastic_springs = false, breakable = false;
  for (const BodyMaterial& bm : materials) {
    plastic_springs = plastic_springs || (bm.material->plastic() && !bm.j2);
    breakable = breakable || bm.material->breakable;
  }
  // The length at the last force pass: for the hardening springs' and the failure law's
  // increments, and the contacts of broken bonds.
  if (plastic_springs || breakable) m.len_prev.assign(nb, 0.0);
  if (plastic_springs)
    for (auto* v : {&m.bond_plastic.f_yield, &m.bond_plastic.kh_n, &m.bond_plastic.kh_s, &m.bond_plastic.alpha_n, &m.bond_plastic.alpha_s, &m.bond_plastic.work}) v->assign(nb, 0.0);
  if (breakable) {
    m.failed_row.assign(nb, -1);  // the cracked and broken bonds' rows (Model::failed)
    // Per bond where the springs are (axisymmetric); otherwise recomputed (Model::bond_section).
    if (m.spring_kind.empty()) m.section.assign(nb, 0.0);
    m.body_mu.assign(materials.size(), 0.0);
    m.body_failure_law.assign(materials.size(), -1);
    for (std::size_t k = 0; k < materials.size(); ++k) {
      m.body_mu[k] = materials[k].material->friction;
      if (materials[k].material->breakable) m.body_failure_law[k] = static_cast<std::int32_t>(k);
    }
    m.newly_broken.assign(nb, 0);
  }
  for (const BodyMaterial& bm : materials) {
    laws::MohrCoulombFailure law;
    if (bm.material->breakable) {
      law.f_t = bm.material->tensile_strength;
      law.f_c = bm.material->compressive_strength;
      law.c = bm.material->cohesion;
      law.phi = bm.material->friction_angle;
      law.rate_dependent = bm.material->rate_dependent;
    }
    m.failure_laws.push_back(law);
    m.failure_tan_phi.push_back(law.tan_phi());
    // Softening: the continuum stress of the criteria from the disks' strains, with the
    // in-plane Lame constants of the geometry (plane stress condenses sigma_zz = 0).
    SofteningParams sp;
    const Material& mat = *bm.material;
    if (mat.breakable && mat.fracture_energy > 0) {
      sp.G_F = mat.fracture_energy;
      sp.mu = mat.lame_mu();
      sp.lambda3 = mat.lame_lambda();
      sp.lambda2 = geometry == Geometry::PlaneStress ? 2 * sp.lambda3 * sp.mu / (sp.lambda3 + 2 * sp.mu) : sp.lambda3;
      sp.radial_cracks = mat.radial_cracks;
      sp.shear = mat.shear_softening;
      if (mat.damage_band > 0)
        sp.damage_kf = 2 * mat.fracture_energy * mat.E / (mat.tensile_strength * mat.tensile_strength * mat.damage_band);
      const double phi = mat.friction_angle * 0.017453292519943295;
      sp.mc = {mat.cohesion, std::sin(phi), std::cos(phi), mat.compressive_strength};
      m.any_softening = true;
    }
    m.softening.push_back(sp);
  }
  // The disks' strains: for the local-strain shear springs, the hoop term, J2 disks and the
  // softening criteria; a rotation-model plane run without softening needs none of them.
  m.uses_strains = shear_model == ShearModel::LocalStrain || axisym || m.any_j2 || m.any_softening;
  if (m.uses_strains) {
    for (auto* v : {&m.strain.minv_xx, &m.strain.minv_xy, &m.strain.minv_yy, &m.strain.eps_xx, &m.strain.eps_yy, &m.strain.eps_xy, &m.strain.w_xx, &m.strain.w_xy, &m.strain.w_yx,
                    &m.strain.w_yy})
      v->assign(n, 0.0);
    if (axisym) m.strain.eps_tt.assign(n, 0.0);
  }
  // The spring kinds, 12 body + 4 direction + 2 sense + edge (direction 0 along the lattice
  // axis, 1 and 2 the other two; sense 0 along the first bond of the direction), and the
  // reference geometry once per kind if every bond's a = x0_j - x0_i is its kind's to 1e-12 |a|
  // (a regular plane lattice), else per bond (Model::rest_length).
  if (per_kind) {
    std::vector<double>* tables[] = {&m.kind_ax, &m.kind_ay, &m.kind_rest, &m.kind_g_xx, &m.kind_g_yy, &m.kind_g_xy};
    for (auto* v : tables) v->assign(kinds, 0.0);
    std::vector<std::uint8_t> seen(kinds, 0);
    bool regular = true;
    double dx[3] = {0, 0, 0}, dy[3] = {0, 0, 0};  // the first bond's direction of each
    for (std::size_t b = 0; b < nb; ++b) {
      const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
      const double ax = m.x0[j] - m.x0[i], ay = m.y0[j] - m.y0[i];
      const double len = std::hypot(ax, ay), nx = ax / len, ny = ay / len;
      int direction = 0;
      if (m.bond_class[b] != 1) {
        if (dx[1] == 0 && dy[1] == 0) dx[1] = nx, dy[1] = ny;
        direction = std::abs(nx * dy[1] - ny * dx[1]) < 0.5 ? 1 : 2;  // 0 or 60 degrees from the first
      }
      if (dx[direction] == 0 && dy[direction] == 0) dx[direction] = nx, dy[direction] = ny;
      const int sense = nx * dx[direction] + ny * dy[direction] > 0 ? 0 : 1;
      const auto kind = static_cast<std::size_t>(12 * m.body[i] + 4 * direction + 2 * sense + (lat.bond_on_edge[b] ? 1 : 0));
      m.spring_kind[b] = static_cast<std::uint8_t>(kind);
      if (!regular) continue;
      if (!seen[kind]) {
        seen[kind] = 1;
        // The kind's first bond's a; |a| by the bond pass's arithmetic (bond_geometry at rest).
        const BondReference r = bond_reference(ax, ay, std::sqrt(ax * ax + ay * ay));
        m.kind_ax[kind] = ax;
        m.kind_ay[kind] = ay;
        m.kind_rest[kind] = r.rest;
        m.kind_g_xx[kind] = r.g_xx;
        m.kind_g_yy[kind] = r.g_yy;
        m.kind_g_xy[kind] = r.g_xy;
      } else if (!(std::abs(ax - m.kind_ax[kind]) <= 1e-12 * len && std::abs(ay - m.kind_ay[kind]) <= 1e-12 * len)) {
        regular = false;
      }
    }
    if (!regular) {
      for (auto* v : tables) std::vector<double>().swap(*v);
    } else if (!m.uses_strains) {
      for (auto* v : {&m.kind_g_xx, &m.kind_g_yy, &m.kind_g_xy}) std::vector<double>().swap(*v);
    }
  }
  if (m.kind_rest.empty()) {
    m.rest_length.assign(nb, 0.0);
    if (m.uses_strains)
      for (auto* v : {&m.g_xx, &m.g_yy, &m.g_xy}) v->assign(nb, 0.0);
  }
  if (m.any_softening) {
    if (axisym)
      for (auto* v : {&m.hoop_cracks.damage, &m.hoop_cracks.kappa, &m.hoop_cracks.e0, &m.hoop_cracks.ef, &m.hoop_cracks.fracture, &m.hoop_cracks.e_last, &m.hoop_cracks.break_kinetic}) v->assign(n, 0.0);
  }
  m.state.assign(nb, static_cast<std::uint8_t>(BondState::Intact));
  for (std::size_t b = 0; b < nb; ++b) {
    const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
    if (!m.rest_length.empty()) {
      const double ax = m.x0[j] - m.x0[i], ay = m.y0[j] - m.y0[i];
      const BondReference r = bond_reference(ax, ay, std::hypot(ax, ay));
      m.rest_length[b] = r.rest;
      if (m.uses_strains) {
        m.g_xx[b] = r.g_xx;
        m.g_yy[b] = r.g_yy;
        m.g_xy[b] = r.g_xy;
      }
    }
    if (!m.touch_at_rest && std::abs(m.rest(b) - (m.radius[i] + m.radius[j])) > 1e-9 * (m.radius[i] + m.radius[j]))
      m.touch_at_rest = true;
    const SpringConstants& K = materials.at(static_cast<std::size_t>(m.body[i])).springs;
    // A bond along a neat edge (two semi-disks) has half a bond's area in the region: half
    // its stiffness, so that the lattice energy under a homogeneous strain is the
    // continuum's right up to the edge.
    double ring = axisym ? lat.bond_b[b] : 0.0;
    if (axisym && lat.bond_on_edge[b] && !(ring > 1e-9 * m.radius[i])) {
      // A bond along the axis (two semi-disks on r = 0, a rotated lattice's bond direction):
      // its midpoint has no ring radius, yet the half of its area inside the region does.
      // Weigh it by that half's centroid, r / (3 sqrt 3) from the axis (the half rhombus
      // of half-width r / sqrt 3), not by 0: with 0 (or the -1e-20 that round-off gives) its
      // springs and strengths vanished or turned negative, and every such bond broke in
      // tension at t = 0.
      ring = m.radius[i] / (3.0 * 1.7320508075688772935);
    }
    const double w = (axisym ? ring : thickness) * (lat.bond_on_edge[b] ? 0.5 : 1.0);
    const bool axis_class = m.bond_class[b] == 1;
    const double kn = (axis_class ? K.kn1 : K.kn2) * w, ks = (axis_class ? K.ks1 : K.ks2) * w;
    if (per_kind) {
      const std::size_t kind = m.spring_kind[b];
      HEXDEM_ASSERT(m.kind_k_n[kind] == 0.0 || (m.kind_k_n[kind] == kn && m.kind_k_s[kind] == ks),
                    "bonds of one spring kind with different stiffnesses");
      m.kind_k_n[kind] = kn;  // the same value for every bond of the kind
      m.kind_k_s[kind] = ks;
    } else {
      m.k_n[b] = kn;
      m.k_s[b] = ks;
    }
    if (!m.len_prev.empty()) m.len_prev[b] = m.rest(b);
    // Strengths and yield forces act on the bond's section 2r w (Eq. 19, physics.md 7).
    const BodyMaterial& bm = materials.at(static_cast<std::size_t>(m.body[i]));
    const double section = 2.0 * m.radius[i] * w;
    if (!m.section.empty()) m.section[b] = section;
    HEXDEM_ASSERT(!breakable || m.bond_section(b) == section, "Model::bond_section disagrees with the build's section");
    if (bm.material->breakable) m.any_breakable = true;
    if (bm.material->plastic() && !bm.j2) {
      // Hardening springs: section 3 with E_t in place of E, i.e. k E_t / E.
      const double ratio = bm.material->tangent_modulus / bm.material->E;
      m.bond_plastic.f_yield[b] = bm.material->yield_stress * section;
      m.bond_plastic.kh_n[b] = kn * ratio;
      m.bond_plastic.kh_s[b] = ks * ratio;
      m.any_plastic = true;
    }
  }
  // An elastic lattice's gather reads the pair force; the laws read f_n and n back.
  if (m.elastic_lattice()) {
    for (auto* v : {&m.pair_fx, &m.pair_fy}) v->assign(nb, 0.0);
  } else {
    for (auto* v : {&m.f_n, &m.nx, &m.ny}) v->assign(nb, 0.0);
  }
  // The shear displacement is read back by the plastic, failure and J2 laws (bond_forces,
  // settle_broken_bonds); an elastic lattice's shear force is k_s u_s and keeps no u_s.
  if (m.uses_strains && (m.any_plastic || m.any_breakable || m.any_softening || m.any_j2)) m.u_s.assign(nb, 0.0);
  // Plane models: the bond's class is in its spring kind (Model::bond_class_of), if every
  // class is one of the two.
  if (per_kind && std::all_of(m.bond_class.begin(), m.bond_class.end(), [](std::uint8_t c) { return c == 1 || c == 2; }))
    std::vector<std::uint8_t>().swap(m.bond_class);

  // Adjacency: incident bonds of each disk in ascending bond order (a fixed summation order).
  // The adjacency's indices are 32-bit: 2 x bonds < 2^31 (about 350 million disks).
  if (2 * nb >= (std::size_t{1} << 31))
    throw InputError("the lattice has " + std::to_string(nb) + " bonds; hexdem handles at most 1073741823 (about 350 million "
                     "disks): use a larger [mesh] radius or a smaller region");
  // Counted, summed and filled in adj_offset itself (no work arrays: they were 8 bytes per
  // disk of the set-up's peak): after the fill, entry i + 1 holds where row i + 1 begins.
  m.adj_offset.assign(n + 1, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    ++m.adj_offset[static_cast<std::size_t>(m.bi[b]) + 1];
    ++m.adj_offset[static_cast<std::size_t>(m.bj[b]) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) m.adj_offset[i + 1] += m.adj_offset[i];
  m.adj_entry.assign(2 * nb, 0);
  for (std::size_t b = 0; b < nb; ++b) {  // row i's next free entry in adj_offset[i]
    const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
    m.adj_entry[m.adj_offset[i]++] = static_cast<std::int32_t>(b);   // i is the bond's bi
    m.adj_entry[m.adj_offset[j]++] = ~static_cast<std::int32_t>(b);  // j is its bj (Model::adj_other)
  }
  for (std::size_t i = n; i > 0; --i) m.adj_offset[i] = m.adj_offset[i - 1];  // back to the rows' starts
  m.adj_offset[0] = 0;
  if (m.any_breakable) {
    for (auto* v : {&m.fx_intact, &m.fy_intact, &m.torque_intact}) v->assign(n, 0.0);
    if (m.uses_strains)  // the strain carried across a change of fit
      for (auto* v : {&m.strain.eps_off_xx, &m.strain.eps_off_yy, &m.strain.eps_off_xy}) v->assign(n, 0.0);
    if (axisym) {
      m.hoop.cut.assign(n, 0);
      m.hoop.constant.assign(n, 0.0);
    }
  }
  // Disks with a local strain of their own: eliminate those whose fit over the remaining
  // ones is singular until none is left (a chain of lone disks goes in a few rounds).
  m.strain.ok.assign(n, 1);
  for (bool changed = m.uses_strains; changed;) {
    update_strain_matrices(m);
    changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (m.strain.ok[i] && m.strain.minv_xx[i] == 0 && m.strain.minv_yy[i] == 0) {
        m.strain.ok[i] = 0;
        changed = true;
      }
    }
  }
  return m;
}

/// Moves (Take) or copies the lattice's disk and bond arrays into a model.
template <bool Take, class L>
Model disk_and_bond_arrays(L& lat) {
  Model m;
  auto give = [](auto& to, auto& from) {
    if constexpr (Take) {
      to = std::move(from);
      std::remove_reference_t<decltype(from)>().swap(from);
      to.shrink_to_fit();  // the generator grew them by push_back (bonds: about 1.4x the size)
    } else {
      to = from;
    }
  };
  give(m.x0, lat.x);
  give(m.y0, lat.y);
  give(m.radius, lat.radius);
  give(m.cell_area, lat.cell_area);
  give(m.kind, lat.kind);
  give(m.body, lat.body);
  // The material is the body's (Lattice::material): kept per body (Model::disk_material).
  std::int32_t bodies = 0;
  for (std::int32_t b : m.body) bodies = std::max(bodies, b + 1);
  m.body_material.assign(static_cast<std::size_t>(bodies), -1);
  for (std::size_t i = 0; i < m.body.size(); ++i) {
    std::int32_t& bm = m.body_material[static_cast<std::size_t>(m.body[i])];
    HEXDEM_VERIFY(bm < 0 || bm == lat.material[i], "disks of one body with different materials");
    bm = lat.material[i];
  }
  if constexpr (Take) std::vector<std::int32_t>().swap(lat.material);
  give(m.bi, lat.bond_i);
  give(m.bj, lat.bond_j);
  give(m.bond_class, lat.bond_class);
  return m;
}

}  // namespace

Model build_model(const meshing::Lattice& lattice, Geometry geometry, double thickness, ShearModel shear_model,
                  const std::vector<BodyMaterial>& materials) {
  return build(lattice, disk_and_bond_arrays<false>(lattice), geometry, thickness, shear_model, materials);
}

Model build_model(meshing::Lattice&& lattice, Geometry geometry, double thickness, ShearModel shear_model,
                  const std::vector<BodyMaterial>& materials) {
  Model m = disk_and_bond_arrays<true>(lattice);
  return build(lattice, std::move(m), geometry, thickness, shear_model, materials);
}

void reset_force_history(Model& m) {
  for (auto* v : {&m.f_n, &m.f_s, &m.u_s, &m.bond_plastic.alpha_n, &m.bond_plastic.alpha_s}) std::fill(v->begin(), v->end(), 0.0);
  // A bond that cracked or broke has a row: its disks' fits change back.
  const bool broke = !m.failed_rows.empty() || std::any_of(m.state.begin(), m.state.end(), [](std::uint8_t s) { return s > 1; });
  m.failed_rows.clear();
  std::fill(m.failed_row.begin(), m.failed_row.end(), -1);
  m.cracks.starts.clear();
  for (std::size_t b = 0; b < m.len_prev.size(); ++b) m.len_prev[b] = m.rest(b);
  std::fill(m.state.begin(), m.state.end(), static_cast<std::uint8_t>(BondState::Intact));
  std::fill(m.newly_broken.begin(), m.newly_broken.end(), 0);
  std::fill(m.hoop.cut.begin(), m.hoop.cut.end(), 0);
  for (auto* v : {&m.hoop.constant, &m.strain.eps_off_xx, &m.strain.eps_off_yy, &m.strain.eps_off_xy, &m.hoop_cracks.damage, &m.hoop_cracks.kappa, &m.hoop_cracks.e0, &m.hoop_cracks.ef, &m.hoop_cracks.e_last}) {
    std::fill(v->begin(), v->end(), 0.0);
  }
  for (auto* v : {&m.j2.eps_p_xx, &m.j2.eps_p_yy, &m.j2.eps_p_xy, &m.j2.eps_p_33, &m.j2.beta_xx, &m.j2.beta_yy, &m.j2.beta_xy,
                  &m.j2.beta_33, &m.j2.eps_p_eq, &m.j2.sig_xx, &m.j2.sig_yy, &m.j2.sig_xy, &m.j2.sig_33}) {
    std::fill(v->begin(), v->end(), 0.0);
  }
  if (broke) update_strain_matrices(m);
}

Model::FailedBond& add_failed_row(Model& m, std::size_t b) {
  if (m.failed_row[b] < 0) {
    m.failed_row[b] = static_cast<std::int32_t>(m.failed_rows.size());
    m.failed_rows.emplace_back();  // grows with the failures only: amortised, not per step
  }
  return m.failed(b);
}

void mark_broken(Model& m, std::size_t b, BondState s) {
  HEXDEM_VERIFY(static_cast<std::uint8_t>(s) > 1 && !m.failed_row.empty(), "mark_broken: a breakable bond and a broken state");
  m.state[b] = static_cast<std::uint8_t>(s);
  add_failed_row(m, b);
}

void reset_bond_history(Model& m) {
  reset_force_history(m);
  // The cumulative energies kept per bond and disk (the failed bonds' rows went with the
  // force history).
  for (auto* v : {&m.bond_plastic.work, &m.hoop_cracks.fracture, &m.hoop_cracks.break_kinetic, &m.j2.work})
    std::fill(v->begin(), v->end(), 0.0);
}

void update_strain_matrix(Model& m, std::size_t i) {
  if (!m.uses_strains) return;
  double sxx = 0, sxy = 0, syy = 0;
  for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
    const auto b = m.adj_bond(k);
    if (!m.bond_in_fit(b) || !m.strain.ok[m.adj_other(i, k)]) continue;
    const double ax = m.adj_ax(i, k), ay = m.adj_ay(i, k);
    sxx += ax * ax;
    sxy += ax * ay;
    syy += ay * ay;
  }
  // A disk with fewer than two independent bonds has no local strain, nor has one whose bonds
  // nearly line up: det / (sxx + syy)^2 = sum over pairs of sin^2 of their angle, over the
  // bond count squared (equal lengths), is 0 or at least 1/6 for any bonds of a regular
  // lattice (two at 60 degrees: 3/16); on an irregular lattice ([mesh] jitter) two bonds a
  // few degrees off a line would give a fit whose inverse, and with it the shear springs'
  // stiffness, grows as 1 / angle^2, far beyond the critical step's. 1/10 keeps every fit of
  // a regular lattice and refuses two bonds closer than 39 degrees to a line.
  const double det = sxx * syy - sxy * sxy;
  const double scale = sxx + syy;
  if (det > 0.1 * scale * scale) {
    m.strain.minv_xx[i] = syy / det;
    m.strain.minv_yy[i] = sxx / det;
    m.strain.minv_xy[i] = -sxy / det;
  } else {
    m.strain.minv_xx[i] = m.strain.minv_yy[i] = m.strain.minv_xy[i] = 0.0;
  }
}

void update_strain_matrices(Model& m) {
  const auto n = static_cast<std::ptrdiff_t>(m.num_disks());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) update_strain_matrix(m, static_cast<std::size_t>(i));
}

}  // namespace hexdem::solver
