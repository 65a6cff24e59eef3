// Elastic runs checked against independent numbers: wave speeds of material B (physics.md
// section 9, from ../shared/reference/lattice_reference.py), 1D bar theory for the narrow
// plate under the Eq. 23 ramp, the energy balance (Eq. 25), the critical time step (a run just
// above it blows up, just below it does not), the Lame thick-walled cylinder in axisymmetry,
// and thread-count independence of the written frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/solver/output.hpp"
#include "hexdem/solver/solver.hpp"

namespace {

using namespace hexdem;
using namespace hexdem::solver;
namespace fs = std::filesystem;

constexpr double kSqrt3 = 1.7320508075688772935;

const char* kMaterialB = R"(
[[material]]
id = 1
name = "material-B"
density = 1244.0
c11 = 5.0961e9
c12 = 1.2256e9
c22 = 3.5359e9
c66 = 1.2198e9
)";

Case parse(const std::string& text) { return parse_case(text, "test.toml", HEXDEM_SOURCE_DIR); }

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// Runs a solver to its end time without output, calling `each` at every step's t_n.
void run(Solver& s, const std::function<void(const Solver&)>& each = {}, bool diagnostics = false) {
  const std::int64_t steps = s.total_steps();
  for (std::int64_t n = 0; n <= steps; ++n) ASSERT_TRUE(s.advance(diagnostics, each)) << s.blow_up().reason;
}

/// Time at which the mean of `v` over the disks `sel` first reaches `level`, interpolated.
struct Crossing {
  std::vector<std::size_t> disks;
  double level = 0;
  double time = -1;
  double prev_t = 0, prev_v = 0;
  void sample(double t, double v) {
    if (time < 0 && v >= level && t > 0) time = prev_t + (level - prev_v) / (v - prev_v) * (t - prev_t);
    prev_t = t;
    prev_v = v;
  }
};

/// Plane wave along x or y in a strip of material B driven by a smooth velocity step on one
/// end; returns the speed of the half-amplitude point between two stations.
double measure_wave_speed(bool along_x, bool longitudinal) {
  const double r = 0.5e-3, d = 2 * r, h = kSqrt3 * r;
  const double len = 240 * d, width = along_x ? 6 * h : 6 * d;
  const double x1 = 60 * d, x2 = 180 * d;
  const double c_expected = along_x ? (longitudinal ? std::sqrt(5.0961e9 / 1244) : std::sqrt(1.2198e9 / 1244))
                                    : (longitudinal ? std::sqrt(3.5359e9 / 1244) : std::sqrt(1.2198e9 / 1244));
  const double t_end = (x2 + 20 * d) / c_expected;
  const std::string drive_axis = along_x == longitudinal ? "vx" : "vy";
  // Sides: hold the displacement component that keeps the wave plane (uniaxial strain for
  // the longitudinal wave, pure shear for the transverse one).
  const std::string side_component = drive_axis == "vx" ? "y" : "x";
  std::string outline;
  if (along_x) {
    outline = "[[body]]\nname = \"strip\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [" + num(len) + ", " +
              num(width) + "]\nboundary = { bottom = \"side\", right = \"far\", top = \"side\", left = \"drive\" }\n";
  } else {
    outline = "[[body]]\nname = \"strip\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [" + num(width) + ", " +
              num(len) + "]\nboundary = { bottom = \"drive\", right = \"side\", top = \"far\", left = \"side\" }\n";
  }
  const std::string text = "[case]\ngeometry = \"plane-strain\"\n[lattice]\nradius = " + num(r) + "\n" + outline +
                           kMaterialB +
                           "[[boundary]]\nset = \"side\"\ntype = \"roller\"\ncomponent = \"" + side_component + "\"\n"
                           "[[boundary]]\nset = \"drive\"\ntype = \"velocity\"\n" + drive_axis +
                           " = 1.0\nfunction = { type = \"ramp-hold\", t1 = 4e-6, t2 = 1.0 }\n"
                           "[time]\nend = " + num(t_end) + "\n";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  const Model& m = s.model();
  Crossing a, b;
  a.level = b.level = 0.5;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double pos = along_x ? m.x0[i] : m.y0[i];
    if (std::abs(pos - x1) < 0.6 * d) a.disks.push_back(i);
    if (std::abs(pos - x2) < 0.6 * d) b.disks.push_back(i);
  }
  EXPECT_GT(a.disks.size(), 3u);
  const bool drive_x = drive_axis == "vx";
  run(s, [&](const Solver& sv) {
    for (Crossing* cr : {&a, &b}) {
      double sum = 0;
      for (std::size_t i : cr->disks) sum += drive_x ? sv.vx_mid(i) : sv.vy_mid(i);
      cr->sample(sv.time(), sum / static_cast<double>(cr->disks.size()));
    }
  });
  EXPECT_GT(a.time, 0);
  EXPECT_GT(b.time, a.time);
  const double speed = (x2 - x1) / (b.time - a.time);
  std::printf("wave %s along %s: measured %.2f m/s, continuum %.2f m/s (%+.3f %%)\n",
              longitudinal ? "qP" : "qS", along_x ? "x" : "y", speed, c_expected,
              100 * (speed / c_expected - 1));
  return speed;
}

TEST(WaveSpeed, MaterialBLongitudinalAlongX) { EXPECT_NEAR(measure_wave_speed(true, true), 2024.0, 0.01 * 2024.0); }
TEST(WaveSpeed, MaterialBLongitudinalAlongY) { EXPECT_NEAR(measure_wave_speed(false, true), 1685.9, 0.01 * 1685.9); }
TEST(WaveSpeed, MaterialBTransverseAlongX) { EXPECT_NEAR(measure_wave_speed(true, false), 990.2, 0.01 * 990.2); }
TEST(WaveSpeed, MaterialBTransverseAlongY) { EXPECT_NEAR(measure_wave_speed(false, false), 990.2, 0.01 * 990.2); }

/// sigma_y along the axis of the narrow plate at t = 104 us against 1D plane-stress bar
/// theory: a ramp front moving at c = sqrt((c22 - c12^2/c11)/rho) (physics.md section 9).
TEST(NarrowPlate, StressAlongTheAxisMatchesBarTheory) {
  const Case c = read_case(std::string(HEXDEM_SOURCE_DIR) + "/cases/narrow_plate/case.toml");
  Solver s(c, mesh_case(c));
  run(s, {}, true);
  const Model& m = s.model();
  const double t = s.time() - s.dt();  // the last t_n that was completed
  ASSERT_NEAR(t, 104e-6, 1e-12);
  const double cbar = std::sqrt((3.5359e9 - 1.2256e9 * 1.2256e9 / 5.0961e9) / 1244.0);
  double num2 = 0, den2 = 0;
  int count = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    if (m.x0[i] > 1e-9) continue;  // the disks on the plate's axis (the symmetry plane)
    const double y = -m.y0[i];
    const double theory = -10e6 * std::clamp((t - y / cbar) / 100e-6, 0.0, 1.0);
    const double sim = disk_stress(m, i).yy;
    num2 += (sim - theory) * (sim - theory);
    den2 += theory * theory;
    ++count;
  }
  EXPECT_GT(count, 150);
  const double l2 = std::sqrt(num2 / den2);
  std::printf("narrow plate: L2 relative error of sigma_y on the axis at 104 us: %.4f\n", l2);
  EXPECT_LT(l2, 0.03) << "L2 relative error of sigma_y on the axis";
  RecordProperty("l2_error", std::to_string(l2));
}

std::string small_plate(const std::string& model, const std::string& time, const std::string& material = "") {
  return "[case]\ngeometry = \"plane-stress\"\nshear_model = \"" + model + "\"\n[lattice]\nradius = 0.5e-3\n"
         "[[body]]\nname = \"plate\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [0, -0.04]\nmax = [0.02, 0]\n"
         "boundary = { bottom = \"bottom\", right = \"right\", top = \"load\", left = \"left\" }\n" +
         (material.empty() ? std::string(kMaterialB) : material) +
         "[[boundary]]\nset = \"bottom\"\ntype = \"fixed\"\n"
         "[[load]]\ntype = \"pressure\"\nset = \"load\"\np0 = 1e6\nfunction = { type = \"pulse\", alpha = 5.689e9, beta = 2659.0 }\n"
         "window = { axis = \"x\", min = 0.0, max = 0.01 }\n" + time;
}

const char* kConcrete = R"(
[[material]]
id = 1
name = "concrete"
density = 2400.0
E = 30e9
nu = 0.2
)";

double max_energy_error(Solver& s) {
  double worst = 0;
  run(s, [&](const Solver& sv) {
    if (sv.step_index() > 20) worst = std::max(worst, std::abs(sv.energy().relative_error()));
  }, true);
  std::printf("%s: largest |relative energy error| %.3g\n",
              ::testing::UnitTest::GetInstance()->current_test_info()->name(), worst);
  return worst;
}

TEST(EnergyBalance, UndampedLocalStrainRunConservesEnergy) {
  const Case c = parse(small_plate("local-strain", "[time]\nend = 60e-6\n"));
  Solver s(c, mesh_case(c));
  EXPECT_LT(max_energy_error(s), 1e-3);
  EXPECT_GT(s.energy().input(), 0.0);
}

TEST(EnergyBalance, UndampedRotationModelRunConservesEnergy) {
  const Case c = parse(small_plate("rotation", "[time]\nend = 60e-6\n", kConcrete));
  Solver s(c, mesh_case(c));
  EXPECT_LT(max_energy_error(s), 1e-3);
}

TEST(EnergyBalance, DampedRunBalancesDissipation) {
  const Case c = parse(small_plate("local-strain", "[time]\nend = 60e-6\nmass_damping = 2e5\n"));
  Solver s(c, mesh_case(c));
  EXPECT_LT(max_energy_error(s), 1e-3);
  EXPECT_GT(s.energy().damping, 0.1 * s.energy().input()) << "damping should dissipate a good part";
}

TEST(EnergyBalance, ProjectileKineticEnergyIsTheInput) {
  const std::string text = "[case]\ngeometry = \"plane-strain\"\n[lattice]\nradius = 0.5e-3\n"
                           "[[body]]\nname = \"block\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [0, 0]\nmax = [0.02, 0.01]\n"
                           "boundary = { bottom = \"base\", right = \"r\", top = \"t\", left = \"l\" }\n" +
                           std::string(kConcrete) +
                           "[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n"
                           "[[initial_velocity]]\nbody = \"block\"\nvelocity = [0.0, -5.0]\n[time]\nend = 40e-6\n";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  EXPECT_LT(max_energy_error(s), 1e-3);
  EXPECT_GT(s.energy().initial, 0.0);
  EXPECT_GT(s.energy().elastic, 0.1 * s.energy().initial);
}

TEST(Stability, RotationModelIsRefusedForMaterialB) {
  const Case c = parse(small_plate("rotation", "[time]\nend = 1e-6\n"));
  try {
    Solver s(c, mesh_case(c));
    FAIL() << "material B accepted with the rotation model";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("material-B"), std::string::npos) << msg;
    EXPECT_NE(msg.find("c66 - c12"), std::string::npos) << msg;
    EXPECT_NE(msg.find("local-strain"), std::string::npos) << msg;
  }
}

/// With allow_unstable the paper's model runs on material B, and its growing mode is caught by
/// the blow-up check well within the first microseconds (Bloch e-folding time about 1.2 us).
TEST(Stability, RotationModelOnMaterialBBlowsUpWhenAllowed) {
  Case c = parse(small_plate("rotation", "[time]\nend = 60e-6\nallow_unstable = true\n[output]\ninterval = 5e-6\n"));
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "rotation_blowup";
  fs::remove_all(dir);
  c.name = "rotation";
  const Solver warned(c, mesh_case(c));
  ASSERT_EQ(warned.warnings().size(), 1u);
  EXPECT_NE(warned.warnings()[0].find("c66 - c12"), std::string::npos) << warned.warnings()[0];
  RunOptions ro;
  ro.out_dir = dir.string();
  ro.quiet = true;
  EXPECT_EQ(run_case(c, ro), kExitRunFailed) << "the unstable lattice ran to the end without blowing up";
}

TEST(Stability, RotationModelIsRefusedForPlaneStrainSteel) {
  const char* steel = "[[material]]\nid = 1\nname = \"steel\"\ndensity = 7850.0\nE = 210e9\nnu = 0.3\n";
  std::string text = small_plate("rotation", "[time]\nend = 1e-6\n", steel);
  text.replace(text.find("plane-stress"), 12, "plane-strain");
  const Case c = parse(text);
  EXPECT_THROW(Solver(c, mesh_case(c)), InputError);
  std::string ok = text;
  ok.replace(ok.find("\"rotation\""), 10, "\"local-strain\"");
  const Case c2 = parse(ok);
  EXPECT_NO_THROW(Solver(c2, mesh_case(c2)));
}

TEST(Stability, UserTimeStepAboveCriticalIsRefused) {
  const Case c = parse(small_plate("local-strain", "[time]\nend = 1e-6\ndt = 1e-6\n"));
  try {
    Solver s(c, mesh_case(c));
    FAIL() << "dt above the critical step accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("allow_unstable"), std::string::npos) << e.what();
  }
}

/// A run 5 % above the critical step blows up, is detected and keeps its last good frame; a
/// run 5 % below it is stable. This pins the computed critical step to within 5 %.
TEST(Stability, CriticalStepSeparatesStableFromUnstable) {
  const Case probe = parse(small_plate("local-strain", "[time]\nend = 1e-6\n"));
  const double dt_c = Solver(probe, mesh_case(probe)).time_step().dt_critical;
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "stability";
  fs::remove_all(dir);
  for (const double factor : {0.95, 1.05}) {
    Case c = parse(small_plate("local-strain", "[time]\nend = 300e-6\ndt = " + num(factor * dt_c) +
                                                   "\nallow_unstable = true\n[output]\ninterval = 5e-6\n"));
    c.name = factor < 1 ? "below" : "above";
    RunOptions ro;
    ro.out_dir = dir.string();
    ro.quiet = true;
    const int code = run_case(c, ro);
    if (factor < 1) {
      EXPECT_EQ(code, 0) << "a run 5 % below the critical step failed";
      continue;
    }
    EXPECT_EQ(code, kExitRunFailed) << "a run 5 % above the critical step did not blow up";
    // The .pvd lists complete frames only, and the last one is finite.
    std::ifstream pvd(dir / "above.pvd");
    std::stringstream ss;
    ss << pvd.rdbuf();
    const std::string text = ss.str();
    EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
    const auto pos = text.rfind("file=\"");
    ASSERT_NE(pos, std::string::npos);
    const std::string last = text.substr(pos + 6, text.find('"', pos + 6) - pos - 6);
    EXPECT_TRUE(fs::exists(dir / last)) << last;
  }
}

/// Lame's thick-walled cylinder (inner radius a, outer b) under internal pressure p, long in z
/// (symmetry planes top and bottom): u_r = A r + B / r with A = (1+nu)(1-2nu) p a^2 / (E (b^2-a^2)),
/// B = (1+nu) p a^2 b^2 / (E (b^2-a^2)). Checks the hoop term of the axisymmetric model.
TEST(Axisymmetric, LameCylinderUnderInternalPressure) {
  const double r = 0.25e-3, h = kSqrt3 * r;
  const double a = 10e-3, b = 20e-3, height = 8 * h;
  const double E = 30e9, nu = 0.2, p = 10e6;
  const std::string text =
      "[case]\ngeometry = \"axisymmetric\"\n[lattice]\nradius = " + num(r) + "\n"
      "[[body]]\nname = \"tube\"\n[[body.shape]]\ntype = \"rectangle\"\nmin = [" + num(a) + ", 0]\nmax = [" + num(b) +
      ", " + num(height) + "]\nboundary = { bottom = \"end\", right = \"outer\", top = \"end\", left = \"inner\" }\n" +
      std::string(kConcrete) +
      "[[boundary]]\nset = \"end\"\ntype = \"symmetry\"\ncomponent = \"y\"\n"
      "[[load]]\ntype = \"pressure\"\nset = \"inner\"\np0 = " + num(p) +
      "\nfunction = { type = \"ramp-hold\", t1 = 10e-6, t2 = 1.0 }\n"
      "[time]\nend = 150e-6\nmass_damping = 2.5e5\n";
  const Case c = parse(text);
  Solver s(c, mesh_case(c));
  run(s);
  const Model& m = s.model();
  const double A = (1 + nu) * (1 - 2 * nu) * p * a * a / (E * (b * b - a * a));
  const double B = (1 + nu) * p * a * a * b * b / (E * (b * b - a * a));
  // Displacements disk by disk: the discretisation error is of the order r / a.
  double worst_u = 0;
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const double u = A * m.x0[i] + B / m.x0[i];
    worst_u = std::max(worst_u, std::abs(m.ux[i] - u) / u);
  }
  EXPECT_LT(worst_u, r / a) << "radial displacement against Lame's solution";
  // Stresses averaged over radial bins one spacing wide (the lattice alternates row by row),
  // two disks away from the faces.
  const double k = p * a * a / (b * b - a * a);
  double worst_s = 0;
  for (double r0 = a + 4 * r; r0 + 2 * r <= b - 4 * r + 1e-12; r0 += 2 * r) {
    double srr = 0, stt = 0, sr = 0;
    int n = 0;
    for (std::size_t i = 0; i < m.num_disks(); ++i) {
      if (m.x0[i] < r0 || m.x0[i] >= r0 + 2 * r) continue;
      const Stress st = disk_stress(m, i);
      srr += st.xx;
      stt += st.zz;
      sr += m.x0[i];
      ++n;
    }
    ASSERT_GT(n, 0);
    const double rr = sr / n;
    worst_s = std::max({worst_s, std::abs(srr / n - k * (1 - b * b / (rr * rr))) / p,
                        std::abs(stt / n - k * (1 + b * b / (rr * rr))) / p});
  }
  std::printf("Lame cylinder: worst u_r error %.4f (bound r/a = %.4f), band stress error %.4f p\n", worst_u,
              r / a, worst_s);
  EXPECT_LT(worst_s, 0.01) << "radial and hoop stress against Lame's solution, relative to p";
}

TEST(Determinism, OneAndTwoThreadsWriteIdenticalFrames) {
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "determinism";
  fs::remove_all(dir);
  Case c = parse(small_plate("local-strain", "[time]\nend = 20e-6\n[output]\ninterval = 10e-6\n"));
  for (int threads : {1, 2}) {
    c.name = "t" + std::to_string(threads);
    RunOptions ro;
    ro.out_dir = dir.string();
    ro.threads = threads;
    ro.quiet = true;
    ASSERT_EQ(run_case(c, ro), 0);
  }
  int compared = 0;
  for (const auto& e : fs::directory_iterator(dir / "t1")) {
    const std::string name = e.path().filename().string();
    const fs::path other = dir / "t2" / ("t2" + name.substr(2));
    std::ifstream f1(e.path(), std::ios::binary), f2(other, std::ios::binary);
    const std::string b1((std::istreambuf_iterator<char>(f1)), {}), b2((std::istreambuf_iterator<char>(f2)), {});
    EXPECT_FALSE(b1.empty());
    EXPECT_EQ(b1, b2) << name << " differs between 1 and 2 threads";
    ++compared;
  }
  EXPECT_EQ(compared, 3);
  std::ifstream e1(dir / "t1.energy.csv"), e2(dir / "t2.energy.csv");
  const std::string s1((std::istreambuf_iterator<char>(e1)), {}), s2((std::istreambuf_iterator<char>(e2)), {});
  EXPECT_EQ(s1, s2);
}

}  // namespace
