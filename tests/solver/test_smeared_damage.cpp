// Smeared damage (`damage_band` on [[material]]; docs/model.md, "Smeared damage"): a bond's
// damage is driven by the criteria at the continuum stress of its midpoint, not by its own
// stretch, so it does not depend on the bond's direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "common/softening_plate.hpp"
#include "hexdem/error.hpp"
#include "hexdem/laws/softening.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// The softening plate (tests/common) with smeared damage over a 3 mm band, without rate
/// dependence or a random field; `extra_material` "" gives the bond-driven law.
std::string plate_case(double angle, const std::string& extra_material = "damage_band = 3e-3\n") {
  return hexdem::testing::softening_plate_case(
      angle, "tensile_strength = 3e6\ncompressive_strength = 30e6\ncohesion = 8.66e6\nfriction_angle = 30.0\n",
      extra_material, 1e-6);
}

/// The affine displacement of a uniaxial stress s f_t along y (plane stress, nu = 0.2).
void uniaxial(Model& m, double s) {
  const double eyy = s * 3e6 / 30e9, exx = -0.2 * eyy;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    m.ux[i] = exx * m.x0[i];
    m.uy[i] = eyy * m.y0[i];
  }
}

bool has_full_disk(const Model& m, std::size_t b) {
  return m.initial_bonds(static_cast<std::size_t>(m.bi[b])) == 6 || m.initial_bonds(static_cast<std::size_t>(m.bj[b])) == 6;
}

TEST(SmearedDamage, EveryBondOfAUniformStressDamagesAlikeWhateverItsDirection) {
  // Under a uniform uniaxial stress of 1.5 f_t every bond with a full neighbourhood starts to
  // damage, the ones across the load (shortened by the Poisson contraction) as much as the
  // ones along it, at the criterion's value 1.5; at 3 f_t (the continuum's effective stress)
  // each has the linear law's damage D(3; 1.5, 1.5 k_f), k_f = 2 G_F E / (f_t^2 w) = 222.2.
  // Damaged bonds stay in their disks' fits. The bond-driven law of the default (no
  // damage_band) starts a crack only in the stretched bonds: the test's contrast.
  const double kf = 2 * 100.0 * 30e9 / (3e6 * 3e6 * 3e-3);
  for (double angle : {0.0, 17.0}) {
    SCOPED_TRACE(angle);
    const Case c = parse_case(plate_case(angle), "plate.toml", ".");
    Solver s(c, mesh_case(c));
    Model m = s.model();  // a copy at rest
    ASSERT_NEAR(m.softening[0].damage_kf, kf, 1e-9 * kf);
    const double dt = s.dt();
    uniaxial(m, 1.5);
    compute_internal_forces(m, dt);
    settle_broken_bonds(m, dt);
    std::size_t full = 0, damaging = 0, across = 0;
    for (std::size_t b = 0; b < m.num_bonds(); ++b) {
      if (!has_full_disk(m, b)) continue;
      ++full;
      if (m.bond_crack(b) != Model::kDamageCrack) continue;
      ++damaging;
      const Model::FailedBond& f = m.failed(b);
      EXPECT_NEAR(f.delta0, 1.5, 1e-9) << b;
      EXPECT_NEAR(f.delta_f, 1.5 * kf, 1e-9 * kf) << b;
      EXPECT_EQ(f.damage, 0.0) << b;
      EXPECT_TRUE(m.bond_in_fit(b)) << b;
      across += m.len_prev[b] < m.rest(b) ? 1 : 0;
    }
    EXPECT_GT(full, 200u);
    EXPECT_EQ(damaging, full);
    EXPECT_GT(across, full / 6) << "bonds across the load, shortened, damage too";
    uniaxial(m, 3.0);
    compute_internal_forces(m, dt);
    settle_broken_bonds(m, dt);
    const double expected = laws::LinearSoftening::damage(3.0, 1.5, 1.5 * kf);
    ASSERT_GT(expected, 0.4);
    double lo = 1, hi = 0, booked = 0;
    for (std::size_t b = 0; b < m.num_bonds(); ++b) {
      if (!has_full_disk(m, b)) continue;
      lo = std::min(lo, m.failed(b).damage);
      hi = std::max(hi, m.failed(b).damage);
      EXPECT_GE(m.bond_fracture_energy(b), 0.0) << b;
      booked += m.bond_fracture_energy(b);
    }
    EXPECT_NEAR(lo, expected, 1e-9);
    EXPECT_NEAR(hi, expected, 1e-9);
    EXPECT_GT(booked, 0.0);
  }
  // The contrast: the bond-driven law cracks only bonds that are stretched.
  const Case c = parse_case(plate_case(0.0, ""), "plate.toml", ".");
  Solver s(c, mesh_case(c));
  Model m = s.model();
  uniaxial(m, 1.5);
  compute_internal_forces(m, s.dt());
  settle_broken_bonds(m, s.dt());
  std::size_t full = 0, cracking = 0;
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    if (!has_full_disk(m, b)) continue;
    ++full;
    cracking += m.bond_intact(b) && m.bond_crack(b) != Model::kNoCrack ? 1 : 0;
  }
  EXPECT_LT(cracking, full * 3 / 4);
}

/// A bar 20 mm wide and 40 mm tall (plane stress, 10 mm thick, r = 0.5 mm) pulled at its top
/// at 0.5 m/s, with smeared damage over `band` and the nonlocal strain over 3 mm.
std::string bar_case(double angle, double band) {
  std::ostringstream s;
  s.precision(12);
  const double r = 0.5, rows = std::round(40.0 / (std::sqrt(3.0) * r)), height = rows * std::sqrt(3.0) * r;
  s << "units = \"mm\"\n[case]\nname = \"bar\"\ngeometry = \"plane-stress\"\nthickness = 0.01\n"
    << "[mesh]\nradius = " << r * 1e-3 << "\nangle = " << angle << "\n"
    << "[[body]]\nname = \"bar\"\nmaterial = 1\n  [[body.shape]]\n  type = \"rectangle\"\n"
    << "  min = [0.0, 0.0]\n  max = [20.0, " << height << "]\n"
    << "  boundary = { bottom = \"base\", right = \"side\", top = \"grip\", left = \"side\" }\n"
    << "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
    << "tensile_strength = 3e6\ncompressive_strength = 30e6\ncohesion = 8.66e6\nfriction_angle = 30.0\n"
    << "fracture_energy = 100.0\nrate_dependent = false\nnonlocal_radius = 3e-3\ndamage_band = " << band << "\n"
    << "[[boundary]]\nset = \"base\"\ntype = \"roller\"\ncomponent = \"y\"\n"
    << "[[boundary]]\nset = \"grip\"\ntype = \"velocity\"\nvy = 0.5\n"
    << "function = { type = \"table\", points = [[0.0, 0.0], [2e-5, 1.0], [1.0, 1.0]] }\n"
    << "[contact]\ndamping = 0.1\n"
    << "[random]\nseed = 1\ncorrelation_length = 5e-3\nstrength_cov = 0.1\n"
    << "[time]\nend = 4e-4\n";
  return s.str();
}

TEST(SmearedDamage, ABarPulledApartKeepsItsEnergyBalanceAndDissipatesAboutGFAtEveryAngle) {
  // Pulled to 190 um, far past the crack opening 2 G_F / f_t = 67 um, the bar separates. Every
  // damage step books its release (none negative) and the run keeps its energy balance. The
  // band is the calibration of docs/model.md ("Smeared damage"), w = 1.72 R, measured on the
  // quasi-static tension test of cases/material_tests (R = 5 mm): this bar (R = 3 mm, loaded
  // 25 times faster) is an independent check of it. Its fracture energy is G_F x 20 mm x
  // 10 mm = 0.02 J within 25 % (measured 1.018 and 1.069 G_F A; a band taken as R would give
  // 1.7 times as much), and the same at 0 and 30 degrees within 10 % (the bond-driven law's
  // bar in test_softening.cpp spans 1.12 to 1.40 G_F A over the angles).
  const double expected = 100.0 * 0.020 * 0.010;
  std::vector<double> energies;
  for (double angle : {0.0, 30.0}) {
    const Case c = parse_case(bar_case(angle, 5.2e-3), "bar.toml", ".");
    Solver s(c, mesh_case(c));
    const Model& m = s.model();
    double max_error = 0;
    const std::int64_t steps = s.total_steps();
    for (std::int64_t n = 0; n <= steps; ++n) {
      ASSERT_TRUE(s.advance(true)) << angle;
      max_error = std::max(max_error, std::abs(s.energy().relative_error()));
    }
    std::size_t damaged = 0, broken = 0;
    double min_bond = 0;
    for (std::size_t b = 0; b < m.num_bonds(); ++b) {
      damaged += m.bond_intact(b) && m.bond_crack(b) == Model::kDamageCrack ? 1 : 0;
      broken += m.bond_intact(b) ? 0 : 1;
      min_bond = std::min(min_bond, m.bond_fracture_energy(b));
    }
    const double fracture = s.energy().fracture;
    std::printf("angle %4.0f: fracture %.4e J (%.3f x G_F A), max |Err| %.2e, damaging %zu, broken %zu\n", angle,
                fracture, fracture / expected, max_error, damaged, broken);
    EXPECT_LE(max_error, 0.01) << angle;
    EXPECT_GE(min_bond, 0.0) << angle;
    EXPECT_GT(broken, 40u) << "the bar separated: at least one row of bonds across its width broke";
    EXPECT_GT(fracture, 0.75 * expected) << angle;
    EXPECT_LT(fracture, 1.25 * expected) << angle;
    energies.push_back(fracture);
  }
  EXPECT_NEAR(energies[1], energies[0], 0.1 * energies[0]) << "the fracture energy at 30 degrees against 0";
}

TEST(SmearedDamage, ABadBandIsRefusedNamingTheKey) {
  for (const auto& [extra, message] : std::vector<std::pair<std::string, std::string>>{
           {"damage_band = -1e-3\n", "damage_band"}, {"damage_band = nan\n", "damage_band"}}) {
    try {
      (void)parse_case(plate_case(0.0, extra), "plate.toml", ".");
      ADD_FAILURE() << extra;
    } catch (const InputError& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find(message), std::string::npos) << text;
      EXPECT_NE(text.find("plate.toml"), std::string::npos) << text;
      EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    }
  }
  // Without a fracture energy there is nothing to spread over the band.
  std::string text = plate_case(0.0);
  text.replace(text.find("fracture_energy = 100.0\n"), 24, "");
  try {
    (void)parse_case(text, "plate.toml", ".");
    ADD_FAILURE() << "damage_band without fracture_energy";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("damage_band"), std::string::npos) << e.what();
  }
}

}  // namespace
