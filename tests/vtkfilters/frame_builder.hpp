#pragma once
/// \file frame_builder.hpp
/// Synthetic hexdem result frames for the filter tests and benchmarks: a hexagonal lattice
/// of disks with every frame array of the solver's output contract (docs/filters.md), built
/// in memory, and writers for .vtu frames and .pvd series.

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hexdem::testing {

/// A hexagonal lattice: nx disks per row, ny rows; odd rows shifted by r. Disk (i, j) has
/// index j * nx + i and centre (2 r i + (j odd ? r : 0), sqrt(3) r j). Bonds go to the
/// right neighbour (class 1) and to the two neighbours in the row above (class 2), i < j.
struct Lattice {
  int nx = 0;
  int ny = 0;
  double r = 0.0;
  std::vector<double> x, y;
  std::vector<std::int64_t> bond_i, bond_j;
  std::vector<std::uint8_t> bond_class;

  std::int64_t disks() const { return static_cast<std::int64_t>(x.size()); }
  std::int64_t bonds() const { return static_cast<std::int64_t>(bond_i.size()); }
  std::int64_t id(int i, int j) const { return static_cast<std::int64_t>(j) * nx + i; }
};

Lattice make_lattice(int nx, int ny, double r);

/// Per-bond and per-disk values of a frame; empty vectors mean defaults (state 0, forces 0,
/// break_time -1, stress 0, velocity 0).
struct FrameData {
  std::vector<std::uint8_t> state;   ///< per bond
  std::vector<double> normal_force;  ///< per bond [N]
  std::vector<double> shear_force;   ///< per bond [N]
  std::vector<double> break_time;    ///< per bond [s]
  std::vector<double> stress;        ///< 9 per disk [Pa]
  std::vector<double> velocity;      ///< 3 per disk [m/s]
  /// Contacts written after the bonds (state 5): disk pairs and their forces.
  std::vector<std::int64_t> contact_i, contact_j;
  std::vector<double> contact_normal_force, contact_shear_force;
  double time = 0.0;
  int step = 0;
  std::string geometry = "plane-stress";
  double thickness = 0.01;  ///< [m]
  double p_max = 0.0;       ///< written as field data when > 0 [Pa]
  double density = 1000.0;  ///< mass = density * cell_area * thickness [kg]
};

/// The frame of `lattice` with `data`: every array of the output contract, with the types
/// the solver writes (Float64, UInt8 state/kind/bond_class, Int32 body/material).
vtkSmartPointer<vtkUnstructuredGrid> make_frame(const Lattice& lattice, const FrameData& data);

/// Writes a frame as a .vtu (appended raw binary, zlib). Throws std::runtime_error on failure.
void write_frame(const std::string& path, vtkUnstructuredGrid* frame);

/// Writes a .pvd listing `files` (relative to the .pvd's folder) at `times`.
void write_series(const std::string& path, const std::vector<std::string>& files,
                  const std::vector<double>& times);

/// Bonds whose segment crosses the vertical line x = x0 (one end left of it, one right).
std::vector<std::int64_t> bonds_crossing_x(const Lattice& lattice, double x0);
/// Bonds whose segment crosses the horizontal line y = y0.
std::vector<std::int64_t> bonds_crossing_y(const Lattice& lattice, double y0);

}  // namespace hexdem::testing
