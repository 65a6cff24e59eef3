#include "hexdem/meshing/lattice_vtu.hpp"

#include <stdexcept>
#include <vector>

namespace hexdem::meshing {

namespace {

void check_size(const std::string& path, const char* name, std::size_t size,
                std::size_t expected) {
  if (size != expected)
    throw std::invalid_argument("'" + path + "': lattice array '" + name + "' has " +
                                std::to_string(size) + " entries, expected " +
                                std::to_string(expected));
}

void check_lattice(const std::string& path, const Lattice& l) {
  const std::size_t n = l.num_disks();
  check_size(path, "y", l.y.size(), n);
  check_size(path, "radius", l.radius.size(), n);
  check_size(path, "cell_area", l.cell_area.size(), n);
  check_size(path, "kind", l.kind.size(), n);
  check_size(path, "body", l.body.size(), n);
  check_size(path, "material", l.material.size(), n);
  if (l.mode == GeometryMode::Axisymmetric) check_size(path, "cell_cx", l.cell_cx.size(), n);
  check_size(path, "bond_j", l.bond_j.size(), l.num_bonds());
  check_size(path, "bond_class", l.bond_class.size(), l.num_bonds());
  if (l.num_sets() != 0 || !l.set_offset.empty())
    check_size(path, "set_offset", l.set_offset.size(), l.num_sets() + 1);
}

/// Radius of the disks of body 0 (all disks of a body share one radius), or a negative value
/// when body 0 has no disk.
double first_body_radius(const Lattice& l) {
  for (std::size_t d = 0; d < l.num_disks(); ++d) {
    if (l.body[d] == 0) return l.radius[d];
  }
  return -1.0;
}

}  // namespace

void write_lattice_vtu(const std::string& path, const Lattice& lattice,
                       const io::WriteOptions& options) {
  check_lattice(path, lattice);
  const std::size_t n = lattice.num_disks();

  io::LineGrid grid;
  grid.num_points = n;
  grid.x = lattice.x.data();
  grid.y = lattice.y.data();
  grid.num_lines = lattice.num_bonds();
  grid.line_i = lattice.bond_i.data();
  grid.line_j = lattice.bond_j.data();

  auto& pd = grid.point_data;
  pd.push_back(io::array_view("radius", lattice.radius.data(), n));
  pd.push_back(io::array_view("kind", lattice.kind.data(), n));
  pd.push_back(io::array_view("cell_area", lattice.cell_area.data(), n));
  pd.push_back(io::array_view("body", lattice.body.data(), n));
  pd.push_back(io::array_view("material", lattice.material.data(), n));
  if (lattice.mode == GeometryMode::Axisymmetric)
    pd.push_back(io::array_view("ring_radius", lattice.cell_cx.data(), n));
  // One byte per disk and set; the vectors must outlive write_vtu.
  std::vector<std::vector<std::uint8_t>> membership;
  membership.reserve(lattice.num_sets());
  for (std::size_t s = 0; s < lattice.num_sets(); ++s) {
    membership.push_back(lattice.set_membership(s));
    pd.push_back(io::array_view(lattice.set_names[s], membership.back().data(), n));
  }

  grid.cell_data.push_back(
      io::array_view("bond_class", lattice.bond_class.data(), lattice.num_bonds()));
  if (lattice.bond_on_edge.size() == lattice.num_bonds()) {
    grid.cell_data.push_back(
        io::array_view("bond_on_edge", lattice.bond_on_edge.data(), lattice.num_bonds()));
  }

  io::FieldValue geometry;
  geometry.name = "geometry";
  geometry.text = lattice.mode == GeometryMode::Axisymmetric ? "axisymmetric" : "plane";
  grid.field_data.push_back(std::move(geometry));
  if (!lattice.body_names.empty()) {
    io::FieldValue names;
    names.name = "body_names";
    names.strings = lattice.body_names;
    grid.field_data.push_back(std::move(names));
  }
  if (const double r = first_body_radius(lattice); r >= 0.0) {
    io::FieldValue radius;
    radius.name = "lattice_radius";
    radius.numbers = {r};
    grid.field_data.push_back(std::move(radius));
  }

  io::write_vtu(path, grid, options);
}

}  // namespace hexdem::meshing
