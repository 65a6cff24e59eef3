#include "frame_builder.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace hexdem::testing {
namespace {

template <typename T>
vtkSmartPointer<T> named(const char* name, int components, std::int64_t tuples) {
  auto a = vtkSmartPointer<T>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

void add_number(vtkFieldData* fd, const char* name, double value) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

}  // namespace

Lattice make_lattice(int nx, int ny, double r) {
  Lattice l;
  l.nx = nx;
  l.ny = ny;
  l.r = r;
  const double h = std::sqrt(3.0) * r;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      l.x.push_back(2 * r * i + (j % 2 ? r : 0.0));
      l.y.push_back(h * j);
    }
  }
  auto bond = [&](std::int64_t a, std::int64_t b, std::uint8_t cls) {
    l.bond_i.push_back(a);
    l.bond_j.push_back(b);
    l.bond_class.push_back(cls);
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) bond(l.id(i, j), l.id(i + 1, j), 1);
      if (j + 1 < ny) {
        // Row above: even rows reach (i-1, j+1) and (i, j+1); odd rows (i, j+1), (i+1, j+1).
        const int left = j % 2 ? i : i - 1;
        if (left >= 0) bond(l.id(i, j), l.id(left, j + 1), 2);
        if (left + 1 < nx) bond(l.id(i, j), l.id(left + 1, j + 1), 2);
      }
    }
  }
  return l;
}

vtkSmartPointer<vtkUnstructuredGrid> make_frame(const Lattice& l, const FrameData& d) {
  const std::int64_t n = l.disks();
  const std::int64_t nb = l.bonds();
  const std::int64_t nc = static_cast<std::int64_t>(d.contact_i.size());
  const std::int64_t cells = nb + nc;
  const double area = 2 * std::sqrt(3.0) * l.r * l.r;

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (std::int64_t k = 0; k < n; ++k) points->SetPoint(k, l.x[k], l.y[k], 0.0);
  grid->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> conn;
  offsets->SetNumberOfValues(cells + 1);
  conn->SetNumberOfValues(2 * cells);
  for (std::int64_t c = 0; c <= cells; ++c) offsets->SetValue(c, 2 * c);
  for (std::int64_t c = 0; c < nb; ++c) {
    conn->SetValue(2 * c, l.bond_i[c]);
    conn->SetValue(2 * c + 1, l.bond_j[c]);
  }
  for (std::int64_t c = 0; c < nc; ++c) {
    conn->SetValue(2 * (nb + c), d.contact_i[c]);
    conn->SetValue(2 * (nb + c) + 1, d.contact_j[c]);
  }
  vtkNew<vtkCellArray> lines;
  lines->SetData(offsets, conn);
  grid->SetCells(VTK_LINE, lines);

  vtkPointData* pd = grid->GetPointData();
  auto radius = named<vtkDoubleArray>("radius", 1, n);
  auto kind = named<vtkUnsignedCharArray>("kind", 1, n);
  auto body = named<vtkIntArray>("body", 1, n);
  auto material = named<vtkIntArray>("material", 1, n);
  auto mass = named<vtkDoubleArray>("mass", 1, n);
  auto cell_area = named<vtkDoubleArray>("cell_area", 1, n);
  auto displacement = named<vtkDoubleArray>("displacement", 3, n);
  auto velocity = named<vtkDoubleArray>("velocity", 3, n);
  auto rotation = named<vtkDoubleArray>("rotation", 1, n);
  auto spin = named<vtkDoubleArray>("spin", 1, n);
  auto stress = named<vtkDoubleArray>("stress", 9, n);
  auto damage = named<vtkDoubleArray>("damage", 1, n);
  // damage: broken fraction of each disk's bonds.
  std::vector<int> bonds_of(n, 0), broken_of(n, 0);
  for (std::int64_t c = 0; c < nb; ++c) {
    const bool broken = !d.state.empty() && d.state[c] >= 2 && d.state[c] <= 4;
    for (std::int64_t k : {l.bond_i[c], l.bond_j[c]}) {
      ++bonds_of[k];
      broken_of[k] += broken;
    }
  }
  for (std::int64_t k = 0; k < n; ++k) {
    radius->SetValue(k, l.r);
    kind->SetValue(k, 0);
    body->SetValue(k, 0);
    material->SetValue(k, 0);
    cell_area->SetValue(k, area);
    mass->SetValue(k, d.density * area * d.thickness);
    rotation->SetValue(k, 0.0);
    spin->SetValue(k, 0.0);
    damage->SetValue(k, bonds_of[k] ? static_cast<double>(broken_of[k]) / bonds_of[k] : 0.0);
    for (int c = 0; c < 3; ++c) {
      displacement->SetComponent(k, c, 0.0);
      velocity->SetComponent(k, c, d.velocity.empty() ? 0.0 : d.velocity[3 * k + c]);
    }
    for (int c = 0; c < 9; ++c)
      stress->SetComponent(k, c, d.stress.empty() ? 0.0 : d.stress[9 * k + c]);
  }
  for (auto* a : {static_cast<vtkDataArray*>(radius), static_cast<vtkDataArray*>(kind),
                  static_cast<vtkDataArray*>(body), static_cast<vtkDataArray*>(material),
                  static_cast<vtkDataArray*>(mass), static_cast<vtkDataArray*>(cell_area),
                  static_cast<vtkDataArray*>(displacement), static_cast<vtkDataArray*>(velocity),
                  static_cast<vtkDataArray*>(rotation), static_cast<vtkDataArray*>(spin),
                  static_cast<vtkDataArray*>(stress), static_cast<vtkDataArray*>(damage)}) {
    pd->AddArray(a);
  }

  vtkCellData* cd = grid->GetCellData();
  auto state = named<vtkUnsignedCharArray>("state", 1, cells);
  auto fn = named<vtkDoubleArray>("normal_force", 1, cells);
  auto fs = named<vtkDoubleArray>("shear_force", 1, cells);
  auto bt = named<vtkDoubleArray>("break_time", 1, cells);
  auto cls = named<vtkUnsignedCharArray>("bond_class", 1, cells);
  for (std::int64_t c = 0; c < nb; ++c) {
    state->SetValue(c, d.state.empty() ? 0 : d.state[c]);
    fn->SetValue(c, d.normal_force.empty() ? 0.0 : d.normal_force[c]);
    fs->SetValue(c, d.shear_force.empty() ? 0.0 : d.shear_force[c]);
    bt->SetValue(c, d.break_time.empty() ? -1.0 : d.break_time[c]);
    cls->SetValue(c, l.bond_class[c]);
  }
  for (std::int64_t c = 0; c < nc; ++c) {
    state->SetValue(nb + c, 5);
    fn->SetValue(nb + c, d.contact_normal_force.empty() ? 0.0 : d.contact_normal_force[c]);
    fs->SetValue(nb + c, d.contact_shear_force.empty() ? 0.0 : d.contact_shear_force[c]);
    bt->SetValue(nb + c, -1.0);
    cls->SetValue(nb + c, 0);
  }
  for (auto* a : {static_cast<vtkDataArray*>(state), static_cast<vtkDataArray*>(fn),
                  static_cast<vtkDataArray*>(fs), static_cast<vtkDataArray*>(bt),
                  static_cast<vtkDataArray*>(cls)}) {
    cd->AddArray(a);
  }

  vtkFieldData* fd = grid->GetFieldData();
  add_number(fd, "time", d.time);
  add_number(fd, "step", d.step);
  vtkNew<vtkStringArray> geometry;
  geometry->SetName("geometry");
  geometry->InsertNextValue(d.geometry);
  fd->AddArray(geometry);
  add_number(fd, "thickness", d.thickness);
  if (d.p_max > 0) add_number(fd, "p_max", d.p_max);
  return grid;
}

void write_frame(const std::string& path, vtkUnstructuredGrid* frame) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(frame);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt64();
  if (writer->Write() != 1) throw std::runtime_error(path + ": cannot write the frame");
}

void write_series(const std::string& path, const std::vector<std::string>& files,
                  const std::vector<double>& times) {
  std::ofstream out(path);
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
  char buffer[64];
  for (std::size_t k = 0; k < files.size(); ++k) {
    std::snprintf(buffer, sizeof buffer, "%.17g", times[k]);
    out << "    <DataSet timestep=\"" << buffer << "\" group=\"\" part=\"0\" file=\"" << files[k]
        << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  if (!out) throw std::runtime_error(path + ": cannot write the series");
}

std::vector<std::int64_t> bonds_crossing_x(const Lattice& l, double x0) {
  std::vector<std::int64_t> out;
  for (std::int64_t b = 0; b < l.bonds(); ++b) {
    const double a = l.x[l.bond_i[b]] - x0;
    const double c = l.x[l.bond_j[b]] - x0;
    if (a * c < 0) out.push_back(b);
  }
  return out;
}

std::vector<std::int64_t> bonds_crossing_y(const Lattice& l, double y0) {
  std::vector<std::int64_t> out;
  for (std::int64_t b = 0; b < l.bonds(); ++b) {
    const double a = l.y[l.bond_i[b]] - y0;
    const double c = l.y[l.bond_j[b]] - y0;
    if (a * c < 0) out.push_back(b);
  }
  return out;
}

}  // namespace hexdem::testing
