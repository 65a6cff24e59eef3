// The nonlocal criterion of softening materials ([[material]] nonlocal_radius; docs/model.md,
// "Nonlocal criterion"): the averaging rows against a brute-force search, the average of
// affine and linear strain fields against their closed forms, the refusals, and a restart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/checkpoint.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;

/// A 60 x 40 mm plate of softening concrete (r = 1 mm, the lattice at `angle`) and, apart
/// from it, a 10 mm steel block that does not average (a body of its own). Plane stress.
std::string plate_case(double angle, const std::string& nonlocal) {
  std::ostringstream s;
  s << "units = \"mm\"\n[case]\nname = \"plate\"\ngeometry = \"plane-stress\"\nthickness = 0.01\n"
    << "[mesh]\nradius = 1e-3\nangle = " << angle << "\n"
    << "[[body]]\nname = \"plate\"\nmaterial = 1\n  [[body.shape]]\n  type = \"rectangle\"\n"
    << "  min = [0.0, 0.0]\n  max = [60.0, 40.0]\n  boundary = { bottom = \"base\" }\n"
    << "[[body]]\nname = \"block\"\nmaterial = 2\n  [[body.shape]]\n  type = \"rectangle\"\n"
    << "  min = [64.0, 0.0]\n  max = [74.0, 10.0]\n"
    << "[[material]]\nid = 1\nname = \"concrete\"\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n"
    << "tensile_strength = 3e6\ncompressive_strength = 30e6\ncohesion = 8.66e6\nfriction_angle = 30.0\n"
    << "fracture_energy = 100.0\nrate_dependent = false\n" << nonlocal << "\n"
    << "[[material]]\nid = 2\nname = \"steel\"\ndensity = 7800.0\nE = 200e9\nnu = 0.3\n"
    << "[[boundary]]\nset = \"base\"\ntype = \"roller\"\ncomponent = \"y\"\n"
    << "[contact]\ndamping = 0.1\n[time]\nend = 2e-5\n[output]\ninterval = 1e-5\n";
  return s.str();
}

bool full(const Model& m, std::size_t j) { return m.strain.ok[j] && m.initial_bonds(j) == 6; }

/// The bonds that have started a tension crack (cracking or broken since).
std::size_t tension_cracks(const Model& m) {
  return static_cast<std::size_t>(std::count_if(m.failed_rows.begin(), m.failed_rows.end(),
                                                [](const Model::FailedBond& f) { return f.crack == Model::kTensionCrack; }));
}

TEST(NonlocalStrain, RowsHoldExactlyTheFullDisksOfTheBodyWithinTheRadius) {
  for (double angle : {0.0, 17.0}) {
    const Case c = parse_case(plate_case(angle, "nonlocal_radius = 3.5e-3"), "plate.toml", ".");
    Solver s(c, mesh_case(c));
    const Model& m = s.model();
    const NonlocalStrain& nl = m.nonlocal;
    ASSERT_EQ(nl.offset.size(), m.num_disks() + 1);
    const double R = 3.5e-3;
    std::size_t interior = 0, interior_count = 0;
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      std::vector<std::int32_t> expected;  // brute force over every disk
      if (m.body[i] == 0) {
        for (std::size_t j = 0; j < m.num_disks(); ++j) {
          const double d = std::hypot(m.x0[j] - m.x0[i], m.y0[j] - m.y0[i]);
          if (m.body[j] == m.body[i] && full(m, j) && d < R) expected.push_back(static_cast<std::int32_t>(j));
        }
      } else if (full(m, i)) {
        expected.push_back(static_cast<std::int32_t>(i));  // the block reads its own strain
      }
      const std::vector<std::int32_t> row(nl.nbr.begin() + nl.offset[i], nl.nbr.begin() + nl.offset[i + 1]);
      ASSERT_EQ(row, expected) << "disk " << i << " at angle " << angle;
      double sum = 0;
      for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        EXPECT_GT(nl.w[k], 0.0);
        sum += nl.w[k];
      }
      if (!row.empty()) {
        EXPECT_NEAR(sum, 1.0, 1e-14) << i;
      }
      // Far from the edges: the hexagonal lattice's disks within 3.5 r are the centre and
      // its rings at 2r (6), 2 sqrt(3) r (6): 13.
      const double x = m.x0[i] * 1e3, y = m.y0[i] * 1e3;
      if (m.body[i] == 0 && x > 8 && x < 52 && y > 8 && y < 32) {
        ++interior;
        interior_count += row.size();
        EXPECT_EQ(row.size(), 13u) << "disk " << i << " at angle " << angle;
      }
    }
    EXPECT_GT(interior, 100u);
    std::printf("angle %4.1f: %zu interior disks, %zu neighbours each\n", angle, interior,
                interior ? interior_count / interior : 0);
  }
}

TEST(NonlocalStrain, AveragesAnAffineFieldExactlyAndALinearStrainToItsCentreValue) {
  const Case c = parse_case(plate_case(23.0, "nonlocal_radius = 5e-3"), "plate.toml", ".");
  Solver s(c, mesh_case(c));
  Model m = s.model();
  // u = E x with E = (2, -1, 0.7) x 1e-4 (above f_t: every cell is hot and every disk is
  // averaged): the fits and so the averages are exactly E.
  const double exx = 2e-4, eyy = -1e-4, exy = 0.7e-4;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    m.ux[i] = exx * m.x0[i] + exy * m.y0[i];
    m.uy[i] = exy * m.x0[i] + eyy * m.y0[i];
  }
  compute_internal_forces(m, 1e-8);
  double worst = 0;
  std::size_t rows = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    if (m.body[i] != 0 || m.nonlocal.offset[i + 1] == m.nonlocal.offset[i]) continue;
    ++rows;
    worst = std::max({worst, std::abs(m.nonlocal.eps_xx[i] - exx), std::abs(m.nonlocal.eps_yy[i] - eyy),
                      std::abs(m.nonlocal.eps_xy[i] - exy)});
  }
  EXPECT_GT(rows, 600u);
  EXPECT_LT(worst, 1e-12 * 2e-4) << "affine field";
  // u_x = k x^2 / 2: eps_xx = k x, linear. The weights depend on distance only and a full
  // row around an interior disk is centrosymmetric, so the average is the centre's k x_i.
  const double k = 0.02;  // [1/m]: eps_xx >= 1.6e-4 (above f_t) from x = 8 mm on
  m = s.model();           // the first field started cracks (their fits changed): start again
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    m.ux[i] = 0.5 * k * m.x0[i] * m.x0[i];
    m.uy[i] = 0;
  }
  compute_internal_forces(m, 1e-8);
  worst = 0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double x = m.x0[i] * 1e3, y = m.y0[i] * 1e3;
    if (m.body[i] != 0 || x < 8 || x > 52 || y < 8 || y > 32) continue;
    ++interior;
    worst = std::max(worst, std::abs(m.nonlocal.eps_xx[i] - k * m.x0[i]));
  }
  EXPECT_GT(interior, 250u);
  EXPECT_LT(worst, 1e-9 * k * 0.06) << "linear strain";
}

TEST(NonlocalStrain, SkippingBondsFarFromEveryCriterionChangesNoBit) {
  // The plate pulled apart at its top (cracks start and grow) with the bound that skips the
  // bonds no criterion can reach, and with every bond averaged and checked: the same bits.
  std::string text = plate_case(11.0, "nonlocal_radius = 4e-3");
  const std::string sets = "boundary = { bottom = \"base\" }";
  text.replace(text.find(sets), sets.size(), "boundary = { bottom = \"base\", top = \"grip\" }");
  text += "[[boundary]]\nset = \"grip\"\ntype = \"velocity\"\nvy = 2.0\n[random]\nseed = 3\n"
          "correlation_length = 4e-3\nstrength_cov = 0.15\n";
  const Case c = parse_case(text, "plate.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice), b(c, lattice);
  b.model().nonlocal.skip_far = false;
  std::size_t skipped_steps = 0;
  for (int k = 0; k < 500; ++k) {
    ASSERT_TRUE(a.advance(k % 7 == 0));
    ASSERT_TRUE(b.advance(k % 7 == 0));
    const auto& hot = a.model().nonlocal.hot;
    if (std::count_if(hot.begin(), hot.end(), [](std::uint8_t h) { return (h & 1) == 0; }) > 0) ++skipped_steps;
  }
  const Model& ma = a.model();
  const Model& mb = b.model();
  EXPECT_GT(tension_cracks(ma), 0u) << "no crack started";
  EXPECT_GT(skipped_steps, 100u) << "the bound never skipped a cell";
  EXPECT_TRUE(ma.ux == mb.ux && ma.uy == mb.uy && ma.f_n == mb.f_n && ma.failed_rows == mb.failed_rows &&
              ma.failed_row == mb.failed_row);
  EXPECT_EQ(a.energy().total(), b.energy().total());
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
}

TEST(LocalCriterion, SkippingBondsFarFromEveryCriterionChangesNoBit) {
  // The local criterion's bound (Model::local_criterion): the plate pulled apart at its top
  // (cracks start and grow) with the bonds whose disks are far from every criterion skipped,
  // and with every bond checked (no classes: the Model a test builds by hand), in the three
  // geometries: the same bits.
  for (const char* geometry : {"plane-stress", "plane-strain", "axisymmetric"}) {
    SCOPED_TRACE(geometry);
    std::string text = plate_case(11.0, "");
    const std::string sets = "boundary = { bottom = \"base\" }";
    text.replace(text.find(sets), sets.size(), "boundary = { bottom = \"base\", top = \"grip\" }");
    text.replace(text.find("plane-stress"), 12, geometry);
    if (std::string(geometry) == "axisymmetric") text.erase(text.find("thickness = 0.01\n"), 17);  // per radian
    text += "[[boundary]]\nset = \"grip\"\ntype = \"velocity\"\nvy = 2.0\n[random]\nseed = 3\n"
            "correlation_length = 4e-3\nstrength_cov = 0.15\n";
    const Case c = parse_case(text, "plate.toml", ".");
    const meshing::Lattice lattice = mesh_case(c);
    Solver a(c, lattice), b(c, lattice);
    ASSERT_EQ(a.model().local_criterion.disk.size(), a.model().num_disks());
    b.model().local_criterion.disk.clear();
    std::size_t far_disks = 0, near_disks = 0;
    for (int k = 0; k < 500; ++k) {
      ASSERT_TRUE(a.advance(k % 7 == 0));
      ASSERT_TRUE(b.advance(k % 7 == 0));
      const auto& cls = a.model().local_criterion.disk;
      far_disks += static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 1));
      near_disks += static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 2));
    }
    const Model& ma = a.model();
    const Model& mb = b.model();
    EXPECT_GT(tension_cracks(ma), 0u) << "no crack started";
    EXPECT_GT(far_disks, 100u * near_disks / 100) << "the bound skipped too little to be tested";
    EXPECT_GT(near_disks, 0u) << "no disk came near a criterion";
    EXPECT_TRUE(ma.ux == mb.ux && ma.uy == mb.uy && ma.f_n == mb.f_n && ma.f_s == mb.f_s &&
                ma.failed_rows == mb.failed_rows && ma.failed_row == mb.failed_row);
    EXPECT_EQ(a.energy().total(), b.energy().total());
    EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
  }
}

TEST(NonlocalStrain, BadRadiiAreRefused) {
  const auto refused = [](const std::string& key, const std::string& needle) {
    try {
      const Case c = parse_case(plate_case(0.0, key), "plate.toml", ".");
      Solver s(c, mesh_case(c));
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(needle), std::string::npos) << what;
      return true;
    }
    return false;
  };
  EXPECT_TRUE(refused("nonlocal_radius = -1e-3", "nonlocal_radius"));
  EXPECT_TRUE(refused("nonlocal_radius = 2e-3", "not larger than the spacing 2r"));  // the neighbours' distance
  EXPECT_TRUE(refused("nonlocal_radius = 1e-3", "not larger than the spacing 2r"));
  // Rows longer than 10,000 disks, and rows whose total would pass 1e9 entries (12 GB), are
  // refused before they are built. A radius beyond the body is bounded by the body: the
  // plate's 693 disks average over each other.
  const auto refused_at = [](double r, const std::string& key, const std::string& needle) {
    std::string text = plate_case(0.0, key);
    text.replace(text.find("radius = 1e-3\n"), 14, "radius = " + std::to_string(r) + "\n");
    try {
      const Case c = parse_case(text, "plate.toml", ".");
      Solver s(c, mesh_case(c));
      EXPECT_EQ(s.model().nonlocal.offset.back(), s.model().nonlocal.nbr.size());
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(needle), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      return true;
    }
    return false;
  };
  EXPECT_TRUE(refused_at(2e-4, "nonlocal_radius = 25e-3", "over about 1.42e+04 disks, more than 10000"));  // 17,000 disks
  EXPECT_FALSE(refused_at(1e-3, "nonlocal_radius = 1e9", ""));     // the plate's 693 disks
  EXPECT_TRUE(refused_at(6.5e-5, "nonlocal_radius = 6.5e-3", "entries (12 bytes each), more than 1e+09"));  // 164,000 x 9,069
  // Only a softening material averages its criteria.
  EXPECT_THROW((void)parse_case(plate_case(0.0, "nonlocal_radius = 4e-3").replace(
                                    plate_case(0.0, "nonlocal_radius = 4e-3").find("fracture_energy = 100.0"),
                                    std::string("fracture_energy = 100.0").size(), "fracture_energy = 0.0"),
                                "plate.toml", "."),
               InputError);
  // A radius of 0 is the local criterion: no rows are built.
  const Case c = parse_case(plate_case(0.0, "nonlocal_radius = 0.0"), "plate.toml", ".");
  Solver s(c, mesh_case(c));
  EXPECT_TRUE(s.model().nonlocal.offset.empty());
}

TEST(ShearSoftening, NeedsAFractureEnergy) {
  std::string text = plate_case(0.0, "shear_softening = true");
  text.replace(text.find("fracture_energy = 100.0"), std::string("fracture_energy = 100.0").size(), "fracture_energy = 0.0");
  try {
    (void)parse_case(text, "plate.toml", ".");
    FAIL() << "shear_softening without a fracture energy was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("plate.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("shear_softening"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // With one, it is accepted and reaches the model.
  const Case c = parse_case(plate_case(0.0, "shear_softening = true"), "plate.toml", ".");
  Solver s(c, mesh_case(c));
  EXPECT_TRUE(s.model().softening[0].shear);
}

/// plate_case with its top edge a set "grip" held at the velocity `velocity` ("vy = 2.0"...).
std::string gripped_plate(double angle, const std::string& extra, const std::string& velocity) {
  std::string text = plate_case(angle, extra);
  const std::string sets = "boundary = { bottom = \"base\" }";
  text.replace(text.find(sets), sets.size(), "boundary = { bottom = \"base\", top = \"grip\" }");
  return text + "[[boundary]]\nset = \"grip\"\ntype = \"velocity\"\n" + velocity + "\n";
}

/// Writes a checkpoint of `a`, reads it into a second solver of the same case, advances both
/// `steps` steps and expects the same bits (checkpoints byte for byte, the ledger's total).
void expect_bit_identical_continuation(const Case& c, const meshing::Lattice& lattice, Solver& a, int steps,
                                       const std::string& tag) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("hexdem_test_" + tag + "_" + std::to_string(::getpid()));
  fs::create_directories(d);
  RunState run;
  write_checkpoint((d / "a.chk").string(), a, run);
  Solver b(c, lattice);
  RunState back;
  read_checkpoint((d / "a.chk").string(), b, back);
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(a.advance(k % 7 == 0));
    ASSERT_TRUE(b.advance(k % 7 == 0));
  }
  write_checkpoint((d / "a2.chk").string(), a, run);
  write_checkpoint((d / "b2.chk").string(), b, run);
  const auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream str;
    str << in.rdbuf();
    return str.str();
  };
  EXPECT_TRUE(slurp(d / "a2.chk") == slurp(d / "b2.chk")) << "the continuation differs";
  EXPECT_EQ(a.energy().total(), b.energy().total());
  fs::remove_all(d);
}

TEST(NonlocalStrain, ARunRestartsBitIdentically) {
  // The plate pulled apart at its top: cracks start by the nonlocal criterion; a checkpoint
  // written mid-way continues to the same bits (the rows are rebuilt from the case, the
  // averages from the strains).
  const Case c = parse_case(gripped_plate(11.0, "nonlocal_radius = 4e-3", "vy = 2.0"), "plate.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  std::size_t cracking = 0;
  for (int k = 0; k < 400 && cracking == 0; ++k) {
    ASSERT_TRUE(a.advance(k % 7 == 0));
    cracking = tension_cracks(a.model());
  }
  ASSERT_GT(cracking, 0u) << "no crack started";
  expect_bit_identical_continuation(c, lattice, a, 60, "nonlocal");
}

TEST(ShearSoftening, ARunWithSlidingShearCracksRestartsBitIdentically) {
  // The plate's top pushed down and sideways: shear cracks start (shear_softening) and their
  // closed faces slip; a checkpoint written then continues to the same bits (the slip is in
  // the failed bonds' rows).
  const Case c = parse_case(gripped_plate(11.0, "shear_softening = true", "vx = 3.0\nvy = -1.0"), "plate.toml", ".");
  const meshing::Lattice lattice = mesh_case(c);
  Solver a(c, lattice);
  const auto sliding = [](const Model& m) {
    std::size_t n = 0;
    for (std::size_t b = 0; b < m.num_bonds(); ++b)
      n += m.bond_crack(b) == Model::kShearCrack && m.bond_intact(b) && m.failed_or_none(b).slip != 0.0 ? 1 : 0;
    return n;
  };
  int k = 0;
  for (; k < 20000 && sliding(a.model()) < 5; ++k) ASSERT_TRUE(a.advance(k % 7 == 0));
  ASSERT_GE(sliding(a.model()), 5u) << "no shear crack slid within " << k << " steps";
  expect_bit_identical_continuation(c, lattice, a, 200, "shear");
  EXPECT_GT(a.energy().friction, 0.0);
  EXPECT_LE(std::abs(a.energy().relative_error()), 0.01);
  std::printf("after %d steps: %zu sliding shear cracks, friction %.3e J, fracture %.3e J, |Err| %.2e\n", k,
              sliding(a.model()), a.energy().friction, a.energy().fracture, std::abs(a.energy().relative_error()));
}

}  // namespace
