#include "hexdem/meshing/lattice.hpp"

#include <stdexcept>

#include "hexdem/error.hpp"

namespace hexdem::meshing {

namespace {

template <typename T>
std::size_t held_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

std::size_t held_bytes(const std::vector<std::string>& v) {
  std::size_t n = v.capacity() * sizeof(std::string);
  for (const auto& s : v) {
    // Short strings live inside the std::string object itself.
    if (s.capacity() > std::string().capacity()) n += s.capacity() + 1;
  }
  return n;
}

}  // namespace

int Lattice::find_set(const std::string& name) const {
  for (std::size_t s = 0; s < set_names.size(); ++s) {
    if (set_names[s] == name) return static_cast<int>(s);
  }
  return -1;
}

std::vector<std::uint8_t> Lattice::set_membership(std::size_t s) const {
  if (s >= num_sets())
    throw std::out_of_range("Lattice::set_membership: set " + std::to_string(s) + " of " +
                            std::to_string(num_sets()));
  HEXDEM_VERIFY(set_offset.size() == num_sets() + 1, "set_offset has one entry per set plus one");
  const auto begin = set_offset[s];
  const auto end = set_offset[s + 1];
  HEXDEM_VERIFY(0 <= begin && begin <= end && end <= static_cast<std::int64_t>(set_disk.size()),
                "set '" + set_names[s] + "' has offsets outside set_disk");
  std::vector<std::uint8_t> member(num_disks(), 0);
  for (auto k = begin; k < end; ++k) {
    const std::int32_t d = set_disk[static_cast<std::size_t>(k)];
    HEXDEM_VERIFY(d >= 0 && static_cast<std::size_t>(d) < num_disks(),
                  "set '" + set_names[s] + "' refers to disk " + std::to_string(d));
    member[static_cast<std::size_t>(d)] = 1;
  }
  return member;
}

std::size_t Lattice::memory_bytes() const {
  return held_bytes(x) + held_bytes(y) + held_bytes(radius) + held_bytes(cell_area) +
         held_bytes(cell_cx) + held_bytes(cell_cy) + held_bytes(kind) + held_bytes(body) +
         held_bytes(material) + held_bytes(bond_i) + held_bytes(bond_j) +
         held_bytes(bond_class) + held_bytes(bond_on_edge) + held_bytes(bond_b) + held_bytes(set_names) +
         held_bytes(set_offset) + held_bytes(set_disk) + held_bytes(set_length) +
         held_bytes(set_nx) + held_bytes(set_ny) + held_bytes(set_distance) + held_bytes(set_cx) + held_bytes(set_cy) + held_bytes(body_names) +
         held_bytes(body_region_area);
}

}  // namespace hexdem::meshing
