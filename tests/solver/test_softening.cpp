// Softening failure with a fracture energy, hoop cracking and the random strength field
// (docs/model.md, "Fracture energy and softening", "Random strength").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/expanding_ring.hpp"
#include "common/softening_plate.hpp"
#include "hexdem/error.hpp"
#include "hexdem/laws/softening.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/random_field.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

TEST(LinearSoftening, WorkIsPeakForceTimesFailureElongationOverTwo) {
  // Monotone loading from 0 to delta_f: the area under (1 - D(delta)) k delta.
  const double k = 2.0e7, d0 = 1e-7, df = 5e-5;
  const int n = 200000;
  double work = 0, prev = 0;
  for (int i = 1; i <= n; ++i) {
    const double d = df * i / n;
    const double f = (1 - laws::LinearSoftening::damage(d, d0, df)) * k * d;
    work += 0.5 * (f + prev) * (df / n);
    prev = f;
  }
  EXPECT_NEAR(work, 0.5 * k * d0 * df, 1e-4 * 0.5 * k * d0 * df);
  // Linear between the peak and zero: half way the force is half the peak.
  const double mid = 0.5 * (d0 + df);
  EXPECT_NEAR((1 - laws::LinearSoftening::damage(mid, d0, df)) * k * mid, 0.5 * k * d0, 1e-9 * k * d0);
  EXPECT_EQ(laws::LinearSoftening::damage(0.5 * d0, d0, df), 0.0);
  EXPECT_EQ(laws::LinearSoftening::damage(2 * df, d0, df), 1.0);
  EXPECT_DOUBLE_EQ(laws::LinearSoftening::crack_opening(124.0, 3.33e6), 2 * 124.0 / 3.33e6);
}

TEST(Principal2D, FindsARotatedUniaxialStress) {
  for (double deg : {0.0, 10.0, 30.0, 45.0, 75.0, 120.0}) {
    const double a = deg * M_PI / 180, s = 3e6;
    const double c = std::cos(a), sn = std::sin(a);
    const laws::Principal2D p = laws::principal_2d(s * c * c, s * sn * sn, s * c * sn);
    EXPECT_NEAR(p.s1, s, 1e-6);
    EXPECT_NEAR(p.s2, 0.0, 1e-6);
    EXPECT_NEAR(std::abs(p.n1x * c + p.n1y * sn), 1.0, 1e-12) << deg;
  }
}

TEST(StressMohrCoulomb, UniaxialCompressionFailsAtTwoCCosPhiOverOneMinusSinPhi) {
  const double phi = 30 * M_PI / 180, c = 8.66e6;
  const laws::StressMohrCoulomb mc{c, std::sin(phi), std::cos(phi), 60e6};
  const double fc = 2 * c * std::cos(phi) / (1 - std::sin(phi));
  EXPECT_EQ(mc.mode(0.0, -0.999 * fc, 1.0), 0);
  EXPECT_EQ(mc.mode(0.0, -1.001 * fc, 1.0), 2);
  EXPECT_EQ(mc.mode(0.0, -61e6, 1.0), 3);  // crushing
  EXPECT_EQ(mc.mode(3e6, 0.0, 1.0), 0);    // uniaxial tension is left to the Rankine check
}

/// The exact continuum test of the softening pass: Rankine on s1, then Mohr-Coulomb on the
/// principal stresses with the out-of-plane one.
bool exact_criterion(double sxx, double syy, double sxy, double s3, double f_t, const laws::StressMohrCoulomb& mc) {
  const laws::Principal2D p = laws::principal_values_2d(sxx, syy, sxy);
  if (p.s1 > f_t) return true;
  return mc.mode(std::max(p.s1, s3), std::min(p.s2, s3), 1.0) != 0;
}

TEST(NearACriterion, NeverMissesAStateTheExactTestFindsEvenOnTheBoundary) {
  // Concrete-like strengths; random stress directions (sxx, syy, sxy, s3), each scaled by
  // bisection to the last double before the exact test fires and the first after: the filter
  // must pass every state the exact test finds, including the first one past the boundary.
  const double phi = 30 * M_PI / 180;
  const laws::StressMohrCoulomb mc{6e6, std::sin(phi), std::cos(phi), 30e6};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  int fired = 0, filtered = 0;
  for (int k = 0; k < 20000; ++k) {
    const double dir[4] = {uni(rng), uni(rng), uni(rng), k % 3 == 0 ? 0.0 : uni(rng)};
    const double f_t = k % 5 == 0 ? std::numeric_limits<double>::infinity() : 3e6;  // closing bonds: no tension check
    auto at = [&](double s) { return exact_criterion(s * dir[0], s * dir[1], s * dir[2], s * dir[3], f_t, mc); };
    auto near = [&](double s) {
      return laws::near_a_criterion(s * dir[0], s * dir[1], s * dir[2], s * dir[3], f_t, mc, 1.0);
    };
    double lo = 0, hi = 1e9;  // the exact test fires at 1e9 Pa in every direction
    ASSERT_TRUE(at(hi));
    for (int it = 0; it < 200 && std::nextafter(lo, hi) < hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (at(mid) ? hi : lo) = mid;
    }
    ASSERT_TRUE(at(hi));
    EXPECT_TRUE(near(hi)) << "missed a failing state at scale " << hi << " (direction " << k << ")";
    // Random states anywhere between: whatever fires must pass the filter.
    for (double f : {0.3, 0.9, 0.999, 1.0000001, 1.5, 4.0}) {
      const bool exact = at(f * hi), pass = near(f * hi);
      fired += exact;
      filtered += !pass;
      if (exact) {
        EXPECT_TRUE(pass) << "direction " << k << ", " << f << " x the boundary";
      }
    }
  }
  // The filter does its job: it rejects most states well inside the criteria (none of those
  // fire), so the exact principal stresses are computed only near them.
  EXPECT_GT(fired, 20000);
  EXPECT_GT(filtered, 30000);
}

TEST(NearACriterion, RejectsStatesFarInsideAndDefersDegenerateOnesToTheExactTest) {
  const double phi = 30 * M_PI / 180;
  const laws::StressMohrCoulomb mc{6e6, std::sin(phi), std::cos(phi), 30e6};
  EXPECT_FALSE(laws::near_a_criterion(1e5, -2e5, 3e4, 0.0, 3e6, mc, 1.0));
  EXPECT_FALSE(laws::near_a_criterion(-1e6, -1e6, 1e3, -1e6, 3e6, mc, 1.0));  // hydrostatic pressure
  EXPECT_TRUE(laws::near_a_criterion(3.1e6, 0.0, 1e4, 0.0, 3e6, mc, 1.0));      // past f_t
  EXPECT_TRUE(laws::near_a_criterion(0.0, 0.0, 0.0, 0.0, 3e6, mc, 1.0));        // zero deviator: exact path
  EXPECT_TRUE(laws::near_a_criterion(1e200, 0.0, 1e200, 0.0, 3e6, mc, 1.0));    // overflow of the square
  // Uniaxial compression 25 MPa: past 2 c cos(phi) / (1 - sin(phi)) = 20.8 MPa, inside it
  // when a random strength factor doubles the strengths.
  EXPECT_TRUE(laws::near_a_criterion(0.0, -25e6, 0.0, 0.0, 3e6, mc, 1.0));
  EXPECT_FALSE(laws::near_a_criterion(0.0, -25e6, 0.0, 0.0, 6e6, mc, 2.0));
}

// ---- runs ---------------------------------------------------------------------------------

/// A bar 20 mm wide and `height` tall (plane stress, 10 mm thick) pulled at its top.
std::string bar_case(double angle, double nu, const std::string& geometry, double radius_mm, double end) {
  std::ostringstream s;
  s.precision(12);
  const double rows = std::round(40.0 / (std::sqrt(3.0) * radius_mm));
  const double height = rows * std::sqrt(3.0) * radius_mm;
  s << "units = \"mm\"\n[case]\nname = \"bar\"\ngeometry = \"" << geometry << "\"\nthickness = 0.01\n"
    << "[mesh]\nradius = " << radius_mm * 1e-3 << "\nangle = " << angle << "\n"
    << "[[body]]\nname = \"bar\"\nmaterial = 1\n  [[body.shape]]\n  type = \"rectangle\"\n"
    << "  min = [0.0, 0.0]\n  max = [20.0, " << height << "]\n"
    << "  boundary = { bottom = \"base\", right = \"side\", top = \"grip\", left = \"side\" }\n"
    << "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = " << nu << "\n"
    << "tensile_strength = 3e6\ncompressive_strength = 30e6\ncohesion = 8.66e6\nfriction_angle = 30.0\n"
    << "fracture_energy = 100.0\nrate_dependent = false\n"
    << "[[boundary]]\nset = \"base\"\ntype = \"roller\"\ncomponent = \"y\"\n"
    << "[[boundary]]\nset = \"grip\"\ntype = \"velocity\"\nvy = 0.5\n"
    << "function = { type = \"table\", points = [[0.0, 0.0], [2e-5, 1.0], [1.0, 1.0]] }\n"
    << "[contact]\ndamping = 0.1\n"
    << "[random]\nseed = 1\ncorrelation_length = 5e-3\nstrength_cov = 0.1\n"
    << "[time]\nend = " << end << "\n";
  return s.str();
}

struct BarResult {
  bool finished = false;
  double max_error = 0, fracture = 0, min_bond_fracture = 0, peak = 0, break_kinetic = 0;
  std::size_t cracked = 0;
};

BarResult run_bar(const std::string& text) {
  const Case c = parse_case(text, "bar.toml", ".");
  Solver s(c, mesh_case(c));
  BarResult r;
  const std::int64_t steps = s.total_steps();
  const Model& m = s.model();
  for (std::int64_t n = 0; n <= steps; ++n) {
    if (!s.advance(true)) return r;
    r.max_error = std::max(r.max_error, std::abs(s.energy().relative_error()));
  }
  r.finished = true;
  r.fracture = s.energy().fracture;
  r.break_kinetic = s.energy().break_kinetic;
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    r.min_bond_fracture = std::min(r.min_bond_fracture, m.bond_fracture_energy(b));
    r.cracked += (!m.bond_intact(b) || m.bond_crack(b) != Model::kNoCrack) ? 1 : 0;
  }
  return r;
}

TEST(Softening, ABarPulledApartDissipatesGFTimesItsSectionAtEveryLatticeAngle) {
  // Pulled far past the crack opening w_c = 2 G_F / f_t = 67 um (0.5 m/s for 400 us: 190 um),
  // the bar separates; the fracture energy of the run is G_F x 20 mm x 10 mm = 0.02 J for
  // the separating crack plus what secondary cracks (at the grips, where the rows of a
  // rotated lattice meet the held edge unevenly) dissipate: at least 0.9 G_F A at every
  // angle (a brittle lattice dissipates a few % of it). The secondary cracks have no bound
  // of their own: the values are printed (measured 1.12 to 1.40 G_F A, docs/validation.md)
  // and not asserted beyond the lower bound. The random field (the same at every angle)
  // localises the crack; without it a perfect lattice under uniform stress cracks
  // everywhere at once.
  const double expected = 100.0 * 0.020 * 0.010;
  std::vector<double> energies;
  for (double angle : {0.0, 10.0, 20.0, 30.0}) {
    const BarResult r = run_bar(bar_case(angle, 0.2, "plane-stress", 0.5, 4e-4));
    ASSERT_TRUE(r.finished) << angle;
    std::printf("angle %4.0f: fracture %.4e J (%.3f x G_F A), break_kinetic %+.2e J, max |Err| %.2e, min per-bond "
                "%.2e J, cracked %zu\n",
                angle, r.fracture, r.fracture / expected, r.break_kinetic, r.max_error, r.min_bond_fracture, r.cracked);
    EXPECT_LE(r.max_error, 0.01) << angle;
    EXPECT_GT(r.fracture, 0.9 * expected) << angle;
    energies.push_back(r.fracture);
  }
  const auto [lo, hi] = std::minmax_element(energies.begin(), energies.end());
  std::printf("fracture energy over the angles: %.3f to %.3f x G_F A\n", *lo / expected, *hi / expected);
}

TEST(Softening, NegativeShearSpringsAreRefusedAsForTheBrittleLaw) {
  // nu = 0.3 in plane strain: k_s < 0. Softening bonds would leave the neighbours' negative
  // shear springs without the normal stiffness that keeps the lattice positive definite.
  const Case c = parse_case(bar_case(30.0, 0.3, "plane-strain", 0.5, 4e-4), "bar.toml", ".");
  try {
    Solver s(c, mesh_case(c));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shear springs that are not negative"), std::string::npos) << e.what();
  }
  // With [time] allow_unstable the run goes ahead, and the run health stops it. (Measured with
  // the strain of a disk without a fit frozen: at r = 1 mm the bar runs at 0-30 degrees but
  // its energy error reaches 1.3 % at 10 degrees and its fracture energy is 1.1-1.8 G_F A; at
  // r = 0.5 mm it runs at 0, 20 and 30 degrees and is stopped at 10.)
  const Case u = parse_case(bar_case(10.0, 0.3, "plane-strain", 0.5, 4e-4) + "allow_unstable = true\n", "bar.toml", ".");
  Solver s(u, mesh_case(u));
  bool stopped = false;
  for (std::int64_t n = 0; n <= s.total_steps() && !stopped; ++n) stopped = !s.advance(true);
  EXPECT_TRUE(stopped) << "a softening lattice with negative shear springs ran to its end";
}

/// A closed system: a 20 x 20 mm plate (plane stress, r = 1 mm) whose bonds across its middle
/// are cracking at damage D (set by hand, with the lattice at rest; strengths so high that no
/// other bond cracks and kappa so close to delta_f that D does not grow), the two halves
/// thrown at each other at 2 V. The crack closes, the halves bounce and it opens and closes
/// again: the only non-smooth term is the kink of the cracking bonds' normal springs at
/// delta = 0, from (1 - D) k_n open to the closed stiffness. Returns the largest |Err| and
/// the largest ratio, over the steps, of the ledger's error |E_in - E_t| to the bound that
/// central differences allow for a one-sided spring whose stiffness jumps by J = min(D k_n,
/// cap) (docs/model.md, "Fracture energy and softening").
struct ClosingCrack {
  double max_error = 0, max_over_bound = 0, bound = 0, input = 0;
  long crossings = 0;
};
ClosingCrack closing_crack(double angle, double damage) {
  const std::string text = hexdem::testing::softening_plate_case(
      angle, "tensile_strength = 3e9\ncompressive_strength = 30e9\ncohesion = 6e9\nfriction_angle = 30.0\n", "", 1e-4);
  const Case c = parse_case(text, "plate.toml", ".");
  Solver sv(c, mesh_case(c));
  Model& m = sv.model();
  const double mid = 0.01, v = 0.5;
  for (std::size_t b = 0; b < m.num_bonds(); ++b) {
    if ((m.y0[m.bi[b]] - mid) * (m.y0[m.bj[b]] - mid) >= 0) continue;
    Model::FailedBond& f = add_failed_row(m, b);
    f.crack = Model::kTensionCrack;
    f.damage = damage;
    f.delta0 = 1e-7;
    f.delta_f = 1e-3;
    f.kappa = 0.999e-3;
  }
  update_strain_matrices(m);  // at rest: no strain to carry over
  for (std::size_t i = 0; i < m.num_disks(); ++i) m.vy[i] = m.y0[i] > mid ? -v : v;
  ClosingCrack r;
  std::vector<double> last(m.num_bonds(), 0.0);
  for (std::int64_t n = 0; n <= sv.total_steps(); ++n) {
    if (!sv.advance(true)) break;  // the run health stops a run past 5 %
    // Across a crossing from a to b (opposite signs) the trapezoid rule of central
    // differences misses the spring's energy by J a b / 2, at most J (b - a)^2 / 8.
    for (std::size_t b = 0; b < m.num_bonds(); ++b) {
      const double delta = m.len_prev[b] - m.rest(b);
      if (n > 0 && m.bond_crack(b) != Model::kNoCrack && (delta > 0) != (last[b] > 0)) {
        const auto i = static_cast<std::size_t>(m.bi[b]), j = static_cast<std::size_t>(m.bj[b]);
        const double cap = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]) * m.contact_omega2;
        r.bound += std::min(m.bond_damage(b) * m.kn(b), cap) * (delta - last[b]) * (delta - last[b]) / 8;
        ++r.crossings;
      }
      last[b] = delta;
    }
    const EnergyBalance& e = sv.energy();
    r.max_error = std::max(r.max_error, std::abs(e.relative_error()));
    // 1e-5 of the input: the smooth terms (the lengths' geometry, the start), measured 2e-6.
    r.max_over_bound = std::max(r.max_over_bound, std::abs(e.input() - e.total()) / (r.bound + 1e-5 * e.input()));
    r.input = e.input();
  }
  return r;
}

TEST(Softening, AClosingCrackKeepsTheEnergyBalanceWithinTheContactResolution) {
  // A closed crack's damaged part of the stiffness, D k_n, acts as the contact the bond
  // becomes at D = 1 and is capped as every contact is, at m_eff (resolution / dt)^2; for
  // the bond's full k_n, omega dt = 0.92. Each crossing then costs at most resolution^2 / 4
  // of the pair's relative kinetic energy, and the error of the whole run stays within the
  // sum of those bounds (measured: 0.60 to 0.78 of it, max |Err| 1.3e-3 to 1.7e-3). With the
  // full k_n a closed crack carried before, the error was 6 to 12 times that sum and reached
  // 2.3 to 5 % of the input (the run health stopped the 20-degree plate at 5 %).
  for (double angle : {0.0, 10.0, 20.0, 30.0}) {
    const ClosingCrack r = closing_crack(angle, 0.9);
    std::printf("angle %4.0f: %ld crossings, max |Err| %.2e, bound %.2e of the input, error / bound %.2f\n", angle,
                r.crossings, r.max_error, r.bound / r.input, r.max_over_bound);
    EXPECT_GT(r.crossings, 100) << angle << ": the crack closes and opens";
    EXPECT_LE(r.max_over_bound, 1.0) << angle;
    EXPECT_LT(r.max_error, 5e-3) << angle;
  }
}

TEST(HoopCracking, AnExpandingRingCracksRadiallyAndKeepsItsEnergyBalance) {
  // A concrete ring (axisymmetric, r 20-30 mm, 10 mm tall) thrown outwards at 5 m/s: the hoop
  // strain u_r / r passes the tensile strength everywhere, the rings soften (radial cracks),
  // and the energy balance holds.
  const std::string text = hexdem::testing::expanding_ring_case();
  const Case c = parse_case(text, "ring.toml", ".");
  Solver s(c, mesh_case(c));
  double max_error = 0;
  for (std::int64_t n = 0; n <= s.total_steps(); ++n) {
    ASSERT_TRUE(s.advance(true)) << s.blow_up().reason;
    max_error = std::max(max_error, std::abs(s.energy().relative_error()));
  }
  const Model& m = s.model();
  ASSERT_FALSE(m.hoop_cracks.damage.empty());
  const double mean_damage = std::accumulate(m.hoop_cracks.damage.begin(), m.hoop_cracks.damage.end(), 0.0) / m.num_disks();
  const double hoop = std::accumulate(m.hoop_cracks.fracture.begin(), m.hoop_cracks.fracture.end(), 0.0);
  std::printf("ring: mean hoop damage %.3f, hoop fracture %.3e J/rad of %.3e, max |Err| %.2e\n", mean_damage, hoop,
              s.energy().input(), max_error);
  EXPECT_GT(mean_damage, 0.5);
  EXPECT_GT(hoop, 0.0);
  for (double h : m.hoop_cracks.fracture) EXPECT_GE(h, 0.0);
  EXPECT_LE(max_error, 0.01);
}

TEST(RandomField, IsReproducibleLognormalWithItsCorrelationLengthAndASecondIndependentStream) {
  // 40,000 points on a 2 m square grid: mean 1, coefficient of variation 0.15, correlation
  // exp(-1/2) at one correlation length.
  const double l = 0.01;
  std::vector<double> x, y;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      x.push_back(i * 0.01);
      y.push_back(j * 0.01);
    }
  const std::vector<double> f = lognormal_field(x, y, 7, l, 0.15);
  EXPECT_EQ(f, lognormal_field(x, y, 7, l, 0.15));
  EXPECT_NE(f, lognormal_field(x, y, 8, l, 0.15));
  const double mean = std::accumulate(f.begin(), f.end(), 0.0) / f.size();
  double var = 0;
  for (double v : f) var += (v - mean) * (v - mean);
  var /= f.size();
  EXPECT_NEAR(mean, 1.0, 0.02);
  EXPECT_NEAR(std::sqrt(var) / mean, 0.15, 0.03);
  // Correlation of ln f at a lag of one correlation length (one grid step here) along x.
  double c0 = 0, c1 = 0;
  std::vector<double> g(f.size());
  for (std::size_t k = 0; k < f.size(); ++k) g[k] = std::log(f[k]);
  const double gm = std::accumulate(g.begin(), g.end(), 0.0) / g.size();
  for (int i = 0; i + 1 < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      const double a = g[i * 200 + j] - gm, b = g[(i + 1) * 200 + j] - gm;
      c0 += a * a;
      c1 += a * b;
    }
  EXPECT_NEAR(c1 / c0, std::exp(-0.5), 0.05);
  // A point's value does not depend on which other points are evaluated (no lattice in it).
  const std::vector<double> one = lognormal_field({x[12345]}, {y[12345]}, 7, l, 0.15);
  EXPECT_EQ(one[0], f[12345]);
  // The stiffness field ([random] stiffness_cov): stream 1 of the same seed, stream 0 being
  // the strength field. Its own mean and coefficient of variation, and no correlation with the
  // strength field (docs/model.md, "Random stiffness").
  EXPECT_EQ(f, lognormal_field(x, y, 7, l, 0.15, 0));
  const std::vector<double> k = lognormal_field(x, y, 7, l, 0.2, 1);
  const double k_mean = std::accumulate(k.begin(), k.end(), 0.0) / k.size();
  double k_var = 0, cross = 0, k_log2 = 0;
  std::vector<double> h(k.size());
  for (std::size_t n = 0; n < k.size(); ++n) h[n] = std::log(k[n]);
  const double hm = std::accumulate(h.begin(), h.end(), 0.0) / h.size();
  for (std::size_t n = 0; n < k.size(); ++n) {
    k_var += (k[n] - k_mean) * (k[n] - k_mean);
    cross += (g[n] - gm) * (h[n] - hm);
    k_log2 += (h[n] - hm) * (h[n] - hm);
  }
  double g_log2 = 0;
  for (double v : g) g_log2 += (v - gm) * (v - gm);
  const double correlation = cross / std::sqrt(g_log2 * k_log2);
  std::printf("stiffness field: mean %.4f, cov %.4f; correlation of the logarithms with the strength field %+.4f\n",
              k_mean, std::sqrt(k_var / k.size()) / k_mean, correlation);
  EXPECT_NEAR(k_mean, 1.0, 0.02);
  EXPECT_NEAR(std::sqrt(k_var / k.size()) / k_mean, 0.2, 0.03);
  EXPECT_LT(std::abs(correlation), 0.05) << "the stiffness field is independent of the strength field";
}

}  // namespace
