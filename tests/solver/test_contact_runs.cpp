// Contacts between disks that were never bonded (physics.md section 8), through the solver:
// the broad phase finds them, the linear spring-dashpot gives the closed-form coefficient of
// restitution, energy is conserved without damping, and bodies that overlap at the start are
// refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hexdem/error.hpp"
#include "hexdem/laws/contact.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

constexpr double kSqrt3 = 1.7320508075688772935;

/// Two single-disk bodies on the x axis, `gap` apart, moving towards each other at v.
struct Pair {
  Case c;
  meshing::Lattice lattice;
};

Pair head_on(double r, double gap, double v, double eta, double dt, double end) {
  Pair p;
  Case& c = p.c;
  c.name = "pair";
  c.source = "pair.toml";
  c.geometry = Geometry::PlaneStrain;
  c.shear_model = ShearModel::LocalStrain;
  for (const char* name : {"left", "right"}) {
    meshing::BodyOutline b;
    b.name = name;
    b.material = 1;
    b.radius = r;
    b.where = name;
    c.outline.bodies.push_back(b);
  }
  Material steel;
  steel.id = 1;
  steel.name = "steel";
  steel.E = 210e9;
  steel.nu = 0.3;
  steel.density = 7850;
  steel.friction = 0.3;
  c.materials.push_back(steel);
  c.initial_velocities.push_back({"left", {v, 0.0}, "left"});
  c.initial_velocities.push_back({"right", {-v, 0.0}, "right"});
  c.contact.damping = eta;
  c.time.end = end;
  c.time.dt = dt;
  meshing::Lattice& lat = p.lattice;
  lat.mode = meshing::GeometryMode::Plane;
  lat.x = {0.0, 2 * r + gap};
  lat.y = {0.0, 0.0};
  lat.radius = {r, r};
  lat.cell_area = {2 * kSqrt3 * r * r, 2 * kSqrt3 * r * r};
  lat.cell_cx = lat.x;
  lat.cell_cy = lat.y;
  lat.kind = {0, 0};
  lat.body = {0, 1};
  lat.material = {1, 1};
  lat.set_offset = {0};
  lat.body_names = {"left", "right"};
  lat.body_region_area = {lat.cell_area[0], lat.cell_area[1]};
  return p;
}

struct Collision {
  double restitution = 0;
  double worst_energy_error = 0;
};

Collision collide(double eta) {
  const double r = 0.5e-3, v = 1.0;
  // The contact's own frequency sets the step: omega dt = 1e-3 keeps the integration error
  // of the restitution (first order with a dashpot, about 3.4 omega dt) below 0.5 %.
  Material steel;
  steel.isotropic = true;
  steel.E = 210e9;
  steel.nu = 0.3;
  const double kn1 = spring_constants(steel.stiffness(Geometry::PlaneStrain)).kn1;
  const double m = 7850 * 2 * kSqrt3 * r * r;
  const double k = 0.5 * kn1;  // series combination of two equal bodies
  // The contact is no stiffer than the cap m_eff contact_omega2, which refers to the default
  // step, not to the step used (docs/model.md, "Energy at contacts"): read it from a solver
  // of the same pair, then resolve the capped contact.
  double omega = std::sqrt(k / (0.5 * m));
  {
    const Pair probe = head_on(r, 20 * v * 1e-3 / omega, v, eta, 1e-3 / omega, 1e-3);
    const Solver s0(probe.c, probe.lattice);
    omega = std::min(omega, std::sqrt(s0.model().contact_omega2));
  }
  const double dt = 1e-3 / omega;
  const double gap = 20 * v * dt;  // they touch after about ten steps
  Pair p = head_on(r, gap, v, eta, dt, gap / (2 * v) + 4.0 / omega);
  Solver s(p.c, p.lattice);
  Collision out;
  const std::int64_t steps = s.total_steps();
  for (std::int64_t n = 0; n <= steps; ++n) {
    EXPECT_TRUE(s.advance(true, [&](const Solver& sv) {
      out.worst_energy_error = std::max(out.worst_energy_error, std::abs(sv.energy().relative_error()));
    })) << s.blow_up().reason;
  }
  const Model& md = s.model();
  out.restitution = (md.vx[1] - md.vx[0]) / (2 * v);
  return out;
}

TEST(ContactRun, HeadOnRestitutionMatchesTheSpringDashpot) {
  for (const double eta : {0.0, 0.1, 0.5}) {
    const Collision c = collide(eta);
    const double expected = laws::LinearContact::restitution(eta);
    std::printf("eta %.1f: restitution %.5f, closed form %.5f\n", eta, c.restitution, expected);
    EXPECT_NEAR(c.restitution, expected, 0.005 * expected) << "eta " << eta;
  }
}

// The contacts' stiffness cap is part of the model: it refers to the default step (0.9 x the
// critical step, landing on the end time) whatever step the run uses, so that a convergence
// study in the step integrates the same contacts (docs/model.md, "Energy at contacts").
TEST(ContactRun, TheContactCapDoesNotFollowTheStep) {
  const double r = 0.5e-3, v = 1.0, end = 2e-5;
  Pair automatic = head_on(r, 0.1 * r, v, 0.5, 0.0, end);
  automatic.c.time.dt.reset();
  const Solver s0(automatic.c, automatic.lattice);
  const TimeStepInfo& ts = s0.time_step();
  ASSERT_FALSE(ts.user_dt);
  EXPECT_EQ(ts.dt_contact, ts.dt) << "the default step is the reference";
  EXPECT_LE(ts.dt_contact, 0.9 * ts.dt_critical);
  EXPECT_GT(ts.dt_contact, 0.9 * ts.dt_critical * (1 - 1.0 / s0.total_steps()));
  const double beta = 0.25;  // [contact] resolution (default), inside the dashpot's bound at eta 0.5
  EXPECT_DOUBLE_EQ(s0.model().contact_omega2, (beta / ts.dt) * (beta / ts.dt));
  for (const double f : {0.5, 0.25, 1.05}) {
    Pair p = head_on(r, 0.1 * r, v, 0.5, f * ts.dt, end);
    const Solver s(p.c, p.lattice);
    EXPECT_EQ(s.time_step().dt, f * ts.dt);
    EXPECT_EQ(s.time_step().dt_contact, ts.dt_contact) << "dt = " << f << " x the default";
    EXPECT_EQ(s.model().contact_omega2, s0.model().contact_omega2) << "dt = " << f << " x the default";
  }
  Pair half = head_on(r, 0.1 * r, v, 0.5, 0.0, end);
  half.c.time.dt.reset();
  half.c.time.safety = 0.45;
  const Solver s1(half.c, half.lattice);
  EXPECT_LT(s1.time_step().dt, 0.51 * ts.dt);
  EXPECT_EQ(s1.model().contact_omega2, s0.model().contact_omega2) << "safety 0.45";
}

TEST(ContactRun, UndampedCollisionConservesEnergy) {
  const Collision c = collide(0.0);
  std::printf("undamped collision: largest |relative energy error| %.3g\n", c.worst_energy_error);
  EXPECT_LT(c.worst_energy_error, 1e-6);
}

TEST(ContactRun, BodiesOverlappingAtTheStartAreRefused) {
  Pair p = head_on(0.5e-3, -0.1e-3, 1.0, 0.0, 1e-8, 1e-6);
  try {
    Solver s(p.c, p.lattice);
    FAIL() << "overlapping bodies accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'left' and 'right' overlap"), std::string::npos) << msg;
    EXPECT_NE(msg.find("0.0001"), std::string::npos) << msg;
  }
}

}  // namespace

namespace {

/// A disk that cannot spin resting on a wall inclined at `deg` degrees under gravity, with
/// friction coefficient 0.5 (friction angle 26.6 degrees); returns its travel down the slope
/// after `time` and the travel of a frictionless block, g sin(theta) t^2 / 2 - mu g cos(theta) t^2 / 2.
struct Slide {
  double travel = 0, expected = 0;
};

Slide slide(double deg, double time) {
  const double r = 0.5e-3, th = deg * 3.14159265358979323846 / 180.0, g = 9.81, mu = 0.5;
  Pair p = head_on(r, 0.0, 0.0, 0.0, 0.0, time);
  Case& c = p.c;
  c.outline.bodies.pop_back();
  c.initial_velocities.clear();
  c.time.dt.reset();
  meshing::Lattice& lat = p.lattice;
  const double nx = -std::sin(th), ny = std::cos(th);
  lat.x = {r * nx};
  lat.y = {r * ny};
  lat.radius = {r};
  lat.cell_area = {lat.cell_area[0]};
  lat.cell_cx = lat.x;
  lat.cell_cy = lat.y;
  lat.kind = {0};
  lat.body = {0};
  lat.material = {1};
  lat.body_names = {"left"};
  lat.body_region_area = {lat.cell_area[0]};
  Wall wall;
  wall.point = {0.0, 0.0};
  wall.normal = {nx, ny};
  wall.friction = mu;
  c.walls.push_back(wall);
  Load gravity;
  gravity.kind = Load::Kind::BodyForce;
  gravity.acceleration = {0.0, -g};
  c.loads.push_back(gravity);
  c.contact.damping = 0.3;
  Solver s(c, lat);
  s.model().constraint[0] |= kFixRotation;
  const std::int64_t steps = s.total_steps();
  for (std::int64_t n = 0; n <= steps; ++n) EXPECT_TRUE(s.advance(false));
  const double down_x = std::cos(th), down_y = std::sin(th);  // along the slope, downwards
  Slide out;
  out.travel = -(s.model().ux[0] * down_x + s.model().uy[0] * down_y);
  out.expected = std::max(0.0, 0.5 * g * (std::sin(th) - mu * std::cos(th)) * time * time);
  return out;
}

TEST(ContactRun, DiskOnAnInclinedWallSticksBelowTheFrictionAngle) {
  const Slide s = slide(20.0, 2e-3);
  std::printf("20 degrees: travel %.3g m (sticks: the contact springs' elastic creep only)\n", s.travel);
  EXPECT_LT(std::abs(s.travel), 1e-6);
}

TEST(ContactRun, DiskOnAnInclinedWallSlidesAboveTheFrictionAngle) {
  const Slide s = slide(35.0, 2e-3);
  std::printf("35 degrees: travel %.4g m, Coulomb sliding %.4g m\n", s.travel, s.expected);
  EXPECT_GT(s.expected, 1e-6);
  EXPECT_NEAR(s.travel, s.expected, 0.02 * s.expected);
}

}  // namespace

#include "hexdem/solver/output.hpp"

namespace {

TEST(ContactRun, ContactsAreWrittenAsExtraCellsAfterTheBonds) {
  const double r = 0.5e-3, v = 1.0, dt = 2e-10;
  Pair p = head_on(r, 10 * v * dt, v, 0.0, dt, 40 * dt);
  Solver s(p.c, p.lattice);
  bool seen = false;
  const std::int64_t steps = s.total_steps();
  for (std::int64_t n = 0; n <= steps; ++n) {
    ASSERT_TRUE(s.advance(false, [&](const Solver& sv) {
      RunOutput::ContactCells cells;
      const io::LineGrid g = RunOutput::frame_grid(sv, cells);
      const bool touching = sv.contacts().size() == 1 && sv.contacts()[0].f_n < 0;
      EXPECT_EQ(g.num_lines, 0u);  // no bonds between the two bodies
      EXPECT_EQ(g.num_extra_lines, touching ? 1u : 0u);
      if (!touching) return;
      seen = true;
      std::uint8_t state = 0;
      double force = 0;
      for (const io::ArraySource& a : g.cell_data) {
        ASSERT_EQ(a.tuples, 1u);
        if (a.name == "state") a.fill(0, 1, &state);
        if (a.name == "normal_force") a.fill(0, 1, &force);
      }
      EXPECT_EQ(state, 5);
      EXPECT_EQ(force, sv.contacts()[0].f_n);
    }));
  }
  EXPECT_TRUE(seen);
}

}  // namespace

namespace {

// [contact] cap_mass = "whole_cell" (docs/model.md, "Energy at contacts"): a disk whose cell
// the outline or the axis cuts is lighter than an interior disk, and the cap m_eff
// contact_omega2 made its contacts softer; the cap is then reckoned with the mass of its
// whole hexagonal cell, at most four times its own. A full-cell disk meets a quarter-cell one
// head on (undamped): with the disks' own masses the cap gives omega^2 = contact_omega2; with
// the whole cells' the spring is sqrt(2.5) times stiffer in omega (m_eff m / 5 against m / 2),
// unless the contact's own spring binds first. The largest overlap is v_rel / omega, and the
// energy is kept either way.
struct ClippedCollision {
  double max_overlap = 0, worst_energy_error = 0, cap_mass0 = 0, cap_mass1 = 0, mass0 = 0, mass1 = 0;
  double omega2 = 0, kn = 0;
};

ClippedCollision clipped_collision(CapMass rule) {
  const double r = 0.5e-3, v = 1.0;
  Pair probe = head_on(r, 0.1 * r, v, 0.0, 0.0, 1e-6);
  probe.c.time.dt.reset();
  probe.lattice.cell_area[1] *= 0.25;  // a quarter of the hexagon: a corner's disk
  const Solver s0(probe.c, probe.lattice);
  const double omega_cap = std::sqrt(s0.model().contact_omega2);
  const double dt = 2e-3 / omega_cap;
  const double gap = 10 * v * dt;
  Pair p = head_on(r, gap, v, 0.0, dt, gap / (2 * v) + 6.0 / omega_cap);
  p.lattice.cell_area[1] *= 0.25;
  p.c.contact.cap_mass = rule;
  Solver s(p.c, p.lattice);
  ClippedCollision out;
  const Model& md = s.model();
  out.cap_mass0 = md.cap_mass(0);
  out.cap_mass1 = md.cap_mass(1);
  out.mass0 = md.mass[0];
  out.mass1 = md.mass[1];
  out.omega2 = md.contact_omega2;
  Material steel;
  steel.isotropic = true;
  steel.E = 210e9;
  steel.nu = 0.3;
  out.kn = 0.5 * spring_constants(steel.stiffness(Geometry::PlaneStrain)).kn1 * p.c.thickness;
  for (std::int64_t n = 0; n <= s.total_steps(); ++n) {
    EXPECT_TRUE(s.advance(true, [&](const Solver& sv) {
      out.worst_energy_error = std::max(out.worst_energy_error, std::abs(sv.energy().relative_error()));
    })) << s.blow_up().reason;
    const double d = (md.x0[1] + md.ux[1]) - (md.x0[0] + md.ux[0]);
    out.max_overlap = std::max(out.max_overlap, 2 * r - d);
  }
  return out;
}

TEST(ContactRun, TheWholeCellCapReckonsAClippedDiskWithItsWholeCell) {
  const ClippedCollision own = clipped_collision(CapMass::Disk);
  const ClippedCollision whole = clipped_collision(CapMass::WholeCell);
  // The masses: the disk's own, or its whole cell's, never more than four times its own.
  EXPECT_DOUBLE_EQ(own.cap_mass0, own.mass0);
  EXPECT_DOUBLE_EQ(own.cap_mass1, own.mass1);
  EXPECT_DOUBLE_EQ(whole.cap_mass0, whole.mass0) << "a full cell's disk keeps its own mass";
  EXPECT_NEAR(whole.cap_mass1, 4.0 * whole.mass1, 1e-12 * whole.mass1) << "a quarter cell's disk";
  EXPECT_NEAR(whole.mass1, 0.25 * whole.mass0, 1e-12 * whole.mass0);
  // The overlaps against v_rel sqrt(m_eff / k), k = min(own spring, cap).
  const double v_rel = 2.0;
  const double m_eff = own.mass0 * own.mass1 / (own.mass0 + own.mass1);
  const double m_cap = whole.cap_mass0 * whole.cap_mass1 / (whole.cap_mass0 + whole.cap_mass1);
  const double k_own = std::min(own.kn, m_eff * own.omega2), k_whole = std::min(whole.kn, m_cap * whole.omega2);
  const double expect_own = v_rel * std::sqrt(m_eff / k_own), expect_whole = v_rel * std::sqrt(m_eff / k_whole);
  std::printf("quarter-cell disk: largest overlap %.4g m (own masses; expected %.4g) and %.4g m (whole cells; %.4g), "
              "k %.4g and %.4g N/m (spring %.4g), energy error %.2g and %.2g\n",
              own.max_overlap, expect_own, whole.max_overlap, expect_whole, k_own, k_whole, own.kn,
              own.worst_energy_error, whole.worst_energy_error);
  ASSERT_LT(k_own, own.kn) << "the cap must bind with the disks' own masses for the test to mean anything";
  EXPECT_GT(k_whole, 2.0 * k_own) << "the whole cells' cap is at least 2.5 times stiffer unless the spring binds";
  EXPECT_NEAR(own.max_overlap, expect_own, 0.01 * expect_own);
  EXPECT_NEAR(whole.max_overlap, expect_whole, 0.01 * expect_whole);
  EXPECT_LT(own.worst_energy_error, 1e-5);
  EXPECT_LT(whole.worst_energy_error, 1e-5);
}

}  // namespace
