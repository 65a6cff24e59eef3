// End-to-end tests of `hexdem post` through the hexdem program: the
// files written (.vtu/.vtp, .pvd, .csv) and their contents, frame selection, and bad input
// (exit code 2, one line on stderr naming the file, nothing on stdout, no output files).

#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "frame_builder.hpp"
#include "hexdem/post/post.hpp"

namespace fs = std::filesystem;

namespace {

using namespace hexdem::testing;

constexpr double kR = 1e-3;

fs::path work_dir(const std::string& sub) {
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "vtkfilters" / "post" / sub;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

struct Result {
  int code = -1;
  std::string out, err;
};

/// Runs `hexdem post` with `args` in `dir`.
Result post(const fs::path& dir, const std::string& args) {
  const std::string command = "cd '" + dir.string() + "' && '" HEXDEM_POST_DRIVER "' post " + args +
                              " > stdout.txt 2> stderr.txt";
  const int status = std::system(command.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(dir / "stdout.txt");
  r.err = read_text(dir / "stderr.txt");
  fs::remove(dir / "stdout.txt");
  fs::remove(dir / "stderr.txt");
  return r;
}

/// A 12 x 10 lattice cut in two between rows 4 and 5 (tension) at time t.
void write_cut_frame(const fs::path& path, double t, bool cut) {
  const Lattice l = make_lattice(12, 10, kR);
  FrameData d;
  d.time = t;
  d.step = static_cast<int>(std::lround(t * 1e6));
  d.p_max = 1e6;
  d.state.assign(l.bonds(), 0);
  d.break_time.assign(l.bonds(), -1.0);
  if (cut) {
    for (auto b : bonds_crossing_y(l, 4.5 * std::sqrt(3.0) * kR)) {
      d.state[b] = 2;
      d.break_time[b] = t;
    }
  }
  d.stress.assign(9 * l.disks(), 0.0);
  for (std::int64_t k = 0; k < l.disks(); ++k) d.stress[9 * k] = 1e5 * k;  // tau = 5e4 k
  write_frame(path.string(), make_frame(l, d));
}

/// A 3-frame series: intact at 0, cut at 1e-5 and 2e-5 s.
fs::path write_series3(const fs::path& dir) {
  fs::create_directories(dir / "frames");
  std::vector<std::string> files;
  std::vector<double> times;
  for (int f = 0; f < 3; ++f) {
    const std::string name = "frames/f" + std::to_string(f) + ".vtu";
    write_cut_frame(dir / name, 1e-5 * f, f > 0);
    files.push_back(name);
    times.push_back(1e-5 * f);
  }
  write_series((dir / "run.pvd").string(), files, times);
  return dir / "run.pvd";
}

TEST(PostCommand, FragmentsOfOneFrameWriteTheFrameAndTheTable) {
  const fs::path dir = work_dir("fragments");
  write_cut_frame(dir / "frame.vtu", 3e-5, true);
  const Result r = post(dir, "fragments frame.vtu -o out");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_NE(r.out.find("2 fragments"), std::string::npos) << r.out;
  const auto csv = lines(read_text(dir / "out.csv"));
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[0],
            "fragment_id,disks,mass,area,centroid_x,centroid_y,velocity_x,velocity_y,"
            "equivalent_diameter");
  EXPECT_EQ(csv[1].substr(0, 5), "0,60,");  // rows 0-4 (lowest disk 0) tie with rows 5-9
  EXPECT_EQ(csv[2].substr(0, 5), "1,60,");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((dir / "out.vtu").c_str());
  reader->Update();
  vtkDataArray* ids = reader->GetOutput()->GetPointData()->GetArray("fragment_id");
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ(ids->GetComponent(0, 0), 0);
  EXPECT_EQ(ids->GetComponent(119, 0), 1);
  EXPECT_EQ(reader->GetOutput()->GetFieldData()->GetArray("fragment_count")->GetComponent(0, 0), 2);
}

TEST(PostCommand, CracksOfEveryFrameWriteASeries) {
  const fs::path dir = work_dir("cracks");
  write_series3(dir);
  const Result r = post(dir, "cracks run.pvd --all -o cracks.pvd -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const auto csv = lines(read_text(dir / "cracks.csv"));
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[0].substr(0, 36), "time,step,crack_count,crack_length,c");
  // 12 + 11 bonds cross between rows 4 and 5, each 2r/sqrt(3) long.
  char expected[128];
  std::snprintf(expected, sizeof expected, "1e-05,10,23,%.10g,23,", 23 * 2 * kR / std::sqrt(3.0));
  EXPECT_EQ(csv[2].substr(0, std::string(expected).size()), expected) << csv[2];
  EXPECT_EQ(csv[1].substr(0, 10), "0,0,0,0,0,");
  const std::string pvd = read_text(dir / "cracks.pvd");
  EXPECT_NE(pvd.find("file=\"cracks_frames/frame_000002.vtp\""), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("timestep=\"2.0000000000000002e-05\""), std::string::npos) << pvd;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir / "cracks_frames" / "frame_000001.vtp").c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 1);
  EXPECT_EQ(reader->GetOutput()->GetFieldData()->GetArray("crack_count")->GetComponent(0, 0), 23);
}

TEST(PostCommand, TimeSelectsTheNearestFrame) {
  const fs::path dir = work_dir("time");
  write_series3(dir);
  Result r = post(dir, "maxshear run.pvd --time 0.4e-5 -o shear");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("frames/f0.vtu"), std::string::npos) << r.out;
  auto csv = lines(read_text(dir / "shear.csv"));
  ASSERT_EQ(csv.size(), 2u);
  EXPECT_EQ(csv[0], "time,step,max_shear_max,x_at_max,y_at_max,max_shear_ratio_max");
  // tau_max = 5e4 k, largest at the last disk (k = 119): 5.95e6 Pa, ratio 5.95.
  EXPECT_EQ(csv[1].substr(0, 14), "0,0,5950000,0.");
  EXPECT_TRUE(csv[1].ends_with(",5.95")) << csv[1];
  r = post(dir, "cracks run.pvd -t 1.6e-5 --csv-only -o c -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines(read_text(dir / "c.csv"))[1].substr(0, 12), "2e-05,20,23,");
  EXPECT_FALSE(fs::exists(dir / "c.vtp"));
  r = post(dir, "fragments run.pvd -q");  // default: the last frame, output run_fragments
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "run_fragments.vtu"));
  EXPECT_EQ(lines(read_text(dir / "run_fragments.csv")).size(), 3u);
}

TEST(PostCommand, OptionsReachTheFilters) {
  const fs::path dir = work_dir("options");
  write_series3(dir);
  Result r = post(dir, "maxshear run.pvd --p-max 2e6 --3d -o s -q");
  ASSERT_EQ(r.code, 0) << r.err;
  auto csv = lines(read_text(dir / "s.csv"));
  EXPECT_TRUE(csv[0].ends_with(",max_shear_3d_max,max_shear_3d_ratio_max")) << csv[0];
  EXPECT_NE(csv[1].find(",2.975,"), std::string::npos) << csv[1];
  // The last frame's bonds broke at 2e-5 s.
  r = post(dir, "cracks run.pvd --max-break-time 2e-5 --no-merge --csv-only -o c -q");
  ASSERT_EQ(r.code, 0) << r.err;
  auto row = lines(read_text(dir / "c.csv"))[1];
  EXPECT_EQ(row.substr(0, 12), "2e-05,20,23,");
  EXPECT_TRUE(row.ends_with(",23")) << row;  // one line cell per bond
  r = post(dir, "cracks run.pvd --max-break-time 1.5e-5 --csv-only -o c -q");
  EXPECT_EQ(lines(read_text(dir / "c.csv"))[1].substr(0, 11), "2e-05,20,0,");
  r = post(dir, "fragments run.pvd --min-disks 100 --csv-only -o f -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines(read_text(dir / "f.csv")).size(), 1u);  // header only: no fragment >= 100
}

/// Expects exit code 2, one line on stderr naming `part`, no stdout and no file "out.*".
void expect_input_error(const fs::path& dir, const std::string& args, const std::string& part) {
  const Result r = post(dir, args);
  EXPECT_EQ(r.code, 2) << args;
  const auto err = lines(r.err);
  ASSERT_EQ(err.size(), 1u) << args << "\n" << r.err;
  EXPECT_EQ(err[0].rfind("hexdem: error: ", 0), 0u) << err[0];
  EXPECT_NE(err[0].find(part), std::string::npos) << err[0];
  EXPECT_TRUE(r.out.empty()) << r.out;
  for (const char* ext : {".vtu", ".vtp", ".csv", ".pvd"}) {
    EXPECT_FALSE(fs::exists(dir / (std::string("out") + ext))) << args << ": out" << ext;
  }
}

TEST(PostCommand, BadInputExitsWithOneLine) {
  const fs::path dir = work_dir("bad");
  const Lattice l = make_lattice(5, 4, kR);
  FrameData d;
  auto frame = make_frame(l, d);
  frame->GetCellData()->RemoveArray("state");
  write_frame((dir / "no_state.vtu").string(), frame);
  frame = make_frame(l, d);
  frame->GetPointData()->RemoveArray("stress");
  write_frame((dir / "no_stress.vtu").string(), frame);
  vtkNew<vtkUnstructuredGrid> empty;
  write_frame((dir / "empty.vtu").string(), empty);
  std::ofstream(dir / "garbage.vtu") << "not a VTK file\n";
  std::ofstream(dir / "garbage.pvd") << "<VTKFile><Collection><DataSet";
  std::ofstream(dir / "nothing.pvd") << "<VTKFile type=\"Collection\"><Collection/></VTKFile>\n";
  write_frame((dir / "good.vtu").string(), make_frame(l, d));

  expect_input_error(dir, "cracks no_state.vtu -o out", "no_state.vtu: Bad input");
  expect_input_error(dir, "fragments no_state.vtu -o out", "'state'");
  expect_input_error(dir, "maxshear no_stress.vtu --stress array -o out", "'stress'");
  for (const char* a : {"maxshear", "cracks", "fragments"}) {
    expect_input_error(dir, std::string(a) + " empty.vtu -o out",
                       "empty.vtu: the frame has no disks");
    expect_input_error(dir, std::string(a) + " garbage.vtu -o out", "garbage.vtu: not a VTK XML");
    expect_input_error(dir, std::string(a) + " missing.pvd -o out", "missing.pvd: no such file");
  }
  expect_input_error(dir, "cracks garbage.pvd -o out", "garbage.pvd: not a readable .pvd");
  expect_input_error(dir, "cracks nothing.pvd -o out", "nothing.pvd: the series lists no frames");
  expect_input_error(dir, "cracks frame.txt -o out", "frame.txt: no such file");
  std::ofstream(dir / "frame.txt") << "x";
  expect_input_error(dir, "cracks frame.txt -o out", "unknown input format '.txt'");
  expect_input_error(dir, "cracks good.vtu --time 1 -o out", "--time: needs a .pvd series");
  std::ofstream(dir / "one.pvd") << "<VTKFile type=\"Collection\"><Collection>"
                                    "<DataSet timestep=\"0\" file=\"good.vtu\"/></Collection></VTKFile>\n";
  expect_input_error(dir, "cracks one.pvd --time nan -o out", "--time: must be a number of seconds (got nan)");
  expect_input_error(dir, "cracks good.vtu -o nowhere/out", "-o: folder 'nowhere' does not exist");
  expect_input_error(dir, "cracks good.vtu --merge-tolerance 2 -o out", "--merge-tolerance");
  expect_input_error(dir, "fragments good.vtu --min-disks 0 -o out", "--min-disks");
  // Command-line parse errors also exit with 2 and name the value.
  const Result r = post(dir, "maxshear good.vtu --stress sideways -o out");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("sideways"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.vtu"));
}

TEST(PostLibrary, ReadSeriesSortsFramesAndResolvesPaths) {
  const fs::path dir = work_dir("series");
  std::ofstream(dir / "s.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">"
                                  "<Collection>"
                                  "<DataSet timestep=\"2e-5\" file=\"b/f2.vtu\"/>"
                                  "<DataSet timestep=\"0\" file=\"/abs/f0.vtu\"/>"
                                  "<DataSet timestep=\"1e-5\" part=\"0\" file=\"f1.vtu\"/>"
                                  "</Collection></VTKFile>\n";
  const auto frames = hexdem::post::read_series((dir / "s.pvd").string());
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].path, "/abs/f0.vtu");
  EXPECT_EQ(frames[1].path, (dir / "f1.vtu").string());
  EXPECT_EQ(frames[2].path, (dir / "b/f2.vtu").string());
  EXPECT_EQ(frames[2].time, 2e-5);
  EXPECT_EQ(hexdem::post::nearest_frame(frames, 0.6e-5), 1u);
  EXPECT_EQ(hexdem::post::nearest_frame(frames, 0.5e-5), 0u);  // tie: the earlier
  EXPECT_EQ(hexdem::post::nearest_frame(frames, 1.0), 2u);
  // Far beyond the end every difference rounds to the same value; the last frame is nearest.
  EXPECT_EQ(hexdem::post::nearest_frame(frames, 1e300), 2u);
  EXPECT_EQ(hexdem::post::nearest_frame(frames, std::numeric_limits<double>::infinity()), 2u);
  EXPECT_EQ(hexdem::post::nearest_frame(frames, -1e300), 0u);
}

}  // namespace

// ---- damaged frames, lying headers, full disks ---------------------------------------------
// Each of these once ended in SIGFPE, SIGSEGV, SIGABRT, a stack overflow or std::bad_alloc,
// or was believed (a wrong count, exit 0).

std::string read_binary(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_binary(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

/// The good frame's bytes with `from` replaced by `to` (first occurrence).
std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = text;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

/// Byte offset of the first array's data (just after the '_' of the appended data).
std::size_t appended_start(const std::string& text) {
  return text.find('_', text.find("<AppendedData")) + 1;
}

void put_u64(std::string& text, std::size_t at, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) text[at + k] = static_cast<char>((v >> (8 * k)) & 0xff);
}

TEST(PostHostile, DamagedFramesAreInputErrors) {
  const fs::path dir = work_dir("hostile");
  write_cut_frame(dir / "good.vtu", 1e-5, true);
  const std::string good = read_binary(dir / "good.vtu");
  ASSERT_NE(good.find("header_type=\"UInt64\""), std::string::npos);
  ASSERT_NE(good.find("NumberOfPoints=\"120\""), std::string::npos);
  const std::size_t data = appended_start(good);

  std::vector<std::pair<std::string, std::string>> cases;  // file content, expected part
  cases.push_back({replaced(good, "header_type=\"UInt64\"", "header_type=\"UInt32\""), "compressed block size 0"});
  {
    std::string t = good;
    put_u64(t, data + 8, 0);  // block size of the first array
    cases.push_back({t, "compressed block size 0"});
  }
  {
    std::string t = good;
    put_u64(t, data + 24, std::uint64_t{1} << 40);  // compressed size of its first block
    cases.push_back({t, "compressed block of 1099511627776 bytes is larger than the file"});
  }
  cases.push_back({replaced(good, "NumberOfPoints=\"120\"", "NumberOfPoints=\"-5\""),
                   "NumberOfPoints=\"-5\" is not a non-negative integer"});
  cases.push_back({replaced(good, "NumberOfPoints=\"120\"", "NumberOfPoints=\"999999999\""),
                   "but NumberOfPoints=999999999 makes"});
  cases.push_back({replaced(good, "NumberOfCells=", "NumberOfCells=\"4000000000\" x="),
                   "but NumberOfCells=4000000000 makes"});
  cases.push_back({replaced(good, "byte_order=\"LittleEndian\"", "byte_order=\"BigEndian\""),
                   "compressed blocks do not fit in the file"});
  {
    std::string nest;
    for (int k = 0; k < 200000; ++k) nest += "<a>";
    for (int k = 0; k < 200000; ++k) nest += "</a>";
    cases.push_back({replaced(good, "<UnstructuredGrid>", nest + "<UnstructuredGrid>"),
                     "XML elements nested deeper than 64 levels"});
  }
  // A NumberOfCells that is smaller than the cells the file holds was believed: "2 broken
  // bonds" of a frame with more.
  cases.push_back({replaced(good, "NumberOfCells=", "NumberOfCells=\"2\" x="), "but NumberOfCells=2 makes"});
  cases.push_back({good.substr(0, data + 40), "runs past the end of the file"});
  {
    // Found by the fuzzer: a repeated array element made VTK's reader crash (SIGSEGV).
    const std::size_t at = good.find("<DataArray type=\"Float64\" Name=\"shear_force\"");
    ASSERT_NE(at, std::string::npos);
    const std::size_t end = good.find('\n', at) + 1;
    std::string t = good;
    t.insert(end, good.substr(at, end - at));
    cases.push_back({t, "array 'shear_force' appears twice in <CellData>"});
  }
  // Found by the fuzzer under ASan: NumberOfTuples="4000000000" of a String array made VTK
  // allocate 128 GB; a repeated <AppendedData> tag made it read a garbage block count
  // (std::length_error, an internal error).
  cases.push_back({replaced(good, "Name=\"geometry\" NumberOfTuples=\"1\"", "Name=\"geometry\" NumberOfTuples=\"4000000000\""),
                   "NumberOfTuples=4000000000 strings cannot fit in"});
  cases.push_back({replaced(good, "<AppendedData encoding=\"raw\">", "<AppendedData encoding=\"raw\">\n  <AppendedData encoding=\"raw\">"),
                   "damaged AppendedData (text before its '_' marker)"});

  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string name = "bad" + std::to_string(k) + ".vtu";
    write_binary(dir / name, cases[k].first);
    for (const char* a : {"cracks", "fragments"}) {
      SCOPED_TRACE(std::string(a) + " " + name);
      expect_input_error(dir, std::string(a) + " " + name + " -o out", name + ": ");
      const Result r = post(dir, std::string(a) + " " + name + " -o out");
      EXPECT_NE(r.err.find(cases[k].second), std::string::npos) << r.err;
    }
  }
  // The good frame still reads.
  EXPECT_EQ(post(dir, "cracks good.vtu -o ok").code, 0);
}

TEST(PostHostile, NonNumericTimestepIsRefused) {
  // Was: read as t = 0.
  const fs::path dir = work_dir("hostile_pvd");
  write_series3(dir);
  const std::string pvd = read_binary(dir / "run.pvd");
  const std::size_t at = pvd.find("timestep=\"");
  ASSERT_NE(at, std::string::npos);
  std::string bad = pvd;
  bad.insert(at + 10, "abc");
  write_binary(dir / "bad.pvd", bad);
  expect_input_error(dir, "cracks bad.pvd --all -o out", "which is not a finite number");
  std::string deep = "<VTKFile type=\"Collection\"><Collection>";
  for (int k = 0; k < 200000; ++k) deep += "<a>";
  write_binary(dir / "deep.pvd", deep);
  expect_input_error(dir, "cracks deep.pvd -o out", "deep.pvd: XML elements nested deeper than 64");
}

TEST(PostHostile, FullDiskLeavesNoTruncatedFileAndNoSuccessLine) {
  // Was: frame_000007.vtp of 4,096 bytes under its final name, a success line printed before
  // the failure, and the write error blamed on the next input frame.
  const fs::path dir = work_dir("hostile_disk");
  write_series3(dir);
  const fs::path disk = dir / "disk";
  fs::create_directories(disk);
  if (std::system(("mount -t tmpfs -o size=12k tmpfs '" + disk.string() + "' 2> /dev/null").c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const Result r = post(dir, "fragments run.pvd --all -o disk/out");
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(disk))
    if (e.is_regular_file()) files.push_back(e.path());
  // Every file that has its final name must be complete: VTK reads it without error.
  for (const fs::path& f : files) {
    EXPECT_EQ(f.string().find(".tmp"), std::string::npos) << f;
    if (f.extension() == ".vtu") {
      vtkNew<vtkXMLUnstructuredGridReader> reader;
      reader->SetFileName(f.c_str());
      reader->Update();
      EXPECT_EQ(reader->GetErrorCode(), 0UL) << f;
      EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 120) << f;
    }
  }
  EXPECT_EQ(std::system(("umount '" + disk.string() + "'").c_str()), 0);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_EQ(lines(r.err).size(), 1U) << r.err;
  EXPECT_NE(r.err.find("disk/out"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot write the file"), std::string::npos) << r.err;
  for (const char* input : {"frames/f0.vtu", "frames/f1.vtu", "frames/f2.vtu"})
    EXPECT_EQ(r.err.find(input), std::string::npos) << "blames an input frame: " << r.err;
}

// ---- hostile-input report 3: items 9, 12 and 23 (`hexdem post`) ---------------------------

TEST(PostHostile, NonFiniteOrOutOfRangeFrameValuesAreRefused) {
  // Was: exit 0 with "max tau_max  Pa at (, )", empty CSV fields, a mass of -55, every disk
  // a fragment for state 200, t = 0 for a NaN time.
  const fs::path dir = work_dir("hostile_values");
  const Lattice l = make_lattice(5, 4, kR);
  FrameData d;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    std::string name, expected;
    std::function<void(vtkUnstructuredGrid*)> damage;
  };
  const std::vector<Case> cases = {
      {"stress_nan", "point array 'stress' holds nan at tuple 0, component 0",
       [&](vtkUnstructuredGrid* g) { g->GetPointData()->GetArray("stress")->SetComponent(0, 0, nan); }},
      {"points_nan", "the 'Points' array holds nan at tuple 2, component 0",
       [&](vtkUnstructuredGrid* g) { g->GetPoints()->GetData()->SetComponent(2, 0, nan); }},
      {"mass_negative", "point array 'mass' holds -55 at tuple 1",
       [&](vtkUnstructuredGrid* g) { g->GetPointData()->GetArray("mass")->SetComponent(1, 0, -55); }},
      {"state_200", "cell array 'state' holds 200 at tuple 3",
       [&](vtkUnstructuredGrid* g) { g->GetCellData()->GetArray("state")->SetComponent(3, 0, 200); }},
      {"time_nan", "field array 'time' holds nan",
       [&](vtkUnstructuredGrid* g) {
         vtkDataArray::SafeDownCast(g->GetFieldData()->GetAbstractArray("time"))->SetComponent(0, 0, nan);
       }},
      {"body_7", "point array 'body' holds 7 at tuple 0",
       [&](vtkUnstructuredGrid* g) {
         g->GetPointData()->GetArray("body")->SetComponent(0, 0, 7);
         vtkNew<vtkStringArray> names;
         names->SetName("body_names");
         names->InsertNextValue("plate");
         g->GetFieldData()->AddArray(names);
       }},
  };
  for (const Case& c : cases) {
    auto frame = make_frame(l, d);
    c.damage(frame);
    write_frame((dir / (c.name + ".vtu")).string(), frame);
    for (const char* a : {"maxshear", "cracks", "fragments"}) {
      SCOPED_TRACE(std::string(a) + " " + c.name);
      expect_input_error(dir, std::string(a) + " " + c.name + ".vtu -o out", c.name + ".vtu: " + c.expected);
    }
  }
  // Options: NaN, infinite, or a p_max whose inverse overflows.
  write_frame((dir / "good.vtu").string(), make_frame(l, d));
  expect_input_error(dir, "maxshear good.vtu --p-max nan -o out", "--p-max: must be a finite number >= 0 (got nan)");
  expect_input_error(dir, "maxshear good.vtu --p-max 1e-320 -o out", "1/p_max overflows");
  expect_input_error(dir, "maxshear good.vtu --thickness nan -o out", "--thickness: must be a finite number >= 0 (got nan)");
  expect_input_error(dir, "maxshear good.vtu --thickness inf -o out", "(got inf)");
  expect_input_error(dir, "cracks good.vtu --max-break-time nan -o out", "--max-break-time");
  expect_input_error(dir, "cracks good.vtu --merge-tolerance nan -o out", "--merge-tolerance");
  expect_input_error(dir, "fragments good.vtu --min-disks -5 -o out", "--min-disks");
  EXPECT_EQ(post(dir, "maxshear good.vtu -o ok -q").code, 0);
}

TEST(PostHostile, OutputsNeverReplaceInputs) {
  // Was: `post fragments f.vtu -o f` replaced f.vtu, and `post maxshear run.pvd --all -o run`
  // replaced the run's own series.
  const fs::path dir = work_dir("hostile_overwrite");
  write_series3(dir);
  const std::string frame = read_binary(dir / "frames/f1.vtu");
  const std::string series = read_binary(dir / "run.pvd");
  Result r = post(dir, "fragments frames/f1.vtu -o frames/f1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("-o: the output frames/f1.vtu would overwrite the input frames/f1.vtu"),
            std::string::npos) << r.err;
  r = post(dir, "maxshear run.pvd --all -o run");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("would overwrite the input run.pvd"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
  // A frame of the series that is not processed is protected too.
  r = post(dir, "cracks run.pvd --time 0 --csv-only -o frames/f2.csv");
  EXPECT_EQ(r.code, 0) << r.err;  // the .csv is not an input
  r = post(dir, "maxshear run.pvd --time 0 -o frames/f2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("would overwrite the input"), std::string::npos) << r.err;
  EXPECT_EQ(read_binary(dir / "frames/f1.vtu"), frame);
  EXPECT_EQ(read_binary(dir / "run.pvd"), series);
  EXPECT_FALSE(fs::exists(dir / "run_frames"));
}

TEST(PostHostile, NotRegularFilesAndFailedSeriesLeaveNothing) {
  const fs::path dir = work_dir("hostile_special");
  fs::create_directories(dir / "folder.vtu");
  fs::create_directories(dir / "folder.pvd");
  fs::create_symlink("/dev/zero", dir / "zero.vtu");
  expect_input_error(dir, "cracks folder.vtu -o out", "folder.vtu: not a regular file (a folder)");
  expect_input_error(dir, "cracks folder.pvd -o out", "folder.pvd: not a regular file (a folder)");
  expect_input_error(dir, "cracks zero.vtu -o out", "zero.vtu: not a regular file");
  expect_input_error(dir, "cracks /dev/zero -o out", "/dev/zero: not a regular file");
  // A series whose last frame is bad: no frame folder, no frames, no .pvd, no .csv.
  write_series3(dir);
  auto bad = make_frame(make_lattice(12, 10, kR), FrameData{});
  bad->GetPointData()->GetArray("stress")->SetComponent(0, 0, std::numeric_limits<double>::infinity());
  write_frame((dir / "frames/f2.vtu").string(), bad);
  for (const char* a : {"maxshear", "cracks", "fragments"}) {
    SCOPED_TRACE(a);
    expect_input_error(dir, std::string(a) + " run.pvd --all -o out", "frames/f2.vtu: point array 'stress' holds inf");
    EXPECT_FALSE(fs::exists(dir / "out_frames"));
  }
}
