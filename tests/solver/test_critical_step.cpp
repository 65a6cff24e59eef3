// The critical step's estimate on the edge band (time_step.cpp, "The edge band"): the largest
// eigenvalue of M^-1 K computed on the disks within 16 bonds of an irregular disk equals the
// whole model's Lanczos value to the iteration's own convergence (1e-6), never exceeds it
// (it is a principal submatrix's), and is what the solver's step is made of. A band too narrow
// to hold the edge mode gives a visibly lower value: the comparison can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/edge_band_plate.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// The edge band's test plate (tests/common/edge_band_plate.hpp).
std::string plate_case(const std::string& geometry, const std::string& shear_model) {
  return hexdem::testing::edge_band_plate_case(geometry, shear_model);
}

/// The solver's step from the whole model's Lanczos value omega2 (choose_time_step's rule).
double step_from(const Case& c, const Solver& s, double omega2) {
  const double dt_critical = std::min(s.time_step().dt_bloch, 2.0 / std::sqrt(1.02 * omega2));
  return c.time.end / std::ceil(c.time.end / (c.time.safety * dt_critical) - 1e-9);
}

/// The solver's estimate against the whole model's Lanczos value; `edge_mode`: the largest
/// mode lies more than 2 % above the bulk's (Bloch) top, so the solver takes the band's.
void compare(const std::string& geometry, const std::string& shear_model, bool edge_mode) {
  const Case c = parse_case(plate_case(geometry, shear_model), "band.toml", HEXDEM_SOURCE_DIR);
  Solver s(c, mesh_case(c));
  const std::size_t n = s.model().num_disks();
  const std::size_t used = s.finite_estimate_disks();
  const double dt = s.dt();
  std::size_t band_disks = 0;
  const auto band = s.band_omega2_max(16, 3, &band_disks);
  ASSERT_TRUE(band.has_value()) << "the band applies to a plane model";
  const double whole = s.finite_omega2_max();
  const auto narrow = s.band_omega2_max(1, 3);
  ASSERT_TRUE(narrow.has_value());
  const double bulk = 4.0 / (s.time_step().dt_bloch * s.time_step().dt_bloch);
  std::printf("%s, %s: %zu disks, band %zu; omega^2 max: whole %.10g (%.4f x Bloch), band %.10g (%.2e), one row "
              "%.10g (%.2e); the solver's estimate on %zu disks\n",
              geometry.c_str(), shear_model.c_str(), n, band_disks, whole, whole / bulk, *band, *band / whole - 1,
              *narrow, *narrow / whole - 1, used);
  EXPECT_LE(*band, whole * (1 + 1e-6)) << "a principal submatrix's largest eigenvalue is not above the whole's";
  EXPECT_EQ(whole / bulk > 1.02, edge_mode);
  if (edge_mode) {
    EXPECT_EQ(used, band_disks) << "the solver estimated its step on the edge band";
    EXPECT_LT(used, n / 2);
    EXPECT_NEAR(*band / whole, 1.0, 1e-6) << "the band holds the largest mode";
    EXPECT_LT(*narrow / whole, 1.0 - 1e-4) << "one row is too narrow for the edge mode: the comparison can fail";
  } else {
    EXPECT_EQ(used, n) << "an edge mode near the bulk's top: the solver estimated the whole model";
    EXPECT_LT(*band / whole, 1.0 - 1e-6) << "the reason for the rule: this mode reaches beyond the band";
  }
  EXPECT_EQ(dt, step_from(c, s, whole)) << "the step of the whole model's estimate";
}

TEST(CriticalStep, EdgeBandMatchesWholeModel) { compare("plane-strain", "local-strain", true); }
TEST(CriticalStep, EdgeModeNearTheBulkTopTakesTheWholeModel) { compare("plane-stress", "rotation", false); }

/// The band is built elastic (time_step.cpp): its estimate for a plate whose bonds break and
/// soften, or whose springs yield, equals the whole model's, whose probe runs the laws'
/// kernels, and the elastic plate's. The laws' kernels at rest are the same linear operator.
void compare_laws(const std::string& shear_model, const std::string& name, const std::string& keys) {
  const std::string elastic = plate_case("plane-strain", shear_model);
  std::string laws = elastic;
  laws.replace(laws.find("nu = 0.2\n"), 9, "nu = 0.2\n" + keys);
  const Case ce = parse_case(elastic, "elastic.toml", HEXDEM_SOURCE_DIR);
  const Case cl = parse_case(laws, "laws.toml", HEXDEM_SOURCE_DIR);
  Solver se(ce, mesh_case(ce));
  Solver sl(cl, mesh_case(cl));
  ASSERT_FALSE(sl.model().elastic_lattice()) << "the plate has laws";
  const auto band_elastic = se.band_omega2_max(16, 3);
  const auto band_laws = sl.band_omega2_max(16, 3);
  ASSERT_TRUE(band_elastic.has_value() && band_laws.has_value());
  const double whole_laws = sl.finite_omega2_max();
  std::printf("%s with %s: band %.12g, elastic plate's band %.12g, whole model with its laws %.12g (%.2e)\n",
              shear_model.c_str(), name.c_str(), *band_laws, *band_elastic, whole_laws, *band_laws / whole_laws - 1);
  EXPECT_NEAR(*band_laws / *band_elastic, 1.0, 1e-12) << "the band of a plate with laws is the elastic plate's";
  EXPECT_NEAR(*band_laws / whole_laws, 1.0, 1e-6) << "the laws' kernels at rest are the elastic operator";
  EXPECT_EQ(sl.dt(), se.dt());
}

TEST(CriticalStep, EdgeBandOfBreakableOrYieldingBondsIsTheElasticOperator) {
  const std::string softening =
      "tensile_strength = 3e6\ncompressive_strength = 30e6\ncohesion = 6e6\nfriction_angle = 30\n"
      "fracture_energy = 100\n";
  compare_laws("local-strain", "softening", softening);
  compare_laws("rotation", "softening", softening);
  compare_laws("rotation", "spring plasticity", "yield_stress = 20e6\ntangent_modulus = 3e9\nplasticity = \"spring\"\n");
}

TEST(CriticalStep, NoBandForAxisymmetricOrSmallModels) {
  // An axisymmetric model's rings differ from disk to disk: the whole model is estimated.
  std::string axi = plate_case("axisymmetric", "local-strain");
  axi.replace(axi.find("thickness = 0.01\n"), 17, "");
  axi.replace(axi.find("[[boundary]]\nset = \"mirror\""), 62, "");
  const Case ca = parse_case(axi, "axi.toml", HEXDEM_SOURCE_DIR);
  Solver sa(ca, mesh_case(ca));
  EXPECT_FALSE(sa.band_omega2_max(16, 3).has_value());
  EXPECT_EQ(sa.finite_estimate_disks(), sa.model().num_disks());
  // A plate of 4 x 4 mm is all band.
  std::string small = plate_case("plane-stress", "rotation");
  small.replace(small.find("max = [0.04, 0.04]"), 18, "max = [0.004, 0.004]");
  small.replace(small.find("[[body.shape]]\ntype = \"circle\""), std::string::npos, "");
  small += "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
           "[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n[time]\nend = 1e-6\n";
  const Case cs = parse_case(small, "small.toml", HEXDEM_SOURCE_DIR);
  Solver ss(cs, mesh_case(cs));
  EXPECT_FALSE(ss.band_omega2_max(16, 3).has_value());
  EXPECT_EQ(ss.finite_estimate_disks(), ss.model().num_disks());
}

TEST(CriticalStep, NoBandForAnIrregularLattice) {
  // [mesh] jitter moves the interior disks off their sites: the bulk is no Bloch lattice, so the
  // whole model is estimated, and the step lies below the whole model's critical step.
  const std::string text = std::string("[mesh]\njitter = 0.3\n") + plate_case("plane-stress", "local-strain");
  const Case c = parse_case(text, "jitter.toml", HEXDEM_SOURCE_DIR);
  Solver s(c, mesh_case(c));
  EXPECT_TRUE(s.model().kind_rest.empty()) << "the reference geometry is per bond";
  EXPECT_FALSE(s.band_omega2_max(16, 3).has_value());
  EXPECT_EQ(s.finite_estimate_disks(), s.model().num_disks());
  const double whole = s.finite_omega2_max();
  EXPECT_LE(s.dt(), 2.0 / std::sqrt(whole) * (1 + 1e-12));
}

TEST(CriticalStep, ThinSlitAndALightDiskStayInTheBand) {
  // A slit 0.3 r wide across the plate (in place of the hole): the disks beside it lose their
  // bonds across it or become semi-disks, and none keeps six bonds with a cut cell (which the
  // band would seed as irregular anyway: a lighter disk could carry a mode above the bulk's).
  // The band holds the largest mode.
  std::string cs = plate_case("plane-strain", "local-strain");
  const std::string circle = "type = \"circle\"\nrole = \"hole\"\ncenter = [0.025, 0.02]\nradius = 0.004\n";
  cs.replace(cs.find(circle), circle.size(),
             "type = \"rectangle\"\nrole = \"hole\"\nmin = [0.01, 0.02]\nmax = [0.03, 0.02003]\n");
  const Case c = parse_case(cs, "slit.toml", HEXDEM_SOURCE_DIR);
  Solver s(c, mesh_case(c));
  const Model& m = s.model();
  std::size_t cut_cells = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double hexagon = 2 * 1.7320508075688772935 * m.radius[i] * m.radius[i];
    if (m.initial_bonds(i) == 6 && m.kind[i] == 0 && m.cell_area[i] < hexagon * (1 - 1e-9)) ++cut_cells;
  }
  EXPECT_EQ(cut_cells, 0U) << "disks with six bonds and a cut cell";
  std::size_t band_disks = 0;
  const auto band = s.band_omega2_max(16, 3, &band_disks);
  ASSERT_TRUE(band.has_value());
  const double whole = s.finite_omega2_max();
  const double bulk = 4.0 / (s.time_step().dt_bloch * s.time_step().dt_bloch);
  std::printf("slit: %zu disks, band %zu; omega^2 max: whole %.10g (%.4f x Bloch), band %.10g (%.2e)\n",
              m.num_disks(), band_disks, whole, whole / bulk, *band, *band / whole - 1);
  EXPECT_GT(whole / bulk, 1.02) << "an edge mode: the solver takes the band";
  EXPECT_EQ(s.finite_estimate_disks(), band_disks);
  EXPECT_NEAR(*band / whole, 1.0, 1e-6);
  EXPECT_EQ(s.dt(), step_from(c, s, whole));

  // The guard: one disk in the bulk, 10 mm (50 bonds) from every edge, made four times
  // lighter (its cell a quarter of the hexagon) carries a mode far above the edge's; the band
  // seeds it as irregular and holds that mode too.
  Model& mm = s.model();
  std::size_t light = 0;
  double best = 1e300;
  for (std::size_t i = 0; i < mm.num_disks(); ++i) {
    const double d = std::hypot(mm.x0[i] - 0.02, mm.y0[i] - 0.03);
    if (d < best) {
      best = d;
      light = i;
    }
  }
  ASSERT_EQ(mm.initial_bonds(light), 6);
  mm.cell_area[light] *= 0.25;
  mm.mass[light] *= 0.25;
  const double whole_light = s.finite_omega2_max();
  const auto band_light = s.band_omega2_max(16, 3);
  ASSERT_TRUE(band_light.has_value());
  std::printf("a light disk: whole %.10g (%.4f x Bloch), band %.10g (%.2e)\n", whole_light, whole_light / bulk,
              *band_light, *band_light / whole_light - 1);
  EXPECT_GT(whole_light, 1.1 * whole) << "the light disk's mode is the largest";
  EXPECT_NEAR(*band_light / whole_light, 1.0, 1e-6) << "the band holds the light disk's mode";
}

}  // namespace
