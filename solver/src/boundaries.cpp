// Boundary conditions on the disks of the lattice's sets (held components, prescribed
// velocities, symmetry planes and their mirror springs), surface loads (Eqs. 21, 23), the
// reactions of the sets and the initial velocities.
#include "hexdem/solver/solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/point_clusters.hpp"
#include "hexdem/solver/boundary_checks.hpp"

#include "solver_text.hpp"

namespace hexdem::solver {

namespace {

/// Whether a condition on a boundary set acts on the disk of set entry e: only disks whose
/// centre lies closer than their radius to the edge are held (on a symmetry plane that runs
/// across the lattice rows, the disks one radius off it must stay free).
bool held_by_set(const meshing::Lattice& lattice, std::int64_t e, double radius) {
  return lattice.set_distance[static_cast<std::size_t>(e)] < (1 - 1e-6) * radius;
}

/// The parts of boundary set s: its members grouped by where their set edges lie, two members
/// in one part when their edges' centres are within 3 (r_i + r_j) of each other (neighbouring
/// cells along an edge lie about 2r apart; a set named on two separate edges, such as a beam's
/// two supports, has two parts). Returns the part of each of the set's entries, numbered from 0
/// in order of first appearance, and sets `parts` to their number.
std::vector<std::size_t> set_parts(const meshing::Lattice& lattice, const std::vector<double>& radius, int s,
                                   std::size_t& parts) {
  const auto first = static_cast<std::size_t>(lattice.set_offset[static_cast<std::size_t>(s)]);
  const auto n = static_cast<std::size_t>(lattice.set_offset[static_cast<std::size_t>(s) + 1]) - first;
  const auto r_of = [&](std::size_t k) { return radius[static_cast<std::size_t>(lattice.set_disk[first + k])]; };
  struct Point {
    double x, y;
  };
  const auto point = [&](std::size_t k) { return Point{lattice.set_cx[first + k], lattice.set_cy[first + k]}; };
  double r_max = 0;
  for (std::size_t k = 0; k < n; ++k) r_max = std::max(r_max, r_of(k));
  // Linked members lie within 3 (r_k + r_j) <= 6 r_max of each other: cells of that side.
  return meshing::cluster_points(
      n, point, r_max > 0 ? 6 * r_max : 1.0,
      [&](std::size_t k, std::size_t j) {
        return std::hypot(point(k).x - point(j).x, point(k).y - point(j).y) <= 3 * (r_of(k) + r_of(j));
      },
      parts);
}

/// The velocity components (kFixX, kFixY) a boundary condition holds on its disks.
std::uint8_t held_components(const BoundaryCondition& bc) {
  switch (bc.kind) {
    case BoundaryCondition::Kind::Fixed:
      return kFixX | kFixY;
    case BoundaryCondition::Kind::Roller:
    case BoundaryCondition::Kind::Symmetry:
      return bc.component == 0 ? kFixX : kFixY;
    case BoundaryCondition::Kind::Velocity:
      return static_cast<std::uint8_t>((bc.velocity[0] ? kFixX : 0) | (bc.velocity[1] ? kFixY : 0));
  }
  return 0;
}

const char* boundary_kind_name(BoundaryCondition::Kind k) {
  switch (k) {
    case BoundaryCondition::Kind::Fixed: return "fixed";
    case BoundaryCondition::Kind::Roller: return "roller";
    case BoundaryCondition::Kind::Symmetry: return "symmetry";
    case BoundaryCondition::Kind::Velocity: return "velocity";
  }
  return "?";
}

}  // namespace

using detail::fmt;

void Solver::setup_boundaries() {
  const std::size_t n = model_.num_disks();
  std::vector<std::int32_t> owner(n, -1);  // the velocity set that prescribes each disk
  // Per disk and velocity component, the [[boundary]] entry that holds it at zero (fixed,
  // roller, symmetry) and the one that prescribes it (velocity), for the refusal of
  // contradictory conditions (docs/case-format.md, "Conditions on the same disks").
  // Kept for the sets' disks only (a map: per-disk arrays were 16 bytes per disk of the
  // set-up's peak memory for the few per cent of the disks that sets hold).
  struct Holders {
    std::array<std::int32_t, 2> zero{-1, -1}, velocity{-1, -1};
  };
  std::unordered_map<std::size_t, Holders> holders;
  const auto contradiction = [&](std::int32_t a, std::int32_t b, int c, std::size_t i, const char* why) {
    const BoundaryCondition& first = case_.boundaries[static_cast<std::size_t>(a)];
    const BoundaryCondition& second = case_.boundaries[static_cast<std::size_t>(b)];
    const bool axi = case_.geometry == Geometry::Axisymmetric;
    const std::string comp = c == 0 ? (axi ? "r" : "x") : (axi ? "z" : "y");
    return InputError(second.where + ": " + boundary_kind_name(second.kind) + " condition on set '" + second.set +
                      "' contradicts " + first.where + " (" + boundary_kind_name(first.kind) + " on set '" +
                      first.set + "') in the " + comp + " velocity component of the disk at (" +
                      fmt(model_.x0[i]) + ", " + fmt(model_.y0[i]) + ") m: " + why +
                      "; remove one of them or split the sets (docs/case-format.md, \"Conditions on the same "
                      "disks\")");
  };
  for (std::size_t k = 0; k < case_.boundaries.size(); ++k) {
    const BoundaryCondition& bc = case_.boundaries[k];
    const auto self = static_cast<std::int32_t>(k);
    const int s = lattice_.find_set(bc.set);
    if (s < 0) throw InputError(bc.where + ": unknown boundary set '" + bc.set + "'");
    VelocitySet vs{&bc, {}};
    std::size_t held = 0;
    double nearest = std::numeric_limits<double>::infinity(), r_nearest = 0;
    for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
      const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
      if (lattice_.set_distance[e] < nearest) {
        nearest = lattice_.set_distance[e];
        r_nearest = model_.radius[i];
      }
      if (!held_by_set(lattice_, e, model_.radius[i])) continue;
      ++held;
      const std::uint8_t comps = held_components(bc);
      const bool prescribes = bc.kind == BoundaryCondition::Kind::Velocity;
      auto& zero_by = holders[i].zero;
      auto& velocity_by = holders[i].velocity;
      for (int c = 0; c < 2; ++c) {
        if (!(comps & (c == 0 ? kFixX : kFixY))) continue;
        if (prescribes) {
          if (zero_by[c] >= 0) throw contradiction(zero_by[c], self, c, i, "it cannot be both held at zero and prescribed");
          if (velocity_by[c] >= 0 && velocity_by[c] != self)
            throw contradiction(velocity_by[c], self, c, i, "two velocity conditions prescribe it");
          velocity_by[c] = self;
        } else {
          if (velocity_by[c] >= 0) throw contradiction(velocity_by[c], self, c, i, "it cannot be both prescribed and held at zero");
          if (zero_by[c] < 0) zero_by[c] = self;
        }
      }
      // A disk takes the prescribed velocities of one velocity condition (update_velocities):
      // two on its two components would leave one of them held at zero.
      if (prescribes)
        for (int c = 0; c < 2; ++c)
          if (velocity_by[c] >= 0 && velocity_by[c] != self)
            throw contradiction(velocity_by[c], self, c, i,
                                "a disk may be prescribed by one velocity condition only (give vx and vy in one "
                                "[[boundary]] entry)");
      std::uint8_t& bits = model_.constraint[i];
      bits |= comps;
      switch (bc.kind) {
        case BoundaryCondition::Kind::Fixed:
          if (bc.fix_rotation) bits |= kFixRotation;
          break;
        case BoundaryCondition::Kind::Roller:
          break;
        case BoundaryCondition::Kind::Symmetry:
          bits |= kFixRotation;
          if (lattice_.set_distance[e] < 1e-3 * model_.radius[i]) {
            if (model_.mirror.plane.empty()) model_.mirror.plane.assign(model_.num_disks(), 0);
            model_.mirror.plane[i] = 1;
          }
          break;
        case BoundaryCondition::Kind::Velocity:
          vs.disks.push_back(static_cast<std::int32_t>(i));
          owner[i] = static_cast<std::int32_t>(velocity_sets_.size());
          break;
      }
    }
    if (held == 0) {
      // A condition that holds nothing would let the run go on as if it did (docs/case-format.md).
      throw InputError(bc.where + ": boundary set '" + bc.set + "' selects no disk: " +
                       (std::isfinite(nearest) ? "the nearest disk centre lies " + fmt(nearest) +
                                                     " m from the edge, and a condition acts on disks whose centre "
                                                     "lies within their radius (" + fmt(r_nearest) + " m) of it"
                                               : std::string("the set has no disks")) +
                       "; move the edge onto a lattice row ([mesh] origin) or change the radius");
    }
    check_every_part_held(bc, s);
    if (bc.kind == BoundaryCondition::Kind::Velocity) velocity_sets_.push_back(std::move(vs));
    if (bc.kind == BoundaryCondition::Kind::Symmetry) setup_mirror_springs(bc, s);
  }
  // A disk in several velocity sets was refused above; this keeps each disk in one set.
  for (std::size_t s = 0; s < velocity_sets_.size(); ++s) {
    auto& d = velocity_sets_[s].disks;
    d.erase(std::remove_if(d.begin(), d.end(), [&](std::int32_t i) { return owner[i] != static_cast<std::int32_t>(s); }),
            d.end());
  }
}

void Solver::check_every_part_held(const BoundaryCondition& bc, int s) const {
  // A set named on separate edges (a beam's two supports) whose one part holds nothing would let
  // the run go on with a support missing: refused like a set that holds nothing at all.
  std::size_t parts = 0;
  const std::vector<std::size_t> part = set_parts(lattice_, model_.radius, s, parts);
  if (parts < 2) return;
  const auto first = lattice_.set_offset[static_cast<std::size_t>(s)];
  std::vector<std::size_t> held(parts, 0), members(parts, 0);
  std::vector<double> nearest(parts, std::numeric_limits<double>::infinity());
  std::vector<double> r_nearest(parts, 0), cx(parts, 0), cy(parts, 0);
  for (std::size_t k = 0; k < part.size(); ++k) {
    const std::size_t p = part[k];
    const auto e = static_cast<std::int64_t>(first) + static_cast<std::int64_t>(k);
    const auto ue = static_cast<std::size_t>(e);
    const auto i = static_cast<std::size_t>(lattice_.set_disk[ue]);
    ++members[p];
    cx[p] += lattice_.set_cx[ue];
    cy[p] += lattice_.set_cy[ue];
    if (held_by_set(lattice_, e, model_.radius[i])) ++held[p];
    if (lattice_.set_distance[ue] < nearest[p]) {
      nearest[p] = lattice_.set_distance[ue];
      r_nearest[p] = model_.radius[i];
    }
  }
  for (std::size_t p = 0; p < parts; ++p) {
    if (held[p] > 0) continue;
    const double n = static_cast<double>(members[p]);
    throw InputError(bc.where + ": boundary set '" + bc.set + "' holds no disk on its part near (" + fmt(cx[p] / n) +
                     ", " + fmt(cy[p] / n) + ") m (one of its " + std::to_string(parts) +
                     " separate parts): the nearest disk centre there lies " + fmt(nearest[p]) +
                     " m from the edge, and a condition acts on disks whose centre lies within their radius (" +
                     fmt(r_nearest[p]) + " m) of it; move the edge onto a lattice row ([mesh] origin), widen it or "
                     "change the radius");
  }
}

void Solver::setup_mirror_springs(const BoundaryCondition& bc, int s) {
  // A mirror plane x = const (component 0) or y = const (component 1). A disk one radius off
  // the plane, whose lattice has a bond direction along the plane's normal, is bonded to its
  // own mirror image in the full model: that bond stretches by twice the disk's normal
  // displacement, so in the half model it is a spring to the plane of stiffness 2 k_n.
  const int c = bc.component;
  for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
    const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
    const double normal = c == 0 ? lattice_.set_nx[e] : lattice_.set_ny[e];
    if (std::abs(std::abs(normal) - 1.0) > 1e-6) {
      throw InputError(bc.where + ": symmetry set '" + bc.set + "' must be a straight line " +
                       (c == 0 ? "x" : "y") + " = const (a member's normal is (" + fmt(lattice_.set_nx[e]) + ", " +
                       fmt(lattice_.set_ny[e]) + "))");
    }
    const double r = model_.radius[i];
    if (std::abs(lattice_.set_distance[e] - r) > 1e-6 * r) continue;
    const meshing::BodyOutline& body = case_.outline.bodies[static_cast<std::size_t>(model_.body[i])];
    const double normal_deg = c == 0 ? 0.0 : 90.0;
    double rel = std::fmod(normal_deg - body.angle_deg.value_or(0.0), 180.0);
    if (rel < 0) rel += 180.0;
    const bool class1 = rel < 1e-6 || rel > 180.0 - 1e-6;
    const bool class2 = std::abs(rel - 60.0) < 1e-6 || std::abs(rel - 120.0) < 1e-6;
    if (!class1 && !class2) continue;
    const SpringConstants& K = body_materials_[static_cast<std::size_t>(model_.body[i])].springs;
    double w = case_.thickness;
    if (case_.geometry == Geometry::Axisymmetric) w = c == 0 ? model_.x0[i] + normal * lattice_.set_distance[e] : model_.x0[i];
    const double k = 2.0 * (class1 ? K.kn1 : K.kn2) * w;
    if (!model_.has_mirror_springs())  // allocated for the cases that have mirror springs
      for (auto* v : {&model_.mirror.kx, &model_.mirror.ky, &model_.mirror.sx, &model_.mirror.sy}) v->assign(model_.num_disks(), 0.0);
    (c == 0 ? model_.mirror.kx : model_.mirror.ky)[i] = k;
    (c == 0 ? model_.mirror.sx : model_.mirror.sy)[i] = normal > 0 ? 1.0 : -1.0;
  }
}

void Solver::setup_loads() {
  std::vector<std::uint8_t> loaded(model_.num_disks(), 0);
  for (const Load& load : case_.loads) {
    LoadSet ls{&load, {}, {}, {}, {}, {}};
    if (load.kind == Load::Kind::Pressure) {
      const int s = lattice_.find_set(load.set);
      if (s < 0) throw InputError(load.where + ": unknown boundary set '" + load.set + "'");
      for (auto e = lattice_.set_offset[s]; e < lattice_.set_offset[s + 1]; ++e) {
        const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
        if (load.window) {
          const double coord = load.window->axis == 0 ? model_.x0[i] : model_.y0[i];
          if (coord < load.window->min || coord > load.window->max) continue;
        }
        // Pressure (compression positive) on the disk's share of the named edges:
        // F = -p L w n_out, w = thickness or the faces' radius (per radian).
        const double w = case_.geometry == Geometry::Axisymmetric ? lattice_.set_cx[e] : case_.thickness;
        const double lw = lattice_.set_length[e] * w;
        ls.disks.push_back(static_cast<std::int32_t>(i));
        ls.cx.push_back(-load.p0 * lw * lattice_.set_nx[e]);
        ls.cy.push_back(-load.p0 * lw * lattice_.set_ny[e]);
        ls.lx.push_back(lattice_.set_cx[e] - model_.x0[i]);
        ls.ly.push_back(lattice_.set_cy[e] - model_.y0[i]);
      }
      p_max_ = std::max(p_max_, std::abs(load.p0) * load.function.max_abs(case_.time.end));
    } else {
      for (std::size_t i = 0; i < model_.num_disks(); ++i) {
        const std::string& name = lattice_.body_names[model_.body[i]];
        if (!load.bodies.empty() && std::find(load.bodies.begin(), load.bodies.end(), name) == load.bodies.end()) continue;
        ls.disks.push_back(static_cast<std::int32_t>(i));
        ls.cx.push_back(model_.mass[i] * load.acceleration[0]);
        ls.cy.push_back(model_.mass[i] * load.acceleration[1]);
        ls.lx.push_back(0.0);
        ls.ly.push_back(0.0);
      }
    }
    if (ls.disks.empty()) {
      throw InputError(load.where + ": the load selects no disk (" +
                       (load.kind == Load::Kind::Pressure
                            ? "boundary set '" + load.set + "'" + (load.window ? " within its window" : std::string())
                            : std::string("none of the bodies it names has disks")) +
                       ")");
    }
    for (std::int32_t i : ls.disks) loaded[i] = 1;
    loads_.push_back(std::move(ls));
  }
  for (std::size_t i = 0; i < loaded.size(); ++i)
    if (loaded[i]) loaded_disks_.push_back(static_cast<std::int32_t>(i));
  // The loads' forces and lever arms (disk_stress), for the cases that have loads.
  if (!loaded_disks_.empty())
    for (auto* v : {&model_.fx_ext, &model_.fy_ext, &model_.ext_mxx, &model_.ext_myy, &model_.ext_mxy})
      v->assign(model_.num_disks(), 0.0);
}

void Solver::setup_reactions() {
  for (const std::string& name : case_.output.reactions) {
    const std::string what = case_.source + ": output.reactions: boundary set '" + name + "'";
    // Names were checked against the outline by the reader; a set without disks has no row.
    const int s = lattice_.find_set(name);
    if (s < 0) throw InputError(what + " selects no disk (the set has no disks)");
    const std::int64_t first = lattice_.set_offset[s], end = lattice_.set_offset[s + 1];
    ReactionSet rs;
    std::vector<std::uint8_t> held(static_cast<std::size_t>(end - first), 0);
    std::vector<std::uint8_t> spring(held.size(), 0);
    bool conditioned = false;
    for (const BoundaryCondition& bc : case_.boundaries) {
      if (bc.set != name) continue;
      conditioned = true;  // setup_boundaries refused a condition that holds no disk
      const std::uint8_t bits = held_components(bc);
      for (auto e = first; e < end; ++e) {
        const auto i = static_cast<std::size_t>(lattice_.set_disk[e]);
        if (held_by_set(lattice_, e, model_.radius[i])) held[static_cast<std::size_t>(e - first)] |= bits;
        // A mirror plane's springs to the disks one radius off it (setup_mirror_springs)
        // are part of the condition: their force -k u is the plane's on the body.
        const double k = !model_.has_mirror_springs() ? 0.0 : bc.component == 0 ? model_.mirror.kx[i] : model_.mirror.ky[i];
        if (bc.kind == BoundaryCondition::Kind::Symmetry && k != 0 &&
            std::abs(lattice_.set_distance[e] - model_.radius[i]) <= 1e-6 * model_.radius[i])
          spring[static_cast<std::size_t>(e - first)] |= static_cast<std::uint8_t>(1 << bc.component);
      }
    }
    for (auto e = first; e < end; ++e) {
      const auto k = static_cast<std::size_t>(e - first);
      if (held[k] != 0) {
        rs.disks.push_back(lattice_.set_disk[e]);
        rs.held.push_back(held[k]);
      }
      for (std::uint8_t axis = 0; axis < 2; ++axis) {
        if (!(spring[k] & (1 << axis))) continue;
        rs.spring_disks.push_back(lattice_.set_disk[e]);
        rs.spring_axis.push_back(axis);
      }
    }
    if (!conditioned) {
      // A set that only carries loads reports the force they apply.
      for (std::size_t l = 0; l < loads_.size(); ++l)
        if (loads_[l].load->kind == Load::Kind::Pressure && loads_[l].load->set == name)
          rs.loads.push_back(static_cast<std::int32_t>(l));
      if (rs.loads.empty()) {
        throw InputError(what + " has no [[boundary]] condition and no pressure [[load]]: nothing acts on the "
                                "body there (its reaction would be zero)");
      }
    }
    reaction_sets_.push_back(std::move(rs));
  }
}

std::array<double, 2> Solver::reaction(std::size_t k) const {
  const Model& m = model_;
  const ReactionSet& rs = reaction_sets_[k];
  const double dt = dt_info_.dt;
  double rx = 0, ry = 0;
  // Held components: the force the constraint adds to F(t_n) to give the held disk the
  // leap-frog acceleration (v(t+dt/2) - v(t-dt/2)) / dt it was given (update_velocities).
  for (std::size_t j = 0; j < rs.disks.size(); ++j) {
    const auto i = static_cast<std::size_t>(rs.disks[j]);
    const double fx_ext = m.fx_ext.empty() ? 0.0 : m.fx_ext[i], fy_ext = m.fy_ext.empty() ? 0.0 : m.fy_ext[i];
    if (rs.held[j] & kFixX) rx += m.mass[i] * (m.vx[i] - m.vx_old[i]) / dt - (m.fx[i] + fx_ext);
    if (rs.held[j] & kFixY) ry += m.mass[i] * (m.vy[i] - m.vy_old[i]) / dt - (m.fy[i] + fy_ext);
  }
  // Mirror springs, F = -k u at t_n (compute_internal_forces).
  for (std::size_t j = 0; j < rs.spring_disks.size(); ++j) {
    const auto i = static_cast<std::size_t>(rs.spring_disks[j]);
    if (rs.spring_axis[j] == 0) {
      rx -= m.mirror.kx[i] * m.ux[i];
    } else {
      ry -= m.mirror.ky[i] * m.uy[i];
    }
  }
  // Loads of a set without a condition, at the time of the force pass (apply_external_forces).
  for (std::int32_t l : rs.loads) {
    const LoadSet& ls = loads_[static_cast<std::size_t>(l)];
    const double amp = ls.load->function(m.time);
    for (std::size_t e = 0; e < ls.disks.size(); ++e) {
      rx += amp * ls.cx[e];
      ry += amp * ls.cy[e];
    }
  }
  return {rx, ry};
}

void Solver::setup_initial_velocities() {
  for (const InitialVelocity& iv : case_.initial_velocities) {
    const auto it = std::find(lattice_.body_names.begin(), lattice_.body_names.end(), iv.body);
    if (it == lattice_.body_names.end()) throw InputError(iv.where + ": unknown body '" + iv.body + "'");
    const auto b = static_cast<std::int32_t>(it - lattice_.body_names.begin());
    for (std::size_t i = 0; i < model_.num_disks(); ++i) {
      if (model_.body[i] != b) continue;
      if (!(model_.constraint[i] & kFixX)) model_.vx[i] = iv.velocity[0];
      if (!(model_.constraint[i] & kFixY)) model_.vy[i] = iv.velocity[1];
    }
  }
}

void Solver::apply_external_forces(double t) {
  for (std::int32_t i : loaded_disks_) {
    model_.fx_ext[i] = model_.fy_ext[i] = 0.0;
    model_.ext_mxx[i] = model_.ext_myy[i] = model_.ext_mxy[i] = 0.0;
  }
  for (const LoadSet& ls : loads_) {
    const double amp = ls.load->function(t);
    for (std::size_t k = 0; k < ls.disks.size(); ++k) {
      const auto i = static_cast<std::size_t>(ls.disks[k]);
      const double fx = amp * ls.cx[k], fy = amp * ls.cy[k];
      model_.fx_ext[i] += fx;
      model_.fy_ext[i] += fy;
      model_.ext_mxx[i] += ls.lx[k] * fx;
      model_.ext_myy[i] += ls.ly[k] * fy;
      model_.ext_mxy[i] += 0.5 * (ls.lx[k] * fy + ls.ly[k] * fx);
    }
  }
}

}  // namespace hexdem::solver
