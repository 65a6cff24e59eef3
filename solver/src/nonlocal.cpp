// Nonlocal strain of the softening criteria (docs/model.md, "Nonlocal criterion"): each
// disk's strain averaged over the disks of its body within the radius R of its material, with
// the bell-shaped weight (1 - d^2/R^2)^2 (Pijaudier-Cabot and Bazant 1987; Jirasek and
// Grassl 2008 found such averaging to remove most of the directional bias of cracks on
// regular meshes).
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include "hexdem/solver/model.hpp"

namespace hexdem::solver {
namespace {

/// Per body where `use(body)`, the reciprocals of its smallest static thresholds: the strengths
/// of its softening law times the smallest random-field factor of its bonds (the rate factors
/// only raise them), divided by the bond's stiffness factor (the criteria see the material's
/// stress times it: softening_bond). 0 where a threshold is not positive or the body is not
/// used: such a body's disks are always near a criterion.
template <class Use>
void criterion_thresholds(const Model& m, Use&& use, std::vector<double>& inv_ft, std::vector<double>& inv_fc,
                          std::vector<double>& inv_mc) {
  const std::size_t bodies = m.body_failure_law.size();
  std::vector<double> scale_min(bodies, std::numeric_limits<double>::infinity());
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    const auto body = static_cast<std::size_t>(m.body[static_cast<std::size_t>(m.bi[b])]);
    scale_min[body] = std::min(scale_min[body], m.strength_factor(b) / m.stiffness_factor(b));
  }
  inv_ft.assign(bodies, 0.0);
  inv_fc.assign(bodies, 0.0);
  inv_mc.assign(bodies, 0.0);
  for (std::size_t b = 0; b < bodies; ++b) {
    const std::int32_t l = m.body_failure_law[b];
    if (!use(b) || l < 0) continue;
    const SofteningParams& sp = m.softening[static_cast<std::size_t>(l)];
    const double s = std::isfinite(scale_min[b]) ? scale_min[b] : 1.0;
    const double ft = m.failure_laws[static_cast<std::size_t>(l)].f_t * s, fc = sp.mc.f_c * s;
    const double mc = sp.mc.c * sp.mc.cos_phi * s;
    if (ft > 0 && fc > 0 && mc > 0) {
      inv_ft[b] = 1 / ft;
      inv_fc[b] = 1 / fc;
      inv_mc[b] = 1 / mc;
    }
  }
}

}  // namespace

void build_nonlocal_strain(Model& m, const std::vector<double>& body_radius) {
  NonlocalStrain& nl = m.nonlocal;
  nl = NonlocalStrain{};
  const double r_max = body_radius.empty() ? 0.0 : *std::max_element(body_radius.begin(), body_radius.end());
  if (!(r_max > 0)) return;
  const std::size_t n = m.num_disks();
  // The disks whose strain enters an average: those with a full neighbourhood (six bonds in
  // the initial lattice and a fit), as for the local criterion (softening_bond).
  const auto full = [&](std::size_t j) { return m.strain.ok[j] && m.initial_bonds(j) == 6; };
  // A uniform grid of cell r_max over the reference centres.
  double xmin = 0, ymin = 0;
  if (n > 0) xmin = *std::min_element(m.x0.begin(), m.x0.end()), ymin = *std::min_element(m.y0.begin(), m.y0.end());
  const auto cell = [&](double x, double y) {
    return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(std::floor((x - xmin) / r_max)),
                                                 static_cast<std::int64_t>(std::floor((y - ymin) / r_max))};
  };
  const auto key = [](std::int64_t cx, std::int64_t cy) { return (cx << 32) ^ (cy & 0xffffffff); };
  std::unordered_map<std::int64_t, std::vector<std::int32_t>> grid;
  for (std::size_t j = 0; j < n; ++j)
    if (full(j) && body_radius[static_cast<std::size_t>(m.body[j])] > 0) {
      const auto [cx, cy] = cell(m.x0[j], m.y0[j]);
      grid[key(cx, cy)].push_back(static_cast<std::int32_t>(j));
    }
  nl.offset.assign(n + 1, 0);
  std::vector<std::pair<std::int32_t, double>> row;
  for (std::size_t i = 0; i < n; ++i) {
    const double radius = body_radius[static_cast<std::size_t>(m.body[i])];
    row.clear();
    if (!(radius > 0)) {
      // A body without averaging: the disk's own strain, as the local criterion reads it.
      if (full(i)) row.emplace_back(static_cast<std::int32_t>(i), 1.0);
    } else {
      const double r2 = radius * radius;
      const auto [cx, cy] = cell(m.x0[i], m.y0[i]);
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = grid.find(key(cx + dx, cy + dy));
          if (it == grid.end()) continue;
          for (const std::int32_t j : it->second) {
            const auto ju = static_cast<std::size_t>(j);
            if (m.body[ju] != m.body[i]) continue;
            const double ex = m.x0[ju] - m.x0[i], ey = m.y0[ju] - m.y0[i];
            const double q = 1 - (ex * ex + ey * ey) / r2;
            if (q > 0) row.emplace_back(j, q * q);
          }
        }
      // In index order, so that the sums do not depend on the grid's order.
      std::sort(row.begin(), row.end());
      double sum = 0;
      for (const auto& e : row) sum += e.second;
      for (auto& e : row) e.second /= sum;
    }
    for (const auto& e : row) nl.nbr.push_back(e.first), nl.w.push_back(e.second);
    nl.offset[i + 1] = static_cast<std::uint32_t>(nl.w.size());
  }
  nl.nbr.shrink_to_fit();
  nl.w.shrink_to_fit();
  for (auto* v : {&nl.eps_xx, &nl.eps_yy, &nl.eps_xy}) v->assign(n, 0.0);
  if (m.geometry == Geometry::Axisymmetric) nl.eps_tt.assign(n, 0.0);

  // The bound's grid (NonlocalStrain::hot) over every disk's reference centre.
  double xmax = xmin, ymax = ymin;
  for (std::size_t i = 0; i < n; ++i) xmax = std::max(xmax, m.x0[i]), ymax = std::max(ymax, m.y0[i]);
  nl.cells_x = static_cast<std::int64_t>(std::floor((xmax - xmin) / r_max)) + 1;
  nl.cells_y = static_cast<std::int64_t>(std::floor((ymax - ymin) / r_max)) + 1;
  nl.cell.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [cx, cy] = cell(m.x0[i], m.y0[i]);
    nl.cell[i] = static_cast<std::int32_t>(cy * nl.cells_x + cx);
  }
  nl.relative.assign(n, 0.0);
  nl.packed.assign(4 * n, 0.0);
  nl.cell_max.assign(static_cast<std::size_t>(nl.cells_x * nl.cells_y), 0.0);
  nl.hot.assign(nl.cell_max.size(), 0);
  criterion_thresholds(m, [&](std::size_t b) { return body_radius[b] > 0; }, nl.body_inv_ft, nl.body_inv_fc,
                       nl.body_inv_mc);
}

void build_local_criterion(Model& m) {
  LocalCriterion& lc = m.local_criterion;
  lc = LocalCriterion{};
  if (!m.any_softening || !m.nonlocal.offset.empty()) return;
  // The bodies whose bonds go through softening_bond (bond_forces): a law with G_F > 0.
  const auto softening = [&](std::size_t b) {
    const std::int32_t l = m.body_failure_law[b];
    return l >= 0 && m.softening[static_cast<std::size_t>(l)].G_F > 0;
  };
  std::vector<double> inv_ft, inv_fc, inv_mc;
  criterion_thresholds(m, softening, inv_ft, inv_fc, inv_mc);
  lc.body.assign(inv_ft.size(), {});
  for (std::size_t b = 0; b < lc.body.size(); ++b) {
    if (!(inv_ft[b] > 0)) continue;  // no bound: far_below stays -infinity
    const SofteningParams& sp = m.softening[static_cast<std::size_t>(m.body_failure_law[b])];
    LocalCriterion::Body& p = lc.body[b];
    p.lambda2 = sp.lambda2, p.lambda3 = sp.lambda3, p.mu = sp.mu, p.sin_phi = sp.mc.sin_phi;
    p.inv_ft = inv_ft[b], p.inv_fc = inv_fc[b], p.inv_mc = inv_mc[b];
    p.inv_max = std::max({p.inv_ft, p.inv_fc, p.inv_mc});
    p.moduli = std::abs(sp.lambda2) + std::abs(sp.lambda3) + 2 * std::abs(sp.mu);
    p.far_below = 1 - LocalCriterion::kMargin;
  }
  lc.disk.assign(m.num_disks(), 2);
}

}  // namespace hexdem::solver

