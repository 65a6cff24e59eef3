// Case files (docs/case-format.md): a complete case, the three outline sources (inline,
// .toml file, .dxf drawing), and one test per kind of bad input, each checking that the
// one-line message names the file, the line, the key and the value.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"

namespace hexdem::solver {
namespace {

namespace fs = std::filesystem;

/// A fresh folder for the running test.
fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "case_toml" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

/// 1-based number of the first line of `text` containing `needle` (0 if none).
int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

/// The InputError message of f, or a note that it did not throw.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  return "(no error)";
}

Case parse(const std::string& text) {
  return parse_case(text, "case.toml", ".");
}

std::string parse_error(const std::string& text) {
  return error_of([&] { (void)parse(text); });
}

/// A small valid case in parts, so that each test can change one.
struct Parts {
  std::string head = "[case]\ngeometry = \"plane-stress\"\n";
  std::string outline = R"(
[[body]]
name = "plate"
material = 1
radius = 0.001
  [[body.shape]]
  type = "rectangle"
  min = [0.0, -0.02]
  max = [0.04, 0.0]
  boundary = { top = "load", left = "symmetry", bottom = "base" }
)";
  std::string materials = "\n[[material]]\nid = 1\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n";
  std::string time = "\n[time]\nend = 1e-4\n";
  std::string extra;

  [[nodiscard]] std::string text() const { return head + outline + materials + time + extra; }
};

constexpr const char* kCompleteCase = R"(units = "mm"

[case]
name = "halfplane"
geometry = "plane-stress"
thickness = 0.01
shear_model = "rotation"

[mesh]
radius = 0.5e-3
angle = 0.0
origin = [0.0, 0.0]

[[body]]
name = "plate"
material = 2
  [[body.shape]]
  type = "rectangle"
  min = [0.0, -50.0]
  max = [100.0, 0.0]
  boundary = { top = "load", left = "symmetry", bottom = "base", right = "far" }

[[body]]
name = "ball"
material = 1
radius = 0.25
  [[body.shape]]
  type = "circle"
  center = [50.0, 10.0]
  radius = 5.0
  boundary = "skin"

[[material]]
id = 2
name = "material-B"
density = 1244.0
c11 = 5.0961e9
c12 = 1.2256e9
c22 = 3.5359e9
c66 = 1.2198e9

[[material]]
id = 1
density = 7850
E = 210e9
nu = 0.3

[[boundary]]
set = "symmetry"
type = "roller"
component = "x"

[[boundary]]
set = "base"
type = "fixed"
fix_rotation = true

[[boundary]]
set = "far"
type = "velocity"
vy = -1.0
function = { type = "ramp-hold", t1 = 1e-5, t2 = 1.0 }

[[load]]
type = "pressure"
set = "load"
p0 = 1.0e6
window = { axis = "x", min = -0.02, max = 0.02 }
function = { type = "pulse", alpha = 5.689e9, beta = 2659.0 }

[[load]]
type = "body-force"
acceleration = [0.0, -9.81]
bodies = ["ball"]
function = { type = "table", points = [[0.0, 0.0], [1e-5, 1.0], [2e-5, 0.5]] }

[[initial_velocity]]
body = "ball"
velocity = [0.0, -100.0]

[time]
end = 104e-6
dt = 0.4e-6
safety = 0.8
allow_unstable = true
mass_damping = 1e6

[output]
interval = 10e-6
frames = false
probe_interval = 1e-6
compression_level = 6

[[probe]]
name = "p1"
point = [0.05, -0.01]
fields = ["velocity", "stress"]

[[probe]]
name = "p-2"
point = [0.0, 0.0]
)";

TEST(CaseToml, CompleteCase) {
  const Case c = parse(kCompleteCase);
  EXPECT_EQ(c.name, "halfplane");
  EXPECT_EQ(c.source, "case.toml");
  EXPECT_EQ(c.geometry, Geometry::PlaneStress);
  EXPECT_EQ(c.thickness, 0.01);
  EXPECT_EQ(c.shear_model, ShearModel::Rotation);
  EXPECT_TRUE(c.warnings.empty());

  // Outline: inline, in mm; [mesh] radius overrides the file-wide default, a body's own radius
  // overrides [mesh].
  ASSERT_EQ(c.outline.bodies.size(), 2u);
  const auto& plate = c.outline.bodies[0];
  EXPECT_EQ(plate.name, "plate");
  EXPECT_EQ(plate.material, 2);
  EXPECT_DOUBLE_EQ(*plate.radius, 0.5e-3);
  EXPECT_EQ(*plate.angle_deg, 0.0);
  ASSERT_EQ(plate.outers.size(), 1u);
  EXPECT_DOUBLE_EQ(plate.outers[0].points[2].x, 0.1);
  EXPECT_EQ(plate.where, "case.toml:14: body 'plate'");
  EXPECT_DOUBLE_EQ(*c.outline.bodies[1].radius, 0.25e-3);
  for (const char* set : {"load", "symmetry", "base", "far", "skin"})
    EXPECT_NE(std::find(c.outline.boundary_names.begin(), c.outline.boundary_names.end(), set),
              c.outline.boundary_names.end())
        << set;

  ASSERT_EQ(c.materials.size(), 2u);
  const Material* b = c.find_material(2);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->name, "material-B");
  EXPECT_FALSE(b->isotropic);
  EXPECT_EQ(b->density, 1244.0);
  EXPECT_EQ(b->c.c11, 5.0961e9);
  EXPECT_EQ(b->c.c12, 1.2256e9);
  EXPECT_EQ(b->c.c22, 3.5359e9);
  EXPECT_EQ(b->c.c66, 1.2198e9);
  const Material* steel = c.find_material(1);
  ASSERT_NE(steel, nullptr);
  EXPECT_EQ(steel->name, "material-1");
  EXPECT_TRUE(steel->isotropic);
  EXPECT_EQ(steel->density, 7850.0);
  EXPECT_EQ(steel->E, 210e9);
  EXPECT_EQ(steel->nu, 0.3);
  EXPECT_EQ(c.find_material(3), nullptr);

  ASSERT_EQ(c.boundaries.size(), 3u);
  EXPECT_EQ(c.boundaries[0].kind, BoundaryCondition::Kind::Roller);
  EXPECT_EQ(c.boundaries[0].set, "symmetry");
  EXPECT_EQ(c.boundaries[0].component, 0);
  EXPECT_EQ(
      c.boundaries[0].where,
      "case.toml:" + std::to_string(line_of(kCompleteCase, "[[boundary]]")) + ": boundary[0]");
  EXPECT_EQ(c.boundaries[1].kind, BoundaryCondition::Kind::Fixed);
  EXPECT_EQ(c.boundaries[1].set, "base");
  EXPECT_TRUE(c.boundaries[1].fix_rotation);
  const BoundaryCondition& v = c.boundaries[2];
  EXPECT_EQ(v.kind, BoundaryCondition::Kind::Velocity);
  EXPECT_FALSE(v.velocity[0].has_value());
  ASSERT_TRUE(v.velocity[1].has_value());
  EXPECT_EQ(*v.velocity[1], -1.0);
  EXPECT_EQ(v.function.kind, TimeFunction::Kind::RampHold);
  EXPECT_EQ(v.function.t1, 1e-5);
  EXPECT_EQ(v.function.t2, 1.0);

  ASSERT_EQ(c.loads.size(), 2u);
  const Load& p = c.loads[0];
  EXPECT_EQ(p.kind, Load::Kind::Pressure);
  EXPECT_EQ(p.set, "load");
  EXPECT_EQ(p.p0, 1.0e6);
  ASSERT_TRUE(p.window.has_value());
  EXPECT_EQ(p.window->axis, 0);
  EXPECT_EQ(p.window->min, -0.02);
  EXPECT_EQ(p.window->max, 0.02);
  EXPECT_EQ(p.function.kind, TimeFunction::Kind::Pulse);
  EXPECT_EQ(p.function.alpha, 5.689e9);
  EXPECT_EQ(p.function.beta, 2659.0);
  const Load& g = c.loads[1];
  EXPECT_EQ(g.kind, Load::Kind::BodyForce);
  EXPECT_EQ(g.acceleration[0], 0.0);
  EXPECT_EQ(g.acceleration[1], -9.81);
  EXPECT_EQ(g.bodies, std::vector<std::string>{"ball"});
  EXPECT_EQ(g.function.kind, TimeFunction::Kind::Table);
  ASSERT_EQ(g.function.table.size(), 3u);
  EXPECT_EQ(g.function.table[1], (std::pair<double, double>{1e-5, 1.0}));

  ASSERT_EQ(c.initial_velocities.size(), 1u);
  EXPECT_EQ(c.initial_velocities[0].body, "ball");
  EXPECT_EQ(c.initial_velocities[0].velocity[1], -100.0);

  EXPECT_EQ(c.time.end, 104e-6);
  ASSERT_TRUE(c.time.dt.has_value());
  EXPECT_EQ(*c.time.dt, 0.4e-6);
  EXPECT_EQ(c.time.safety, 0.8);
  EXPECT_TRUE(c.time.allow_unstable);
  EXPECT_EQ(c.time.mass_damping, 1e6);

  EXPECT_EQ(c.output.interval, 10e-6);
  EXPECT_FALSE(c.output.frames);
  EXPECT_EQ(c.output.probe_interval, 1e-6);
  EXPECT_EQ(c.output.compression_level, 6);

  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_EQ(c.probes[0].name, "p1");
  EXPECT_EQ(c.probes[0].point[0], 0.05);
  EXPECT_EQ(c.probes[0].fields, (std::vector<std::string>{"velocity", "stress"}));
  EXPECT_EQ(c.probes[1].name, "p-2");
  EXPECT_EQ(c.probes[1].fields,
            (std::vector<std::string>{"displacement", "velocity", "stress", "rotation", "spin"}));
}

TEST(CaseToml, Defaults) {
  const Case c = parse(Parts{}.text());
  EXPECT_EQ(c.name, "case");  // the file's stem
  EXPECT_EQ(c.thickness, 1.0);
  EXPECT_EQ(c.shear_model, ShearModel::LocalStrain);
  EXPECT_EQ(c.time.end, 1e-4);
  EXPECT_FALSE(c.time.dt.has_value());
  EXPECT_EQ(c.time.safety, 0.9);
  EXPECT_FALSE(c.time.allow_unstable);
  EXPECT_EQ(c.time.mass_damping, 0.0);
  EXPECT_EQ(c.output.interval, 0.0);
  EXPECT_TRUE(c.output.frames);
  EXPECT_EQ(c.output.probe_interval, 0.0);
  EXPECT_EQ(c.output.compression_level, 1);
  EXPECT_TRUE(c.output.body_history.empty());
  EXPECT_TRUE(c.boundaries.empty());
  EXPECT_TRUE(c.loads.empty());
  EXPECT_TRUE(c.probes.empty());
  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].name, "material-1");
}

TEST(CaseToml, AxisymmetricCase) {
  Parts parts;
  parts.head = "[case]\ngeometry = \"axisymmetric\"\n";
  parts.extra = "\n[[boundary]]\nset = \"symmetry\"\ntype = \"roller\"\ncomponent = \"r\"\n";
  const Case c = parse(parts.text());
  EXPECT_EQ(c.geometry, Geometry::Axisymmetric);
  ASSERT_EQ(c.boundaries.size(), 1u);
  EXPECT_EQ(c.boundaries[0].component, 0);
}

TEST(CaseToml, SymmetryBoundary) {
  Parts parts;
  parts.extra = "\n[[boundary]]\nset = \"symmetry\"\ntype = \"symmetry\"\ncomponent = \"x\"\n";
  const Case c = parse(parts.text());
  ASSERT_EQ(c.boundaries.size(), 1u);
  EXPECT_EQ(c.boundaries[0].kind, BoundaryCondition::Kind::Symmetry);
  EXPECT_EQ(c.boundaries[0].component, 0);
  parts.extra = "\n[[boundary]]\nset = \"symmetry\"\ntype = \"symmetry\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "[[boundary]]")) +
                ": boundary[0]: missing key 'component'");
}

TEST(CaseToml, DocumentedExamplesParse) {
  // Every ```toml block of docs/case-format.md is a complete case; the first uses the
  // half-plane outline of cases/halfplane.
  const fs::path dir = work_dir();
  std::ifstream doc(fs::path(HEXDEM_SOURCE_DIR) / "docs" / "case-format.md");
  ASSERT_TRUE(doc.good());
  fs::copy_file(fs::path(HEXDEM_SOURCE_DIR) / "cases" / "halfplane" / "outline.toml",
                dir / "outline.toml");
  std::string line, block;
  bool inside = false;
  int count = 0;
  while (std::getline(doc, line)) {
    if (!inside && line == "```toml") {
      inside = true;
      block.clear();
    } else if (inside && line == "```") {
      inside = false;
      const fs::path path = dir / ("example" + std::to_string(++count) + ".toml");
      write_file(path, block);
      EXPECT_NO_THROW((void)read_case(path.string())) << block;
    } else if (inside) {
      block += line + "\n";
    }
  }
  EXPECT_GE(count, 2);
}

TEST(CaseToml, OutlineFile) {
  const fs::path dir = work_dir();
  fs::create_directories(dir / "shapes");
  write_file(dir / "shapes" / "outline.toml", R"(units = "mm"
[lattice]
radius = 1.0
[[body]]
name = "plate"
  [[body.shape]]
  type = "rectangle"
  min = [0.0, 0.0]
  max = [20.0, 10.0]
  boundary = { top = "load", bottom = "base" }
)");
  Parts parts;
  parts.head +=
      "\n[mesh]\noutline = \"shapes/outline.toml\"\nangle = 60.0\norigin = [0.0005, 0.0]\n";
  parts.outline.clear();
  parts.extra = "\n[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n";
  const fs::path path = dir / "plate-case.toml";
  write_file(path, parts.text());

  const Case c = read_case(path.string());
  EXPECT_EQ(c.name, "plate-case");
  EXPECT_EQ(c.source, path.string());
  ASSERT_EQ(c.outline.bodies.size(), 1u);
  EXPECT_DOUBLE_EQ(*c.outline.bodies[0].radius, 1e-3);  // from the outline's [lattice]
  EXPECT_EQ(*c.outline.bodies[0].angle_deg, 60.0);      // from [mesh]
  EXPECT_EQ(c.outline.bodies[0].origin->x, 0.0005);
  EXPECT_NE(c.outline.source.find("outline.toml"), std::string::npos);
  EXPECT_EQ(c.boundaries.size(), 1u);

  // [mesh] radius overrides the outline's [lattice] radius.
  parts.head += "radius = 0.5e-3\n";
  write_file(path, parts.text());
  EXPECT_DOUBLE_EQ(*read_case(path.string()).outline.bodies[0].radius, 0.5e-3);
}

TEST(CaseToml, DxfOutline) {
  const fs::path dir = work_dir();
  // A 40 x 20 mm rectangle of four LINEs on layers bottom/right/top/left, and a SPLINE that
  // the reader skips with a warning. Written by ezdxf, independently of the reader (dxflib).
  write_file(dir / "make.py", R"(import sys
import ezdxf
doc = ezdxf.new('R2010')
doc.header['$INSUNITS'] = 4
msp = doc.modelspace()
msp.add_line((0, 0), (40, 0), dxfattribs={'layer': 'bottom'})
msp.add_line((40, 0), (40, 20), dxfattribs={'layer': 'right'})
msp.add_line((40, 20), (0, 20), dxfattribs={'layer': 'top'})
msp.add_line((0, 20), (0, 0), dxfattribs={'layer': 'left'})
msp.add_spline([(5, 5), (10, 8), (15, 5)])
doc.saveas(sys.argv[1])
)");
  const std::string command = std::string("'") + HEXDEM_SYSTEM_PYTHON + "' '" +
                              (dir / "make.py").string() + "' '" + (dir / "plate.dxf").string() +
                              "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  Parts parts;
  parts.head += "\n[mesh]\noutline = \"plate.dxf\"\nradius = 1e-3\n";
  parts.outline.clear();
  parts.extra =
      "\n[[boundary]]\nset = \"bottom\"\ntype = \"fixed\"\n"
      "\n[[load]]\ntype = \"pressure\"\nset = \"top\"\np0 = 1e6\n";
  write_file(dir / "case.toml", parts.text());
  const Case c = read_case((dir / "case.toml").string());
  ASSERT_EQ(c.outline.bodies.size(), 1u);
  EXPECT_EQ(c.outline.bodies[0].material, 1);
  EXPECT_DOUBLE_EQ(*c.outline.bodies[0].radius, 1e-3);
  EXPECT_NEAR(std::abs(meshing::signed_area(c.outline.bodies[0].outers[0])), 800e-6, 1e-12);
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_NE(c.warnings[0].find("SPLINE"), std::string::npos) << c.warnings[0];

  // Without [mesh] radius, a DXF outline is refused at the `outline` key.
  Parts no_radius = parts;
  no_radius.head = "[case]\ngeometry = \"plane-stress\"\n\n[mesh]\noutline = \"plate.dxf\"\n";
  write_file(dir / "case.toml", no_radius.text());
  EXPECT_EQ(error_of([&] { (void)read_case((dir / "case.toml").string()); }),
            (dir / "case.toml").string() +
                ":5: mesh.outline: a DXF outline needs the disk radius: give [mesh] radius (got "
                "\"plate.dxf\")");
}

TEST(CaseToml, UnknownKey) {
  Parts parts;
  parts.time = "\n[time]\nend = 1e-4\nsaftey = 0.5\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text),
            "case.toml:" + std::to_string(line_of(text, "saftey")) +
                ": time: unknown key 'saftey' (allowed: end, dt, safety, allow_unstable, "
                "mass_damping, energy_warning, energy_limit)");
  // At the top level, in a time function, and a key of another boundary type.
  parts = Parts{};
  parts.extra = "\n[timee]\nend = 1.0\n";
  EXPECT_NE(parse_error(parts.text())
                .find("case.toml:" + std::to_string(line_of(parts.text(), "[timee]")) +
                      ": unknown key 'timee' (allowed: case, mesh,"),
            std::string::npos);
  parts = Parts{};
  parts.extra =
      "\n[[load]]\ntype = \"pressure\"\nset = \"load\"\np0 = 1\n"
      "function = { type = \"pulse\", alpha = 1.0, beta = 2.0, gamma = 3.0 }\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "gamma")) +
                ": load[0].function: unknown key 'gamma' (allowed for type = \"pulse\": type, "
                "alpha, beta)");
  parts = Parts{};
  parts.extra = "\n[[boundary]]\nset = \"base\"\ntype = \"fixed\"\nvx = 1.0\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "vx =")) +
                ": boundary[0]: unknown key 'vx' (allowed for type = \"fixed\": set, type, "
                "fix_rotation)");
}

TEST(CaseToml, UnknownBoundarySet) {
  Parts parts;
  parts.extra =
      "\n[[boundary]]\nset = \"base\"\ntype = \"fixed\"\n"
      "\n[[boundary]]\nset = \"symetry\"\ntype = \"roller\"\ncomponent = \"x\"\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "\"symetry\"")) +
                                   ": boundary[1].set: unknown boundary set 'symetry' (sets: "
                                   "base, load, symmetry)");
  parts.extra = "\n[[load]]\ntype = \"pressure\"\nset = \"lod\"\np0 = 1e6\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "\"lod\"")) +
                ": load[0].set: unknown boundary set 'lod' (sets: base, load, symmetry)");
}

TEST(CaseToml, UnknownBody) {
  Parts parts;
  parts.extra = "\n[[initial_velocity]]\nbody = \"plat\"\nvelocity = [0.0, -100.0]\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "\"plat\"")) +
                ": initial_velocity[0].body: unknown body 'plat' (bodies: plate)");
  parts.extra =
      "\n[[load]]\ntype = \"body-force\"\nacceleration = [0.0, -9.81]\n"
      "bodies = [\"plate\", \"ball\"]\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "bodies =")) +
                ": load[0].bodies[1]: unknown body 'ball' (bodies: plate)");
}

TEST(CaseToml, BodyHistory) {
  Parts parts;
  parts.extra = "\n[output]\nbody_history = [\"plate\"]\n";
  EXPECT_EQ(parse(parts.text()).output.body_history, std::vector<std::string>{"plate"});
  parts.extra = "\n[output]\nbody_history = [\"plate\", \"ball\"]\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "body_history")) +
                ": output.body_history[1]: unknown body 'ball' (bodies: plate)");
  parts.extra = "\n[output]\nbody_history = [\"plate\", \"plate\"]\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "body_history")) +
                ": output.body_history[1]: duplicate body 'plate'");
  parts.extra = "\n[output]\nbody_history = \"plate\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "body_history")) +
                ": output.body_history: expected a non-empty array of names [\"...\", ...] (got \"plate\")");
  parts.extra = "\n[output]\nbody_history = []\n";
  EXPECT_NE(parse_error(parts.text()).find(": output.body_history: expected a non-empty array"),
            std::string::npos);
}

TEST(CaseToml, MissingMaterial) {
  Parts parts;
  parts.materials = "\n[[material]]\nid = 2\ndensity = 2400.0\nE = 30e9\nnu = 0.2\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "[[body]]")) +
                                   ": body 'plate': material: no [[material]] with id 1 (ids: 2)");
}

TEST(CaseToml, OrthotropicInAxisymmetric) {
  Parts parts;
  parts.head = "[case]\ngeometry = \"axisymmetric\"\n";
  parts.materials =
      "\n[[material]]\nid = 1\nname = \"material-B\"\ndensity = 1244.0\n"
      "c11 = 5.0961e9\nc12 = 1.2256e9\nc22 = 3.5359e9\nc66 = 1.2198e9\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text),
            "case.toml:" + std::to_string(line_of(text, "[[material]]")) +
                ": material[0]: material 'material-B' (id 1): orthotropic materials are not "
                "supported in axisymmetric mode (give E and nu)");
}

TEST(CaseToml, DiskPlasticityNeedsTheLocalStrainModel) {
  // The message names the shear model that conflicts, not only the plasticity's own value.
  Parts parts;
  parts.head = "[case]\ngeometry = \"plane-strain\"\nshear_model = \"rotation\"\n";
  parts.materials =
      "\n[[material]]\nid = 1\ndensity = 7800.0\nE = 210e9\nnu = 0.3\nyield_stress = 400e6\n"
      "tangent_modulus = 2e9\nplasticity = \"j2\"\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "plasticity")) +
                                   ": material[0].plasticity: \"j2\" needs [case] shear_model = \"local-strain\", "
                                   "not \"rotation\" (got \"j2\")");
}

TEST(CaseToml, ThicknessInAxisymmetric) {
  Parts parts;
  parts.head = "[case]\ngeometry = \"axisymmetric\"\nthickness = 0.01\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:3: case.thickness: not allowed in axisymmetric mode (quantities are per "
            "radian) (got 0.01)");
}

TEST(CaseToml, NegativeDensity) {
  Parts parts;
  parts.materials = "\n[[material]]\nid = 1\ndensity = -2400.0\nE = 30e9\nnu = 0.2\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "density")) +
                                   ": material[0].density: must be > 0 [kg/m^3] (got -2400)");
}

TEST(CaseToml, PoissonRatioTooLarge) {
  Parts parts;
  parts.materials = "\n[[material]]\nid = 1\ndensity = 2400.0\nE = 30e9\nnu = 0.5\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "nu =")) +
                                   ": material[0].nu: must lie in (-1, 0.5) (got 0.5)");
}

TEST(CaseToml, BothIsotropicAndOrthotropic) {
  Parts parts;
  parts.materials = "\n[[material]]\nid = 1\ndensity = 2400.0\nE = 30e9\nnu = 0.2\nc11 = 1e9\n";
  const std::string text = parts.text();
  EXPECT_EQ(parse_error(text),
            "case.toml:" + std::to_string(line_of(text, "E = 30e9")) +
                ": material[0]: give either E and nu (isotropic) or c11, c12, c22, c66 "
                "(orthotropic), not both");
  // Incomplete sets are errors too.
  parts.materials = "\n[[material]]\nid = 1\ndensity = 2400.0\nc11 = 1e9\nc22 = 1e9\n";
  EXPECT_NE(
      parse_error(parts.text()).find(": material[0]: missing key 'c12' (orthotropic material)"),
      std::string::npos);
  parts.materials = "\n[[material]]\nid = 1\ndensity = 2400.0\n";
  EXPECT_NE(parse_error(parts.text()).find(": material[0]: missing elastic constants"),
            std::string::npos);
}

TEST(CaseToml, BadTimeFunction) {
  const auto with_function = [](const std::string& function) {
    Parts parts;
    parts.extra =
        "\n[[load]]\ntype = \"pressure\"\nset = \"load\"\np0 = 1e6\nfunction = " + function + "\n";
    return parts.text();
  };
  std::string text = with_function("{ type = \"ramp\", t1 = 1e-5 }");
  const std::string line = std::to_string(line_of(text, "function ="));
  EXPECT_EQ(parse_error(text), "case.toml:" + line +
                                   ": load[0].function.type: expected one of \"constant\", "
                                   "\"pulse\", \"ramp-hold\", \"table\" (got \"ramp\")");
  text = with_function("{ type = \"ramp-hold\", t1 = 1e-5, t2 = 1e-6 }");
  EXPECT_EQ(parse_error(text),
            "case.toml:" + line + ": load[0].function.t2: must be >= t1 = 1e-05 (got 1e-06)");
  text = with_function("{ type = \"ramp-hold\", t1 = 0.0, t2 = 1e-6 }");
  EXPECT_EQ(parse_error(text), "case.toml:" + line + ": load[0].function.t1: must be > 0 (got 0)");
  text = with_function("{ type = \"pulse\", alpha = 5.689e9 }");
  EXPECT_EQ(parse_error(text), "case.toml:" + line + ": load[0].function: missing key 'beta'");
  text = with_function("{ type = \"table\", points = [[0.0, 0.0], [0.0, 1.0]] }");
  EXPECT_EQ(parse_error(text), "case.toml:" + line +
                                   ": load[0].function.points[1]: times must increase (got t = 0 "
                                   "after t = 0)");
  text = with_function("{ type = \"table\", points = [[0.0, 0.0]] }");
  EXPECT_NE(parse_error(text).find("load[0].function.points: expected at least 2 points"),
            std::string::npos);
  text = with_function("\"pulse\"");
  EXPECT_EQ(parse_error(text),
            "case.toml:" + line + ": load[0].function: expected a table { ... } (got \"pulse\")");
}

TEST(CaseToml, TimeStepNotPositive) {
  Parts parts;
  parts.time = "\n[time]\nend = 1e-4\ndt = 0.0\n";
  std::string text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "dt =")) +
                                   ": time.dt: must be > 0 (got 0)");
  parts.time = "\n[time]\nend = 1e-4\ndt = -1e-7\n";
  text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "dt =")) +
                                   ": time.dt: must be > 0 (got -1e-07)");
  parts.time = "\n[time]\nend = 1e-4\nsafety = 1.5\n";
  text = parts.text();
  EXPECT_EQ(parse_error(text), "case.toml:" + std::to_string(line_of(text, "safety")) +
                                   ": time.safety: must lie in (0, 1] (got 1.5)");
}

TEST(CaseToml, MeshJitter) {
  Parts parts;
  EXPECT_EQ(parse(parts.text()).mesh_jitter, 0.0);  // the regular lattice by default
  EXPECT_EQ(parse(parts.text()).mesh_jitter_seed, 1);
  parts.head += "[mesh]\njitter = 0.25\njitter_seed = 7\n";
  const Case c = parse(parts.text());
  EXPECT_EQ(c.mesh_jitter, 0.25);
  EXPECT_EQ(c.mesh_jitter_seed, 7);
  for (const char* bad : {"0.5", "-0.1"}) {
    parts.head = std::string("[case]\ngeometry = \"plane-stress\"\n[mesh]\njitter = ") + bad + "\n";
    EXPECT_EQ(parse_error(parts.text()), "case.toml:" + std::to_string(line_of(parts.text(), "jitter =")) +
                                             ": mesh.jitter: must lie in [0, 0.3] (a fraction of the disk radius) (got " +
                                             bad + ")");
  }
  parts.head = "[case]\ngeometry = \"plane-stress\"\n[mesh]\njitter = nan\n";
  EXPECT_EQ(parse_error(parts.text()), "case.toml:4: mesh.jitter: must be finite (got nan)");
  parts.head = "[case]\ngeometry = \"plane-stress\"\n[mesh]\njitter_seed = -1\n";
  EXPECT_NE(parse_error(parts.text()).find(": mesh.jitter_seed: "), std::string::npos) << parse_error(parts.text());
}

TEST(CaseToml, ContactRadiusSpread) {
  Parts parts;
  EXPECT_EQ(parse(parts.text()).contact.radius_spread, 0.0);  // every disk touches at r by default
  parts.head += "[contact]\nradius_spread = 0.1\n";
  EXPECT_EQ(parse(parts.text()).contact.radius_spread, 0.1);
  for (const char* bad : {"0.2", "-0.01", "nan"}) {
    parts.head = std::string("[case]\ngeometry = \"plane-stress\"\n[contact]\nradius_spread = ") + bad + "\n";
    const std::string want = std::string(bad) == "nan" ? ": contact.radius_spread: must be finite (got nan)"
                                                       : std::string(": contact.radius_spread: must lie in [0, 0.13] "
                                                                     "(a fraction of the disk radius) (got ") + bad + ")";
    EXPECT_EQ(parse_error(parts.text()), "case.toml:4" + want);
  }
}

TEST(CaseToml, ContactCapMass) {
  Parts parts;
  EXPECT_EQ(parse(parts.text()).contact.cap_mass, CapMass::Disk);  // the disks' own masses by default
  parts.head += "[contact]\ncap_mass = \"whole_cell\"\n";
  EXPECT_EQ(parse(parts.text()).contact.cap_mass, CapMass::WholeCell);
  parts.head = "[case]\ngeometry = \"plane-stress\"\n[contact]\ncap_mass = \"cell\"\n";
  const std::string why = parse_error(parts.text());
  EXPECT_EQ(why.rfind("case.toml:4: contact.cap_mass: ", 0), 0U) << why;
  EXPECT_NE(why.find("\"cell\""), std::string::npos) << why;
  EXPECT_NE(why.find("whole_cell"), std::string::npos) << why;  // names the choices
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;         // one line
}

TEST(CaseToml, MissingTimeEnd) {
  Parts parts;
  parts.time = "\n[time]\ndt = 1e-7\n";
  std::string text = parts.text();
  EXPECT_EQ(parse_error(text),
            "case.toml:" + std::to_string(line_of(text, "[time]")) + ": time: missing key 'end'");
  parts.time.clear();
  EXPECT_EQ(parse_error(parts.text()), "case.toml: missing table [time] (with at least `end`)");
}

TEST(CaseToml, MissingFile) {
  const fs::path dir = work_dir();
  const std::string path = (dir / "nowhere.toml").string();
  EXPECT_EQ(error_of([&] { (void)read_case(path); }), path + ": cannot open file");
  // A missing outline file is reported at the case file's `outline` key.
  Parts parts;
  parts.head += "\n[mesh]\noutline = \"missing.toml\"\n";
  parts.outline.clear();
  write_file(dir / "case.toml", parts.text());
  EXPECT_EQ(error_of([&] { (void)read_case((dir / "case.toml").string()); }),
            (dir / "case.toml").string() + ":5: mesh.outline: cannot open outline file '" +
                (dir / "missing.toml").string() + "' (got \"missing.toml\")");
}

TEST(CaseToml, ParseError) {
  Parts parts;
  parts.time = "\n[time]\nend = 1e-4 s\n";
  const std::string text = parts.text();
  const std::string message = parse_error(text);
  EXPECT_EQ(message.rfind("case.toml:" + std::to_string(line_of(text, "1e-4 s")) + ":", 0), 0u)
      << message;
  EXPECT_NE(message.find(": TOML parse error: "), std::string::npos) << message;
}

TEST(CaseToml, OtherBadInput) {
  // Missing [case] and bad geometry.
  Parts parts;
  parts.head.clear();
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml: missing table [case] (with at least `geometry`)");
  parts.head = "[case]\ngeometry = \"plane\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:2: case.geometry: expected one of \"plane-stress\", \"plane-strain\", "
            "\"axisymmetric\" (got \"plane\")");
  // No outline at all, and an outline given twice.
  parts = Parts{};
  parts.outline.clear();
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml: no outline: give [mesh] outline = \"FILE\" or inline [[body]] tables");
  parts = Parts{};
  parts.head += "\n[mesh]\noutline = \"outline.toml\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "[[body]]")) +
                ": body: not allowed together with [mesh] outline = \"outline.toml\" (give the "
                "outline in one place)");
  // Outline errors come from the outline reader, with the case file's lines.
  parts = Parts{};
  parts.outline += "  raduis = 2.0\n";
  EXPECT_NE(parse_error(parts.text())
                .find("case.toml:" + std::to_string(line_of(parts.text(), "raduis")) +
                      ": body[0].shape[0]: unknown key 'raduis'"),
            std::string::npos);
  // Velocity boundary without components; roller without a component.
  parts = Parts{};
  parts.extra = "\n[[boundary]]\nset = \"base\"\ntype = \"velocity\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "[[boundary]]")) +
                ": boundary[0]: a velocity boundary needs vx and/or vy");
  parts.extra = "\n[[boundary]]\nset = \"base\"\ntype = \"roller\"\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "[[boundary]]")) +
                ": boundary[0]: missing key 'component'");
  // Duplicate material id, bad probe name, bad probe field, window, compression level.
  parts = Parts{};
  parts.materials += parts.materials;
  EXPECT_NE(parse_error(parts.text()).find(": material[1].id: duplicate material id 1"),
            std::string::npos);
  parts = Parts{};
  parts.extra = "\n[[probe]]\nname = \"a b\"\npoint = [0.0, 0.0]\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "\"a b\"")) +
                ": probe[0].name: must consist of letters, digits, '_' and '-' (got \"a b\")");
  parts.extra = "\n[[probe]]\nname = \"a\"\npoint = [0.0, 0.0]\nfields = [\"strain\"]\n";
  EXPECT_NE(parse_error(parts.text()).find(": probe[0].fields[0]: unknown field 'strain'"),
            std::string::npos);
  parts.extra =
      "\n[[load]]\ntype = \"pressure\"\nset = \"load\"\np0 = 1e6\n"
      "window = { axis = \"x\", min = 0.02, max = -0.02 }\n";
  EXPECT_NE(
      parse_error(parts.text()).find(": load[0].window.max: must be > min = 0.02 (got -0.02)"),
      std::string::npos);
  parts.extra = "\n[output]\ncompression_level = 10\n";
  EXPECT_EQ(parse_error(parts.text()),
            "case.toml:" + std::to_string(line_of(parts.text(), "compression_level")) +
                ": output.compression_level: must lie in [0, 9] (got 10)");
  // Axisymmetric bodies must lie in r >= 0.
  parts = Parts{};
  parts.head = "[case]\ngeometry = \"axisymmetric\"\n";
  parts.outline = R"(
[[body]]
name = "plate"
radius = 0.001
  [[body.shape]]
  type = "rectangle"
  min = [-0.01, -0.02]
  max = [0.04, 0.0]
)";
  EXPECT_NE(parse_error(parts.text()).find("body 'plate': axisymmetric bodies must lie in r >= 0"),
            std::string::npos);
}

}  // namespace
}  // namespace hexdem::solver
