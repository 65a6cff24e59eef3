// Hostile input to the outline readers and the lattice generator: every case here once
// crashed, tripped a sanitizer, ended as an internal error or was read silently wrong. Each
// must now be an InputError (exit 2 in the program) with a one-line message that names the
// file and the value.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/outline.hpp"
#include "hexdem/meshing/outline_dxf.hpp"
#include "hexdem/meshing/outline_toml.hpp"
#include "hexdem/meshing/text.hpp"
#include "hexdem/meshing/toml_values.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hexdem::meshing;
using hexdem::InputError;

fs::path work_dir() {
  const fs::path d = fs::path(HEXDEM_TEST_WORK_DIR) / "meshing_hostile";
  fs::create_directories(d);
  return d;
}

/// The message of the InputError that `f` throws ("" and a test failure if none).
template <typename F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    return what;
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

std::string rectangle_outline(const std::string& lattice, const std::string& min,
                              const std::string& max, const std::string& extra = "") {
  return "[lattice]\n" + lattice + "\n[[body]]\nname = \"plate\"\n" + extra +
         "[[body.shape]]\ntype = \"rectangle\"\nmin = " + min + "\nmax = " + max + "\n";
}

Lattice generate(const std::string& toml, std::int64_t max_disks = kDefaultMaxDisks) {
  const Outline outline = parse_outline_toml(toml, "hostile.toml", {});
  GeneratorOptions go;
  go.max_disks = max_disks;
  return generate_lattice(outline, go);
}

// ---- lattice size ---------------------------------------------------------------------

TEST(HostileInput, TinyRadiusIsRefusedBeforeTheRowIndexOverflows) {
  // Was: signed overflow in build_edges (UBSan) for the row index of r = 1e-300.
  const std::string msg = input_error(
      [] { generate(rectangle_outline("radius = 1e-300", "[0, 0]", "[1, 1]")); });
  EXPECT_NE(msg.find("hostile.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit 2^30"), std::string::npos) << msg;
}

TEST(HostileInput, HugeRadiusNamesTheRegionsSize) {
  // Was: "too large for the region (0 x 0 m ...)": the region's size was taken after a
  // perturbation of a fraction of the disk diameter, which swamped it.
  const std::string msg = input_error(
      [] { generate(rectangle_outline("radius = 1e300", "[0, 0]", "[0.02, 0.01]")); });
  EXPECT_NE(msg.find("disk radius 1e+300 m is too large for the region (0.02 x 0.01 m"), std::string::npos) << msg;
}

TEST(HostileInput, HugeCoordinatesAreRefused) {
  // Was: a 3-disk mesh with region area inf and error -nan (from a DXF at 1e300).
  const std::string msg = input_error(
      [] { generate(rectangle_outline("radius = 1e-3", "[1e300, 1e300]", "[2e300, 2e300]")); });
  EXPECT_NE(msg.find("coordinate out of range"), std::string::npos) << msg;
  const std::string msg308 = input_error(
      [] { generate(rectangle_outline("radius = 1e-3", "[-1e308, -1e308]", "[1e308, 1e308]")); });
  EXPECT_NE(msg308.find("1e+308"), std::string::npos) << msg308;
}

TEST(HostileInput, DiskCountIsEstimatedAndRefusedBeforeAllocating) {
  // Was: a 1.15 TB allocation request (std::bad_alloc, an internal error) at r = 1e-9.
  // 1 m^2 / (2 sqrt(3) r^2) = 2.9e17 disks: beyond the reader's ceiling of 1e12.
  const std::string absurd = input_error(
      [] { generate(rectangle_outline("radius = 1e-9", "[0, 0]", "[1, 1]")); });
  EXPECT_NE(absurd.find("hostile.toml: about 2.88675e+17 disks"), std::string::npos) << absurd;
  EXPECT_NE(absurd.find("limit of 1000000000000"), std::string::npos) << absurd;
  // r = 1e-6: 2.9e11 disks, within the ceiling, refused by the generator's limit.
  const std::string toml = rectangle_outline("radius = 1e-6", "[0, 0]", "[1, 1]");
  const std::string msg = input_error([&] { generate(toml); });
  EXPECT_NE(msg.find("hostile.toml: about 2.88675e+11 disks"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit of 100000000 "), std::string::npos) << msg;
  EXPECT_NE(msg.find(" GB"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--max-disks N"), std::string::npos) << msg;
}

TEST(HostileInput, DiskLimitCanBeRaisedAndLowered) {
  // 10 mm x 10 mm at r = 0.5 mm: about 115 disks.
  const std::string toml = rectangle_outline("radius = 0.5e-3", "[0, 0]", "[0.01, 0.01]");
  EXPECT_GT(generate(toml, 200).num_disks(), 100U);
  const std::string msg = input_error([&] { generate(toml, 50); });
  EXPECT_NE(msg.find("about 115.47 disks"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit of 50"), std::string::npos) << msg;
}

TEST(HostileInput, ThinTallSliverCountsItsRows) {
  // Tiny area, many lattice rows: the row arrays alone would be large.
  const std::string toml = rectangle_outline("radius = 1e-3", "[0, 0]", "[2.5e-3, 1e5]");
  const std::string msg = input_error([&] { generate(toml, 1000000); });
  EXPECT_NE(msg.find("disks"), std::string::npos) << msg;
}

// ---- names -----------------------------------------------------------------------------

TEST(HostileInput, BoundaryNamedLikeAPointArrayIsRefused) {
  // Was: internal error "point array 'body' appears twice" when writing the mesh.
  for (const std::string name : {"body", "radius", "kind", "cell_area", "material"}) {
    const std::string toml = "[lattice]\nradius = 1e-3\n[[body]]\nname = \"p\"\n[[body.shape]]\n"
                             "type = \"rectangle\"\nmin = [0, 0]\nmax = [0.01, 0.01]\nboundary = \"" +
                             name + "\"\n";
    const std::string msg = input_error([&] { generate(toml); });
    EXPECT_NE(msg.find("boundary set (layer) name '" + name + "' is reserved"), std::string::npos)
        << msg;
  }
}

TEST(HostileInput, NulInBodyNameIsRefused) {
  // Was: internal error "field data string 'body_names' contains a NUL".
  const std::string toml = rectangle_outline("radius = 1e-3", "[0, 0]", "[0.01, 0.01]");
  std::string bad = toml;
  bad.replace(bad.find("\"plate\""), 7, "\"pl\\u0000ate\"");
  const std::string msg = input_error([&] { generate(bad); });
  EXPECT_NE(msg.find("hostile.toml:4: body[0].name: must not hold control characters"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("\\x00"), std::string::npos) << msg;
}

TEST(HostileInput, NewlinesInQuotedStringsStayOnOneLine) {
  const std::string msg = input_error([] {
    parse_outline_toml("units = \"m\\nm\"\n[[body]]\nname = \"a\"\n", "hostile.toml", {});
  });
  EXPECT_NE(msg.find("unknown unit \"m\\nm\""), std::string::npos) << msg;
  const std::string key = input_error(
      [] { parse_outline_toml("\"bad\\nkey\" = 1\n", "hostile.toml", {}); });
  EXPECT_NE(key.find("unknown key 'bad\\nkey'"), std::string::npos) << key;
}

// ---- arcs --------------------------------------------------------------------------------

TEST(HostileInput, HugeBulgeIsRefused) {
  // Was: a non-finite arc centre that reached CGAL (internal error).
  const std::string toml =
      "[lattice]\nradius = 1e-3\n[[body]]\nname = \"a\"\n[[body.shape]]\ntype = \"path\"\n"
      "start = [0, 0]\nsegments = [ { to = [0.01, 0] }, { to = [0.01, 0.01], bulge = 1e300 },\n"
      "  { to = [0, 0.01] }, { to = [0, 0] } ]\n";
  const std::string msg = input_error([&] { generate(toml); });
  EXPECT_NE(msg.find("hostile.toml:8: body[0].shape[0].segments[1].bulge: too large"),
            std::string::npos)
      << msg;
}

TEST(HostileInput, ArcNeedingTooManyChordsIsRefused) {
  const std::string toml =
      "[lattice]\nradius = 1e-12\n[[body]]\nname = \"a\"\n[[body.shape]]\ntype = \"circle\"\n"
      "center = [0, 0]\nradius = 1e6\n";
  const std::string msg = input_error([&] { parse_outline_toml(toml, "hostile.toml", {}); });
  EXPECT_NE(msg.find("hostile.toml:5: body[0].shape[0]: an arc of radius"), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("chords"), std::string::npos) << msg;
}

// ---- TOML nesting and file size ------------------------------------------------------------

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) out += s;
  return out;
}

TEST(HostileInput, DeeplyNestedDottedKeyIsRefusedBeforeParsing) {
  // Was: toml++ recursed until the stack overflowed (SIGSEGV) at 50,000 levels.
  const std::string msg = input_error(
      [] { parse_toml(repeat("a.", 50000) + "b = 1\n", "deep.toml"); });
  EXPECT_NE(msg.find("deep.toml:1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("key nested 257 levels deep (limit 256)"), std::string::npos) << msg;
  const std::string header = input_error(
      [] { parse_toml("x = 1\n[" + repeat("a.", 50000) + "b]\n", "deep.toml"); });
  EXPECT_NE(header.find("deep.toml:2:"), std::string::npos) << header;
  const std::string arrays = input_error(
      [] { parse_toml("x = " + repeat("[", 50000) + repeat("]", 50000) + "\n", "deep.toml"); });
  EXPECT_NE(arrays.find("value nested 257 levels deep"), std::string::npos) << arrays;
  const std::string tables = input_error(
      [] { parse_toml("x = " + repeat("{a=", 50000) + "1" + repeat("}", 50000) + "\n", "deep.toml"); });
  EXPECT_NE(tables.find("value nested 257 levels deep"), std::string::npos) << tables;
}

TEST(HostileInput, OrdinaryNestingAndDotsInValuesAreAccepted) {
  // Dots in numbers, strings and comments are not key levels; 256 levels are allowed.
  std::string floats = "p = [";
  for (int k = 0; k < 1000; ++k) floats += "1.5, ";
  floats += "2.5]\ns = \"" + repeat(".", 1000) + "\"\n# " + repeat(".", 1000) + "\n" +
            "m = '''\n" + repeat("a.", 1000) + "\n'''\n" + repeat("k.", 255) + "z = 1\n";
  EXPECT_NO_THROW(parse_toml(floats, "ok.toml"));
}

TEST(HostileInput, InputFilesAreReadUpToALimit) {
  // Was: /dev/zero as an outline was read without limit (4.2 GB). A device (or a FIFO, which
  // blocked the open for ever) is now refused before it is opened; a large file is capped.
  const std::string dev = input_error([] { read_text_file("/dev/zero", 1 << 20); });
  EXPECT_EQ(dev, "/dev/zero: not a regular file (a FIFO, device or socket); give a file");
  const std::string big = (work_dir() / "big.toml").string();
  std::ofstream(big, std::ios::binary) << std::string((1 << 20) + 1, ' ');
  const std::string msg = input_error([&] { read_text_file(big, 1 << 20); });
  EXPECT_EQ(msg, big + ": file larger than 1048576 bytes (not an outline or case file?)");
  const std::string dir = input_error([] { read_text_file("/tmp"); });
  EXPECT_EQ(dir, "/tmp: is a folder, not a file");
}

// ---- DXF -------------------------------------------------------------------------------------

/// A minimal ASCII DXF with one closed LWPOLYLINE through `points` ("x", "y" text pairs).
std::string dxf_polyline(const std::vector<std::pair<std::string, std::string>>& points,
                         const std::string& layer = "0") {
  std::string t = "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n" + layer + "\n90\n" +
                  std::to_string(points.size()) + "\n70\n1\n";
  for (const auto& [x, y] : points) t += "10\n" + x + "\n20\n" + y + "\n";
  return t + "0\nENDSEC\n0\nEOF\n";
}

std::string write_file(const std::string& name, const std::string& text) {
  const fs::path p = work_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

ReadOptions dxf_options() {
  ReadOptions o;
  o.radius = 0.5e-3;
  return o;
}

TEST(HostileInput, DxfWithNanOrInfCoordinateIsRefused) {
  // Was: dxflib read "nan" as 0, and a square became a triangle.
  for (const std::string bad : {"nan", "inf", "-inf", "1e400", "abc"}) {
    const std::string path = write_file(
        "nan.dxf", dxf_polyline({{"0", "0"}, {"0.01", "0"}, {"0.01", bad}, {"0", "0.01"}}));
    const std::string msg = input_error([&] { read_outline_dxf(path, dxf_options()); });
    EXPECT_NE(msg.find(path + ":24: group code 20 of LWPOLYLINE: not a finite number (got '" +
                       bad + "')"),
              std::string::npos)
        << msg;
  }
  // Coordinates near 1e300 were read, and meshed into 3 disks with region area inf.
  const std::string huge = write_file(
      "huge.dxf", dxf_polyline({{"1e300", "1e300"}, {"2e300", "1e300"}, {"2e300", "2e300"}, {"1e300", "2e300"}}));
  const std::string msg = input_error([&] { read_outline_dxf(huge, dxf_options()); });
  EXPECT_NE(msg.find("coordinate out of range"), std::string::npos) << msg;
  // The same square with good numbers (also with a decimal comma, as dxflib allows) reads.
  const std::string good = write_file(
      "good.dxf", dxf_polyline({{"0", "0"}, {"0,01", "0"}, {"0.01", "1e-2"}, {"+0", "0.01"}}));
  const Outline outline = read_outline_dxf(good, dxf_options());
  ASSERT_EQ(outline.bodies.size(), 1U);
  EXPECT_EQ(outline.bodies[0].outers.at(0).points.size(), 4U);
}

TEST(HostileInput, DxfCircleWithNegativeRadiusIsRefused) {
  const std::string path = write_file(
      "circle.dxf",
      "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n8\nrim\n10\n0\n20\n0\n40\n-5\n0\nENDSEC\n0\nEOF\n");
  const std::string msg = input_error([&] { read_outline_dxf(path, dxf_options()); });
  EXPECT_EQ(msg, path + ": CIRCLE on layer 'rim' has radius -5 (must be > 0)");
}

TEST(HostileInput, DxfHugeCircleIsRefusedQuickly) {
  // Found by the fuzzer: a circle of radius 4e9 mm at r = 0.5 mm was flattened into 7 million
  // chords that CGAL then validated (28 s and 1.8 GB before the size was refused).
  const std::string path = write_file(
      "huge_circle.dxf",
      "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n"
      "0\nCIRCLE\n8\nrim\n10\n0\n20\n0\n40\n4000000000\n0\nENDSEC\n0\nEOF\n");
  const auto start = std::chrono::steady_clock::now();
  const std::string msg = input_error([&] { read_outline_dxf(path, dxf_options()); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(msg, path + ": an arc of radius 4e+09 would need more than 1000000 chords at a chord "
                        "error of 0.0005 (the disk radius is too small for the arc)");
  EXPECT_LT(seconds, 5.0);
}

TEST(HostileInput, OutlineSizeIsCheckedBeforeValidation) {
  // A circle of 1e5 m at r = 0.5 mm: 3.6e16 disks; refused by the reader's ceiling before its
  // 62,000 chords are validated.
  const std::string toml = "[lattice]\nradius = 0.5e-3\n[[body]]\nname = \"a\"\n[[body.shape]]\n"
                           "type = \"circle\"\ncenter = [0, 0]\nradius = 1e5\n";
  const std::string msg = input_error([&] { parse_outline_toml(toml, "hostile.toml", {}); });
  EXPECT_NE(msg.find("hostile.toml: about 3.6"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit of 1000000000000"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("--max-disks"), std::string::npos) << msg;
}

TEST(HostileInput, DxfLayerWithNewlineIsQuotedOnOneLine) {
  // An open LINE on a layer whose name holds a control character.
  const std::string path = write_file(
      "layer.dxf", "0\nSECTION\n2\nENTITIES\n0\nLINE\n8\nba\td\n10\n0\n20\n0\n11\n1\n21\n0\n"
                   "0\nENDSEC\n0\nEOF\n");
  const std::string msg = input_error([&] { read_outline_dxf(path, dxf_options()); });
  EXPECT_NE(msg.find("'ba\\td'"), std::string::npos) << msg;
}

TEST(HostileInput, DxfFileSizeIsCapped) {
  // A device is refused before it is read (read_text_file caps regular files).
  const std::string msg = input_error([] { read_outline_dxf("/dev/zero", dxf_options()); });
  EXPECT_NE(msg.find("/dev/zero: not a regular file"), std::string::npos) << msg;
}

TEST(HostileInput, EscapeText) {
  EXPECT_EQ(escape_text(std::string("a\nb\tc\\d\x01", 8)), "a\\nb\\tc\\\\d\\x01");
  EXPECT_EQ(one_line("x\\n\ny"), "x\\n\\ny");
  EXPECT_TRUE(has_control_character(std::string("a\0b", 3)));
  EXPECT_FALSE(has_control_character("caf\xc3\xa9"));
}

}  // namespace
