// Tests of the streaming .vtu/.pvd writer and of the lattice .vtu: every file is read back
// with VTK's own XML reader, and the appended blocks are also decoded byte by byte to check
// the compression-header layout VTK expects.

#include <gtest/gtest.h>
#include <omp.h>
#include <zlib.h>

#include <vtkCallbackCommand.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "hexdem/io/vtu_writer.hpp"
#include "hexdem/meshing/lattice.hpp"
#include "hexdem/meshing/lattice_vtu.hpp"

namespace fs = std::filesystem;
using hexdem::io::ArraySource;
using hexdem::io::FieldValue;
using hexdem::io::LineGrid;
using hexdem::io::ScalarType;
using hexdem::io::WriteOptions;

namespace {

fs::path work_dir(const std::string& sub) {
  const fs::path dir = fs::path(HEXDEM_TEST_WORK_DIR) / "vtu_writer" / sub;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::string> folder_listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Reads a .vtu with VTK; fails the test on any VTK error or warning.
vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& p) {
  struct Log {
    int messages = 0;
    std::string text;
  } log;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetClientData(&log);
  observer->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    auto* l = static_cast<Log*>(client);
    ++l->messages;
    if (call != nullptr) l->text += static_cast<const char*>(call);
  });
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, observer);
  reader->AddObserver(vtkCommand::WarningEvent, observer);
  reader->SetFileName(p.string().c_str());
  reader->Update();
  EXPECT_EQ(log.messages, 0) << p << ": " << log.text;
  vtkSmartPointer<vtkUnstructuredGrid> out = reader->GetOutput();
  return out;
}

/// One appended array decoded by hand: its compression header and uncompressed bytes.
struct RawArray {
  std::vector<std::uint64_t> header;
  std::string bytes;
};

/// Decodes every appended array of a file written by write_vtu, by Name (in Points: "Points").
std::map<std::string, RawArray> decode_appended(const fs::path& p) {
  const std::string file = read_bytes(p);
  const std::size_t mark = file.find("<AppendedData encoding=\"raw\">");
  if (mark == std::string::npos) throw std::runtime_error("no AppendedData");
  const std::size_t data = file.find('_', mark) + 1;
  std::map<std::string, RawArray> arrays;
  std::size_t pos = 0;
  while (true) {
    const std::size_t a = file.find("Array type=\"", pos);
    if (a == std::string::npos || a > mark) break;
    const std::size_t end = file.find("/>", a);
    const std::string element = file.substr(a, end - a);
    pos = end;
    auto attribute = [&](const std::string& key) {
      const std::size_t k = element.find(" " + key + "=\"");
      const std::size_t v = k + key.size() + 3;
      return element.substr(v, element.find('"', v) - v);
    };
    const std::uint64_t offset = std::stoull(attribute("offset"));
    const char* h = file.data() + data + offset;
    RawArray r;
    std::uint64_t head[3];
    std::memcpy(head, h, sizeof head);
    r.header.assign(head, head + 3);
    for (std::uint64_t b = 0; b < head[0]; ++b) {
      std::uint64_t size = 0;
      std::memcpy(&size, h + 24 + 8 * b, 8);
      r.header.push_back(size);
    }
    const char* block = h + 24 + 8 * head[0];
    for (std::uint64_t b = 0; b < head[0]; ++b) {
      const bool last = b + 1 == head[0];
      uLongf len = static_cast<uLongf>(last && head[2] != 0 ? head[2] : head[1]);
      std::string out(len, '\0');
      const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &len,
                                reinterpret_cast<const Bytef*>(block), r.header[3 + b]);
      if (rc != Z_OK || len != out.size()) throw std::runtime_error("bad zlib block");
      r.bytes += out;
      block += r.header[3 + b];
    }
    arrays[attribute("Name")] = r;
  }
  return arrays;
}

template <typename T>
ArraySource typed_view(const std::string& name, ScalarType type, const std::vector<T>& v,
                       int components) {
  ArraySource a;
  a.name = name;
  a.type = type;
  a.components = components;
  a.tuples = v.size() / static_cast<std::size_t>(components);
  const T* data = v.data();
  a.fill = [data, components](std::size_t first, std::size_t count, void* out) {
    const auto c = static_cast<std::size_t>(components);
    std::memcpy(out, data + first * c, count * c * sizeof(T));
  };
  return a;
}

template <typename T>
void expect_array(vtkDataArray* a, const std::vector<T>& expected, int components, int vtk_type) {
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->GetDataType(), vtk_type) << a->GetName();
  ASSERT_EQ(a->GetNumberOfComponents(), components) << a->GetName();
  ASSERT_EQ(static_cast<std::size_t>(a->GetNumberOfValues()), expected.size()) << a->GetName();
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const auto tuple = static_cast<vtkIdType>(k / static_cast<std::size_t>(components));
    const int comp = static_cast<int>(k % static_cast<std::size_t>(components));
    EXPECT_EQ(a->GetComponent(tuple, comp), static_cast<double>(expected[k]))
        << a->GetName() << " value " << k;
  }
}

std::vector<std::string> string_values(vtkAbstractArray* a) {
  std::vector<std::string> out;
  auto* s = vtkStringArray::SafeDownCast(a);
  if (s == nullptr) return out;
  for (vtkIdType k = 0; k < s->GetNumberOfValues(); ++k) out.push_back(s->GetValue(k));
  return out;
}

void expect_lines(vtkUnstructuredGrid* g, const std::vector<std::int32_t>& i,
                  const std::vector<std::int32_t>& j) {
  ASSERT_EQ(static_cast<std::size_t>(g->GetNumberOfCells()), i.size());
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    EXPECT_EQ(g->GetCellType(c), VTK_LINE);
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    g->GetCellPoints(c, npts, pts);
    ASSERT_EQ(npts, 2);
    EXPECT_EQ(pts[0], i[static_cast<std::size_t>(c)]) << "cell " << c;
    EXPECT_EQ(pts[1], j[static_cast<std::size_t>(c)]) << "cell " << c;
  }
}

void expect_points(vtkUnstructuredGrid* g, const std::vector<double>& x,
                   const std::vector<double>& y, const std::vector<double>* z) {
  ASSERT_EQ(static_cast<std::size_t>(g->GetNumberOfPoints()), x.size());
  if (x.empty()) return;
  EXPECT_EQ(g->GetPoints()->GetDataType(), VTK_DOUBLE);
  for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p) {
    double q[3];
    g->GetPoint(p, q);
    const auto k = static_cast<std::size_t>(p);
    EXPECT_EQ(q[0], x[k]);
    EXPECT_EQ(q[1], y[k]);
    EXPECT_EQ(q[2], z != nullptr ? (*z)[k] : 0.0);
  }
}

/// A ring of n points with lines i -> i+1 and chords i -> i+n/2 as extra lines.
struct Ring {
  std::vector<double> x, y, z;
  std::vector<std::int32_t> i, j, ei, ej;
  explicit Ring(int n) {
    for (int k = 0; k < n; ++k) {
      x.push_back(std::cos(0.1 * k) * (1.0 + 1e-3 * k));
      y.push_back(std::sin(0.1 * k) / 3.0);
      z.push_back(k % 7 == 0 ? -0.25 * k : 0.0);
      i.push_back(k);
      j.push_back((k + 1) % n);
      if (k < n / 2) {
        ei.push_back(k);
        ej.push_back(k + n / 2);
      }
    }
  }
  LineGrid grid(bool with_z, bool with_extra) const {
    LineGrid g;
    g.num_points = x.size();
    g.x = x.data();
    g.y = y.data();
    g.z = with_z ? z.data() : nullptr;
    g.num_lines = i.size();
    g.line_i = i.data();
    g.line_j = j.data();
    if (with_extra) {
      g.num_extra_lines = ei.size();
      g.extra_i = ei.data();
      g.extra_j = ej.data();
    }
    return g;
  }
};

}  // namespace

TEST(VtuWriter, ScalarSizes) {
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::Int8), 1u);
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::UInt8), 1u);
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::Int32), 4u);
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::Int64), 8u);
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::Float32), 4u);
  EXPECT_EQ(hexdem::io::scalar_size(ScalarType::Float64), 8u);
}

TEST(VtuWriter, SmallGridAllTypesRoundTrip) {
  const fs::path dir = work_dir("small");
  const std::vector<double> x{0.0, 1.0, 1.0, 0.0}, y{0.0, 0.0, 1.0, 1.0}, z{0.5, -0.5, 1e-300, 3e300};
  const std::vector<std::int32_t> li{0, 1, 2, 3, 0}, lj{1, 2, 3, 0, 2};
  const std::vector<std::int8_t> i8{-128, -1, 0, 127};
  const std::vector<std::uint8_t> u8{0, 1, 200, 255};
  const std::vector<std::int32_t> i32{-2147483647 - 1, -7, 42, 2147483647};
  const std::vector<std::int64_t> i64{-(std::int64_t{1} << 62), -1, 0, (std::int64_t{1} << 53) + 1};
  const std::vector<float> f32{-1.5f, 0.1f, 3.4e38f, -0.0f};
  const std::vector<double> f64{0.1, -2.5e-310, 1.0 / 3.0, 6.02214076e23};
  const std::vector<double> vec3{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const std::vector<std::int32_t> pair{1, -1, 2, -2, 3, -3, 4, -4};
  const std::vector<std::uint8_t> cls{1, 2, 2, 1, 2};
  const std::vector<float> cvec{0.f, 1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f, 8.f, 9.f};

  LineGrid g;
  g.num_points = 4;
  g.x = x.data();
  g.y = y.data();
  g.z = z.data();
  g.num_lines = li.size();
  g.line_i = li.data();
  g.line_j = lj.data();
  g.point_data.push_back(typed_view("int8", ScalarType::Int8, i8, 1));
  g.point_data.push_back(typed_view("uint8", ScalarType::UInt8, u8, 1));
  g.point_data.push_back(typed_view("int32", ScalarType::Int32, i32, 1));
  g.point_data.push_back(typed_view("int64", ScalarType::Int64, i64, 1));
  g.point_data.push_back(typed_view("float32", ScalarType::Float32, f32, 1));
  g.point_data.push_back(hexdem::io::array_view("float64", f64.data(), f64.size()));
  g.point_data.push_back(typed_view("vector <&> \"3\"", ScalarType::Float64, vec3, 3));
  g.point_data.push_back(typed_view("pair", ScalarType::Int32, pair, 2));
  g.cell_data.push_back(hexdem::io::array_view("bond_class", cls.data(), cls.size()));
  g.cell_data.push_back(typed_view("cell_vector", ScalarType::Float32, cvec, 2));
  g.field_data.push_back(FieldValue{"geometry", {}, "plane", {}});
  g.field_data.push_back(FieldValue{"time", {1.25e-6}, "", {}});
  g.field_data.push_back(FieldValue{"box", {0.0, -1.0, 2.5}, "", {}});
  g.field_data.push_back(FieldValue{"body_names", {}, "", {"target", "projectile & co", "x"}});

  const fs::path file = dir / "small.vtu";
  hexdem::io::write_vtu(file.string(), g);
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"small.vtu"});

  auto out = read_vtu(file);
  expect_points(out, x, y, &z);
  expect_lines(out, li, lj);
  vtkPointData* pd = out->GetPointData();
  ASSERT_EQ(pd->GetNumberOfArrays(), 8);
  EXPECT_STREQ(pd->GetArrayName(0), "int8");
  EXPECT_STREQ(pd->GetArrayName(6), "vector <&> \"3\"");
  expect_array(pd->GetArray("int8"), i8, 1, VTK_SIGNED_CHAR);
  expect_array(pd->GetArray("uint8"), u8, 1, VTK_UNSIGNED_CHAR);
  expect_array(pd->GetArray("int32"), i32, 1, VTK_INT);
  expect_array(pd->GetArray("int64"), i64, 1, VTK_LONG_LONG);
  expect_array(pd->GetArray("float32"), f32, 1, VTK_FLOAT);
  expect_array(pd->GetArray("float64"), f64, 1, VTK_DOUBLE);
  expect_array(pd->GetArray("vector <&> \"3\""), vec3, 3, VTK_DOUBLE);
  expect_array(pd->GetArray("pair"), pair, 2, VTK_INT);
  // Int64 values beyond double precision: compare exactly through the integer interface.
  auto* i64_read = pd->GetArray("int64");
  ASSERT_NE(i64_read, nullptr);
  EXPECT_EQ(static_cast<std::int64_t>(i64_read->GetVariantValue(3).ToTypeInt64()), i64[3]);

  vtkCellData* cd = out->GetCellData();
  ASSERT_EQ(cd->GetNumberOfArrays(), 2);
  expect_array(cd->GetArray("bond_class"), cls, 1, VTK_UNSIGNED_CHAR);
  expect_array(cd->GetArray("cell_vector"), cvec, 2, VTK_FLOAT);

  vtkFieldData* fd = out->GetFieldData();
  ASSERT_EQ(fd->GetNumberOfArrays(), 4);
  EXPECT_EQ(string_values(fd->GetAbstractArray("geometry")), std::vector<std::string>{"plane"});
  EXPECT_EQ(string_values(fd->GetAbstractArray("body_names")),
            (std::vector<std::string>{"target", "projectile & co", "x"}));
  expect_array(vtkDataArray::SafeDownCast(fd->GetAbstractArray("time")),
               std::vector<double>{1.25e-6}, 1, VTK_DOUBLE);
  expect_array(vtkDataArray::SafeDownCast(fd->GetAbstractArray("box")),
               std::vector<double>{0.0, -1.0, 2.5}, 3, VTK_DOUBLE);
}

TEST(VtuWriter, EmptyGrid) {
  const fs::path dir = work_dir("empty");
  LineGrid g;
  g.point_data.push_back(hexdem::io::array_view("radius", static_cast<const double*>(nullptr), 0));
  g.cell_data.push_back(hexdem::io::array_view("bond_class", static_cast<const std::uint8_t*>(nullptr), 0));
  g.field_data.push_back(FieldValue{"geometry", {}, "axisymmetric", {}});
  const fs::path file = dir / "empty.vtu";
  hexdem::io::write_vtu(file.string(), g);

  auto out = read_vtu(file);
  EXPECT_EQ(out->GetNumberOfPoints(), 0);
  EXPECT_EQ(out->GetNumberOfCells(), 0);
  ASSERT_NE(out->GetPointData()->GetArray("radius"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetArray("radius")->GetNumberOfTuples(), 0);
  ASSERT_NE(out->GetCellData()->GetArray("bond_class"), nullptr);
  EXPECT_EQ(string_values(out->GetFieldData()->GetAbstractArray("geometry")),
            std::vector<std::string>{"axisymmetric"});

  // VTK's own layout for an empty array: no blocks, header [0, block size, 0].
  const auto raw = decode_appended(file);
  ASSERT_EQ(raw.at("Points").header.size(), 3u);
  EXPECT_EQ(raw.at("Points").header[0], 0u);
  EXPECT_EQ(raw.at("Points").header[2], 0u);
  EXPECT_TRUE(raw.at("connectivity").bytes.empty());
}

TEST(VtuWriter, ManyBlocksWithTinyBlockSize) {
  const fs::path dir = work_dir("blocks");
  const Ring ring(1000);
  LineGrid g = ring.grid(true, true);
  std::vector<double> radius(ring.x.size());
  std::vector<std::int64_t> id(ring.x.size());
  for (std::size_t k = 0; k < radius.size(); ++k) {
    radius[k] = 1e-3 * static_cast<double>(k + 1);
    id[k] = static_cast<std::int64_t>(k) * 1000003;
  }
  std::vector<std::uint8_t> cls(ring.i.size() + ring.ei.size());
  for (std::size_t k = 0; k < cls.size(); ++k) cls[k] = static_cast<std::uint8_t>(k % 3);
  g.point_data.push_back(hexdem::io::array_view("radius", radius.data(), radius.size()));
  g.point_data.push_back(typed_view("id", ScalarType::Int64, id, 1));
  g.cell_data.push_back(hexdem::io::array_view("bond_class", cls.data(), cls.size()));

  for (std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{100}, std::size_t{4096}}) {
    SCOPED_TRACE("block_size " + std::to_string(block));
    WriteOptions options;
    options.block_size = block;
    const fs::path file = dir / ("blocks" + std::to_string(block) + ".vtu");
    hexdem::io::write_vtu(file.string(), g, options);

    auto out = read_vtu(file);
    expect_points(out, ring.x, ring.y, &ring.z);
    std::vector<std::int32_t> all_i = ring.i, all_j = ring.j;
    all_i.insert(all_i.end(), ring.ei.begin(), ring.ei.end());
    all_j.insert(all_j.end(), ring.ej.begin(), ring.ej.end());
    expect_lines(out, all_i, all_j);
    expect_array(out->GetPointData()->GetArray("radius"), radius, 1, VTK_DOUBLE);
    expect_array(out->GetPointData()->GetArray("id"), id, 1, VTK_LONG_LONG);
    expect_array(out->GetCellData()->GetArray("bond_class"), cls, 1, VTK_UNSIGNED_CHAR);

    // Header semantics: whole tuples per block, last block size 0 when the last block is full.
    const auto raw = decode_appended(file);
    const RawArray& points = raw.at("Points");
    const std::uint64_t tuples_per_block = std::max<std::uint64_t>(1, block / 24);
    EXPECT_EQ(points.header[1], 24 * tuples_per_block);
    EXPECT_EQ(points.header[0], (1000 + tuples_per_block - 1) / tuples_per_block);
    EXPECT_EQ(points.header[2], (1000 % tuples_per_block) * 24);
    EXPECT_EQ(points.bytes.size(), 24000u);
    for (const auto& [name, a] : raw) {
      ASSERT_GE(a.header.size(), 3u) << name;
      EXPECT_EQ(a.header.size(), 3 + a.header[0]) << name;
      EXPECT_LT(a.header[2], a.header[1]) << name;
    }
    const RawArray& offsets = raw.at("offsets");
    ASSERT_EQ(offsets.bytes.size(), 4 * all_i.size());  // Int32
    std::int32_t last = 0;
    std::memcpy(&last, offsets.bytes.data() + offsets.bytes.size() - 4, 4);
    EXPECT_EQ(last, static_cast<std::int32_t>(2 * all_i.size()));
  }
}

TEST(VtuWriter, ExtraLinesFollowMainLines) {
  const fs::path dir = work_dir("extra");
  const Ring ring(10);
  LineGrid g = ring.grid(false, true);
  const fs::path file = dir / "extra.vtu";
  hexdem::io::write_vtu(file.string(), g);
  auto out = read_vtu(file);
  expect_points(out, ring.x, ring.y, nullptr);
  std::vector<std::int32_t> all_i = ring.i, all_j = ring.j;
  all_i.insert(all_i.end(), ring.ei.begin(), ring.ei.end());
  all_j.insert(all_j.end(), ring.ej.begin(), ring.ej.end());
  expect_lines(out, all_i, all_j);
  EXPECT_EQ(out->GetNumberOfCells(), 15);
}

TEST(VtuWriter, CompressionLevelsAndThreadCountsGiveSameContent) {
  const fs::path dir = work_dir("levels");
  const Ring ring(5000);
  std::vector<double> a(ring.x.size());
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = std::sqrt(static_cast<double>(k));
  LineGrid g = ring.grid(true, false);
  g.point_data.push_back(hexdem::io::array_view("a", a.data(), a.size()));
  WriteOptions options;
  options.block_size = 1000;

  std::string reference;
  for (int level : {0, 1, 9}) {
    for (int threads : {1, 2, 3}) {
      SCOPED_TRACE("level " + std::to_string(level) + " threads " + std::to_string(threads));
      const int saved = omp_get_max_threads();
      omp_set_num_threads(threads);
      options.compression_level = level;
      const fs::path file = dir / ("l" + std::to_string(level) + "t" + std::to_string(threads) + ".vtu");
      hexdem::io::write_vtu(file.string(), g, options);
      omp_set_num_threads(saved);
      // Thread count never changes the bytes of the file.
      const fs::path first = dir / ("l" + std::to_string(level) + "t1.vtu");
      EXPECT_EQ(read_bytes(file), read_bytes(first));
      auto out = read_vtu(file);
      expect_points(out, ring.x, ring.y, &ring.z);
      expect_array(out->GetPointData()->GetArray("a"), a, 1, VTK_DOUBLE);
      const std::string content = decode_appended(file).at("a").bytes;
      if (reference.empty()) reference = content;
      EXPECT_EQ(content, reference);
    }
  }
  EXPECT_THROW(
      hexdem::io::write_vtu((dir / "bad.vtu").string(), g, WriteOptions{10, 1 << 15}),
      std::invalid_argument);
  EXPECT_THROW(hexdem::io::write_vtu((dir / "bad.vtu").string(), g, WriteOptions{1, 0}),
               std::invalid_argument);
}

TEST(VtuWriter, RepeatedWritesReuseTheirBuffersAndGiveTheSameBytes) {
  // The writer keeps its compressors and batch buffers from one write to the next on each
  // thread: a small write after a large one (buffers larger than it needs, holding the large
  // one's bytes), the large one again, and a write from another thread (its own buffers) give
  // the bytes of the first writes.
  const fs::path dir = work_dir("repeat");
  const Ring small(500), large(60000);
  const LineGrid gs = small.grid(true, false), gl = large.grid(true, false);
  auto write = [&dir](const LineGrid& g, const std::string& name) {
    hexdem::io::write_vtu((dir / name).string(), g);
    return read_bytes(dir / name);
  };
  const std::string s1 = write(gs, "s1.vtu"), l1 = write(gl, "l1.vtu");
  EXPECT_EQ(write(gs, "s2.vtu"), s1);
  EXPECT_EQ(write(gl, "l2.vtu"), l1);
  std::string s3;
  std::thread other([&] { s3 = write(gs, "s3.vtu"); });
  other.join();
  EXPECT_EQ(s3, s1);
  expect_points(read_vtu(dir / "s2.vtu"), small.x, small.y, &small.z);
}

TEST(VtuWriter, AtomicWriteLeavesNoTemporaryFile) {
  const fs::path dir = work_dir("atomic");
  const Ring ring(20);
  LineGrid g = ring.grid(false, false);
  const fs::path file = dir / "grid.vtu";
  hexdem::io::write_vtu(file.string(), g);
  hexdem::io::write_vtu(file.string(), g);  // overwrites
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"grid.vtu"});
  EXPECT_EQ(read_vtu(file)->GetNumberOfPoints(), 20);
}

TEST(VtuWriter, UnwritableFolderThrowsAndLeavesNothing) {
  const fs::path dir = work_dir("unwritable");
  const Ring ring(5);
  LineGrid g = ring.grid(false, false);
  const std::string missing = (dir / "no" / "such" / "folder" / "grid.vtu").string();
  try {
    hexdem::io::write_vtu(missing, g);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  // A regular file where the folder should be.
  std::ofstream(dir / "plain").put('x');
  const std::string under_file = (dir / "plain" / "grid.vtu").string();
  EXPECT_THROW(hexdem::io::write_vtu(under_file, g), std::runtime_error);
  EXPECT_THROW(hexdem::io::write_pvd(under_file + ".pvd", {{0.0, "a.vtu"}}), std::runtime_error);
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"plain"});
}

TEST(VtuWriter, FailingSourceKeepsPreviousFile) {
  const fs::path dir = work_dir("failing");
  const Ring ring(100);
  LineGrid g = ring.grid(false, false);
  const fs::path file = dir / "grid.vtu";
  hexdem::io::write_vtu(file.string(), g);
  const std::string before = read_bytes(file);

  ArraySource bad;
  bad.name = "bad";
  bad.tuples = 100;
  bad.fill = [](std::size_t, std::size_t, void*) { throw std::runtime_error("source failed"); };
  g.point_data.push_back(bad);
  EXPECT_THROW(hexdem::io::write_vtu(file.string(), g), std::runtime_error);
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"grid.vtu"});
  EXPECT_EQ(read_bytes(file), before);
}

TEST(VtuWriter, InvalidGridsAreRejected) {
  const fs::path dir = work_dir("invalid");
  const Ring ring(4);
  const std::string file = (dir / "grid.vtu").string();
  {
    LineGrid g = ring.grid(false, false);
    const std::vector<std::int32_t> bad_i{0, 4};
    const std::vector<std::int32_t> bad_j{1, 2};
    g.num_lines = 2;
    g.line_i = bad_i.data();
    g.line_j = bad_j.data();
    EXPECT_THROW(hexdem::io::write_vtu(file, g), std::invalid_argument);
  }
  {
    LineGrid g = ring.grid(false, false);
    const std::vector<double> short_array(3, 1.0);
    g.point_data.push_back(hexdem::io::array_view("short", short_array.data(), 3));
    EXPECT_THROW(hexdem::io::write_vtu(file, g), std::invalid_argument);
  }
  {
    LineGrid g = ring.grid(false, false);
    const std::vector<double> v(4, 1.0);
    g.point_data.push_back(hexdem::io::array_view("twice", v.data(), 4));
    g.point_data.push_back(hexdem::io::array_view("twice", v.data(), 4));
    EXPECT_THROW(hexdem::io::write_vtu(file, g), std::invalid_argument);
  }
  {
    LineGrid g = ring.grid(false, false);
    g.field_data.push_back(FieldValue{"nul", {}, std::string("a\0b", 3), {}});
    EXPECT_THROW(hexdem::io::write_vtu(file, g), std::invalid_argument);
  }
  EXPECT_TRUE(folder_listing(dir).empty());
}

TEST(VtuWriter, WriteFileAtomic) {
  const fs::path dir = work_dir("atomic_text");
  const fs::path file = dir / "a.txt";
  hexdem::io::write_file_atomic(file.string(), "first");
  hexdem::io::write_file_atomic(file.string(), "second\n");
  EXPECT_EQ(read_bytes(file), "second\n");
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"a.txt"});
}

TEST(VtuPvd, CollectionReadsBack) {
  const fs::path dir = work_dir("pvd");
  const Ring ring(8);
  LineGrid g = ring.grid(false, false);
  const std::vector<double> times{0.0, 1.0 / 3.0, 2.5e-7, 1e-300};
  std::vector<hexdem::io::PvdEntry> entries;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const std::string name = "frames/f_" + std::to_string(k) + ".vtu";
    fs::create_directories(dir / "frames");
    hexdem::io::write_vtu((dir / name).string(), g);
    entries.push_back({times[k], name});
  }
  const fs::path pvd = dir / "series.pvd";
  hexdem::io::write_pvd(pvd.string(), entries);
  EXPECT_EQ(folder_listing(dir), (std::vector<std::string>{"frames", "series.pvd"}));

  const std::string text = read_bytes(pvd);
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\"?>", 0), 0u);
  EXPECT_NE(text.find("<DataSet timestep=\"0.33333333333333331\" group=\"\" part=\"0\" "
                      "file=\"frames/f_1.vtu\"/>"),
            std::string::npos)
      << text;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(pvd.string().c_str());
  ASSERT_EQ(parser->Parse(), 1);
  vtkXMLDataElement* root = parser->GetRootElement();
  ASSERT_NE(root, nullptr);
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  EXPECT_STREQ(root->GetAttribute("version"), "0.1");
  EXPECT_STREQ(root->GetAttribute("byte_order"), "LittleEndian");
  ASSERT_EQ(root->GetNumberOfNestedElements(), 1);
  vtkXMLDataElement* collection = root->GetNestedElement(0);
  EXPECT_STREQ(collection->GetName(), "Collection");
  ASSERT_EQ(collection->GetNumberOfNestedElements(), static_cast<int>(times.size()));
  for (int k = 0; k < collection->GetNumberOfNestedElements(); ++k) {
    vtkXMLDataElement* ds = collection->GetNestedElement(k);
    EXPECT_STREQ(ds->GetName(), "DataSet");
    // %.17g round-trips every double exactly.
    EXPECT_EQ(std::stod(ds->GetAttribute("timestep")), times[static_cast<std::size_t>(k)]);
    // VTK's parser drops empty attributes; the text check below covers group="".
    EXPECT_STREQ(ds->GetAttribute("part"), "0");
    const std::string file = ds->GetAttribute("file");
    EXPECT_EQ(file, entries[static_cast<std::size_t>(k)].file);
    EXPECT_EQ(read_vtu(dir / file)->GetNumberOfCells(), 8);
  }
  EXPECT_THROW(hexdem::io::write_pvd((dir / "nan.pvd").string(), {{std::nan(""), "a.vtu"}}),
               std::invalid_argument);
}

namespace {

/// Four disks of body 0 in a rhombus plus one disk of body 1; sets "bottom" and "left".
hexdem::meshing::Lattice small_lattice(hexdem::meshing::GeometryMode mode) {
  hexdem::meshing::Lattice l;
  l.mode = mode;
  const double r = 0.5e-3;
  const double h = std::sqrt(3.0) * r;
  l.x = {r, 3 * r, 2 * r, 4 * r, 10 * r};
  l.y = {0.0, 0.0, h, h, 5 * r};
  l.radius = {r, r, r, r, 2 * r};
  const double a = 2 * std::sqrt(3.0) * r * r;
  l.cell_area = {a / 2, a / 2, a, a, 4 * a};
  l.cell_cx = {r * 1.1, 3 * r, 2 * r, 4 * r, 10 * r};
  l.cell_cy = {h / 6, h / 6, h, h, 5 * r};
  l.kind = {1, 1, 0, 0, 0};
  l.body = {0, 0, 0, 0, 1};
  l.material = {0, 0, 0, 0, 3};
  l.bond_i = {0, 0, 1, 1, 2};
  l.bond_j = {1, 2, 2, 3, 3};
  l.bond_class = {1, 2, 2, 2, 1};
  if (mode == hexdem::meshing::GeometryMode::Axisymmetric) l.bond_b = {2 * r, 1.5 * r, 2.5 * r, 3.5 * r, 3 * r};
  l.set_names = {"bottom", "left"};
  l.set_offset = {0, 2, 4};
  l.set_disk = {0, 1, 0, 2};
  l.set_length = {r, r, h, h};
  l.set_nx = {0, 0, -1, -1};
  l.set_ny = {-1, -1, 0, 0};
  l.body_names = {"target", "projectile"};
  l.body_region_area = {4 * a, 4 * a};
  return l;
}

void expect_lattice_readback(const fs::path& file, const hexdem::meshing::Lattice& l) {
  auto out = read_vtu(file);
  expect_points(out, l.x, l.y, nullptr);
  expect_lines(out, l.bond_i, l.bond_j);
  vtkPointData* pd = out->GetPointData();
  expect_array(pd->GetArray("radius"), l.radius, 1, VTK_DOUBLE);
  expect_array(pd->GetArray("kind"), l.kind, 1, VTK_UNSIGNED_CHAR);
  expect_array(pd->GetArray("cell_area"), l.cell_area, 1, VTK_DOUBLE);
  expect_array(pd->GetArray("body"), l.body, 1, VTK_INT);
  expect_array(pd->GetArray("material"), l.material, 1, VTK_INT);
  expect_array(pd->GetArray("bottom"), std::vector<std::uint8_t>{1, 1, 0, 0, 0}, 1, VTK_UNSIGNED_CHAR);
  expect_array(pd->GetArray("left"), std::vector<std::uint8_t>{1, 0, 1, 0, 0}, 1, VTK_UNSIGNED_CHAR);
  const bool axi = l.mode == hexdem::meshing::GeometryMode::Axisymmetric;
  EXPECT_EQ(pd->GetNumberOfArrays(), axi ? 8 : 7);
  if (axi)
    expect_array(pd->GetArray("ring_radius"), l.cell_cx, 1, VTK_DOUBLE);
  else
    EXPECT_EQ(pd->GetArray("ring_radius"), nullptr);
  ASSERT_EQ(out->GetCellData()->GetNumberOfArrays(), 1);
  expect_array(out->GetCellData()->GetArray("bond_class"), l.bond_class, 1, VTK_UNSIGNED_CHAR);
  vtkFieldData* fd = out->GetFieldData();
  EXPECT_EQ(fd->GetNumberOfArrays(), 3);
  EXPECT_EQ(string_values(fd->GetAbstractArray("geometry")),
            std::vector<std::string>{axi ? "axisymmetric" : "plane"});
  EXPECT_EQ(string_values(fd->GetAbstractArray("body_names")), l.body_names);
  expect_array(vtkDataArray::SafeDownCast(fd->GetAbstractArray("lattice_radius")),
               std::vector<double>{0.5e-3}, 1, VTK_DOUBLE);
}

}  // namespace

TEST(LatticeVtu, PlaneRoundTrip) {
  const fs::path dir = work_dir("lattice_plane");
  const auto l = small_lattice(hexdem::meshing::GeometryMode::Plane);
  const fs::path file = dir / "lattice.vtu";
  hexdem::meshing::write_lattice_vtu(file.string(), l);
  expect_lattice_readback(file, l);
  EXPECT_EQ(folder_listing(dir), std::vector<std::string>{"lattice.vtu"});
}

TEST(LatticeVtu, AxisymmetricRoundTrip) {
  const fs::path dir = work_dir("lattice_axi");
  const auto l = small_lattice(hexdem::meshing::GeometryMode::Axisymmetric);
  const fs::path file = dir / "lattice.vtu";
  hexdem::meshing::write_lattice_vtu(file.string(), l, WriteOptions{6, 64});
  expect_lattice_readback(file, l);
}

TEST(LatticeVtu, EmptyLattice) {
  const fs::path dir = work_dir("lattice_empty");
  const hexdem::meshing::Lattice l;
  const fs::path file = dir / "lattice.vtu";
  hexdem::meshing::write_lattice_vtu(file.string(), l);
  auto out = read_vtu(file);
  EXPECT_EQ(out->GetNumberOfPoints(), 0);
  EXPECT_EQ(string_values(out->GetFieldData()->GetAbstractArray("geometry")),
            std::vector<std::string>{"plane"});
}

TEST(LatticeVtu, InconsistentArraysAreRejected) {
  const fs::path dir = work_dir("lattice_bad");
  auto l = small_lattice(hexdem::meshing::GeometryMode::Plane);
  l.cell_area.pop_back();
  EXPECT_THROW(hexdem::meshing::write_lattice_vtu((dir / "l.vtu").string(), l),
               std::invalid_argument);
  l = small_lattice(hexdem::meshing::GeometryMode::Plane);
  l.set_names = {"radius", "left"};  // clashes with a built-in array
  EXPECT_THROW(hexdem::meshing::write_lattice_vtu((dir / "l.vtu").string(), l),
               std::invalid_argument);
  EXPECT_TRUE(folder_listing(dir).empty());
}

TEST(LatticeVtuSets, FindSetAndMembership) {
  const auto l = small_lattice(hexdem::meshing::GeometryMode::Plane);
  EXPECT_EQ(l.find_set("bottom"), 0);
  EXPECT_EQ(l.find_set("left"), 1);
  EXPECT_EQ(l.find_set("top"), -1);
  EXPECT_EQ(l.set_membership(0), (std::vector<std::uint8_t>{1, 1, 0, 0, 0}));
  EXPECT_EQ(l.set_membership(1), (std::vector<std::uint8_t>{1, 0, 1, 0, 0}));
  EXPECT_THROW((void)l.set_membership(2), std::out_of_range);
}

TEST(LatticeVtuSets, MemoryBytesCountsCapacity) {
  hexdem::meshing::Lattice l;
  EXPECT_EQ(l.memory_bytes(), 0u);
  l.x.reserve(1000);
  l.bond_i.reserve(10);
  EXPECT_GE(l.memory_bytes(), 1000 * sizeof(double) + 10 * sizeof(std::int32_t));
  l.body_names = {std::string(100, 'a')};
  EXPECT_GE(l.memory_bytes(), 1000 * sizeof(double) + 40 + 100);
}
