// Writes the synthetic frames that the ParaView, Python and `hexdem post` tests read:
//   fractured.vtu   120 x 80 disks under a line load (Flamant stress field), 10 % of the
//                   bonds broken at random, cracks that cut off two blocks, round chips,
//                   a crushed zone of loose disks under the load, and contacts (state 5)
//   series.pvd      3 frames of a 30 x 20 lattice: intact, cut in two, then in three
//   bad/            no_state.vtu, no_stress.vtu (no stress and no bond forces), empty.vtu,
//                   not_hexdem.vtu (a triangle), garbage.vtu (not XML), truncated.vtu
// Usage: make_test_frames OUTPUT_FOLDER

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "frame_builder.hpp"

namespace fs = std::filesystem;
using namespace hexdem::testing;

namespace {

constexpr double kR = 5e-4;

/// Flamant's solution for a line load P [N/m] on a half-plane, applied at (xc, yc) above
/// the lattice: sigma_r = -2 P cos(theta) / (pi rho), radial. Plane strain s_zz (nu 0.25).
std::vector<double> flamant(const Lattice& l, double P, double xc, double yc) {
  std::vector<double> s;
  for (std::int64_t k = 0; k < l.disks(); ++k) {
    const double dx = l.x[k] - xc, dy = l.y[k] - yc;
    const double rho = std::hypot(dx, dy);
    const double ex = dx / rho, ey = dy / rho;
    const double sr = -2 * P * (-ey) / (std::numbers::pi * rho);
    const double xx = sr * ex * ex, yy = sr * ey * ey, xy = sr * ex * ey;
    s.insert(s.end(), {xx, xy, 0.0, xy, yy, 0.0, 0.0, 0.0, 0.25 * (xx + yy)});
  }
  return s;
}

void break_bonds(FrameData& d, const std::vector<std::int64_t>& bonds, std::uint8_t mode,
                 double t) {
  for (auto b : bonds) {
    d.state[b] = mode;
    d.break_time[b] = t;
  }
}

void write_fractured(const fs::path& dir) {
  Lattice l = make_lattice(120, 80, kR);
  const double width = 2 * kR * 120, height = std::sqrt(3.0) * kR * 79;
  FrameData d;
  d.time = 1.04e-4;
  d.step = 416;
  d.geometry = "plane-strain";
  d.thickness = 1.0;
  d.p_max = 1e7;
  d.state.assign(l.bonds(), 0);
  d.break_time.assign(l.bonds(), -1.0);
  d.normal_force.assign(l.bonds(), 0.0);
  d.shear_force.assign(l.bonds(), 0.0);
  std::mt19937 rng(2004);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::int64_t b = 0; b < l.bonds(); ++b) {
    if (unit(rng) < 0.10) {
      d.state[b] = static_cast<std::uint8_t>(2 + static_cast<int>(3 * unit(rng)) % 3);
      d.break_time[b] = 1e-4 * unit(rng);
    } else {
      d.normal_force[b] = 200.0 * (unit(rng) - 0.5);
      d.shear_force[b] = 50.0 * (unit(rng) - 0.5);
      if (unit(rng) < 0.05) d.state[b] = 1;
    }
  }
  // Cracks from the top down to a horizontal crack: two blocks come loose.
  std::vector<std::int64_t> vertical, horizontal;
  for (auto b : bonds_crossing_x(l, 0.5 * width - 0.5 * kR)) {
    if (l.y[l.bond_i[b]] > 0.45 * height) vertical.push_back(b);
  }
  for (auto b : bonds_crossing_y(l, 0.45 * height + 0.25 * kR)) {
    const double x = l.x[l.bond_i[b]];
    if (x > 0.2 * width && x < 0.8 * width) horizontal.push_back(b);
  }
  for (double x0 : {0.2 * width + 0.5 * kR, 0.8 * width + 0.5 * kR}) {
    for (auto b : bonds_crossing_x(l, x0)) {
      if (l.y[l.bond_i[b]] > 0.45 * height) horizontal.push_back(b);
    }
  }
  break_bonds(d, vertical, 2, 3e-5);
  break_bonds(d, horizontal, 3, 6e-5);
  // Round chips of 10 to 200 disks cut out of the lower part.
  const double chips[][3] = {{0.15, 0.2, 2.0}, {0.3, 0.15, 3.5}, {0.45, 0.25, 5.0},
                             {0.6, 0.12, 2.6}, {0.75, 0.3, 7.5}, {0.9, 0.2, 4.2}};
  for (const auto& c : chips) {
    const double cx = c[0] * width, cy = c[1] * height, radius = c[2] * 2 * kR;
    for (std::int64_t b = 0; b < l.bonds(); ++b) {
      const bool in_i = std::hypot(l.x[l.bond_i[b]] - cx, l.y[l.bond_i[b]] - cy) < radius;
      const bool in_j = std::hypot(l.x[l.bond_j[b]] - cx, l.y[l.bond_j[b]] - cy) < radius;
      if (in_i != in_j) {
        d.state[b] = 3;
        d.break_time[b] = 8e-5;
      }
    }
  }
  // Crushed zone under the load: every bond broken in compression.
  for (std::int64_t b = 0; b < l.bonds(); ++b) {
    const std::int64_t i = l.bond_i[b];
    if (std::hypot(l.x[i] - 0.3 * width, l.y[i] - height) < 8 * kR) {
      d.state[b] = 4;
      d.break_time[b] = 1e-5;
    }
  }
  // Contacts across the vertical crack (they must not connect fragments).
  for (std::size_t k = 0; k < vertical.size(); k += 3) {
    d.contact_i.push_back(l.bond_i[vertical[k]]);
    d.contact_j.push_back(l.bond_j[vertical[k]]);
    d.contact_normal_force.push_back(-20.0);
    d.contact_shear_force.push_back(1.0);
  }
  d.stress = flamant(l, 2e4, 0.3 * width, height + 4 * kR);
  for (std::int64_t k = 0; k < l.disks(); ++k) {
    d.velocity.insert(d.velocity.end(), {0.1 * (l.x[k] - 0.5 * width), -2.0, 0.0});
  }
  write_frame((dir / "fractured.vtu").string(), make_frame(l, d));
}

void write_series_frames(const fs::path& dir) {
  const Lattice l = make_lattice(30, 20, kR);
  const double h = std::sqrt(3.0) * kR;
  std::vector<std::string> files;
  std::vector<double> times;
  FrameData d;
  d.state.assign(l.bonds(), 0);
  d.break_time.assign(l.bonds(), -1.0);
  d.p_max = 2e6;
  d.stress.assign(9 * l.disks(), 0.0);
  for (std::int64_t k = 0; k < l.disks(); ++k) d.stress[9 * k] = 1e6 * (1 + l.y[k] / (20 * h));
  for (int f = 0; f < 3; ++f) {
    d.time = 1e-5 * f;
    d.step = 100 * f;
    if (f == 1) break_bonds(d, bonds_crossing_y(l, 9.5 * h), 2, 0.7e-5);
    if (f == 2) {
      std::vector<std::int64_t> upper;
      for (auto b : bonds_crossing_x(l, 30.5 * kR)) {
        if (l.y[l.bond_i[b]] > 9.5 * h) upper.push_back(b);
      }
      break_bonds(d, upper, 3, 1.6e-5);
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.vtu", f);
    fs::create_directories(dir / "series");
    write_frame((dir / "series" / name).string(), make_frame(l, d));
    files.push_back(std::string("series/") + name);
    times.push_back(d.time);
  }
  write_series((dir / "series.pvd").string(), files, times);
}

void write_bad_frames(const fs::path& dir) {
  const fs::path bad = dir / "bad";
  fs::create_directories(bad);
  const Lattice l = make_lattice(8, 6, kR);
  FrameData d;
  d.p_max = 1e6;
  d.state.assign(l.bonds(), 0);
  d.state[3] = 2;
  auto frame = make_frame(l, d);
  frame->GetCellData()->RemoveArray("state");
  write_frame((bad / "no_state.vtu").string(), frame);
  frame = make_frame(l, d);
  frame->GetPointData()->RemoveArray("stress");
  frame->GetCellData()->RemoveArray("normal_force");
  write_frame((bad / "no_stress.vtu").string(), frame);
  vtkNew<vtkUnstructuredGrid> empty;
  write_frame((bad / "empty.vtu").string(), empty);

  vtkNew<vtkUnstructuredGrid> triangle;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(0, 1, 0);
  triangle->SetPoints(points);
  vtkIdType ids[3] = {0, 1, 2};
  triangle->InsertNextCell(VTK_TRIANGLE, 3, ids);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("temperature");
  temperature->SetNumberOfTuples(3);
  temperature->FillValue(300.0);
  triangle->GetPointData()->AddArray(temperature);
  write_frame((bad / "not_hexdem.vtu").string(), triangle);

  std::ofstream(bad / "garbage.vtu") << "this is not a VTK file\n";
  const fs::path good = bad / "good.vtu";
  write_frame(good.string(), make_frame(l, d));
  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(bad / "truncated.vtu", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_test_frames OUTPUT_FOLDER\n");
    return 2;
  }
  try {
    const fs::path dir = argv[1];
    fs::create_directories(dir);
    write_fractured(dir);
    write_series_frames(dir);
    write_bad_frames(dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_test_frames: %s\n", e.what());
    return 1;
  }
  return 0;
}
