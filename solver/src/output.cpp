// Run output: frames (.vtu + .pvd), energy and probe histories (CSV), and the run loop.
#include "hexdem/solver/output.hpp"

#include <fcntl.h>
#include <omp.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hexdem/error.hpp"
#include "hexdem/solver/case_toml.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/toml_values.hpp"
#include "hexdem/solver/run_summary.hpp"

namespace hexdem::solver {
namespace {

namespace fs = std::filesystem;

std::string frame_name(const std::string& name, std::int64_t step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "_%09lld.vtu", static_cast<long long>(step));
  return name + buf;
}

void csv_number(CsvFile& o, double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  o << std::string_view(buf);
}

std::string errno_reason() { return std::strerror(errno); }

/// Next output time after `now` for outputs every `interval` from `next`: the smallest
/// next + k interval > now. Jumps instead of stepping when the interval is so small that
/// stepping would take long or, below the resolution of `next`, never end.
double next_output_time(double next, double interval, double now) {
  if (next > now) return next;
  const double stepped = next + interval;
  if (stepped > now) return stepped;
  double jumped = interval * (std::floor(now / interval) + 1.0);
  if (!(jumped > now)) jumped = std::nextafter(now, std::numeric_limits<double>::infinity());
  return jumped;
}

/// Names of the point arrays of a frame (a boundary set of one of these names is written
/// as `set_<name>`, so that it cannot replace the frame's own array).
bool is_frame_array(const std::string& name) {
  static const char* const names[] = {"radius",   "kind",         "body",     "material",
                                      "mass",     "cell_area",    "ring_radius", "displacement",
                                      "velocity", "rotation",     "spin",     "stress",
                                      "damage",   "plastic_strain", "contact_radius"};
  for (const char* n : names) {
    if (name == n) return true;
  }
  return name.rfind("set_", 0) == 0;
}

/// What the lattice file has and a frame needs to name bodies and select sets: the field data
/// `body_names` and `boundary_sets` (the point array of each set, in set order) and one UInt8
/// point array per boundary set, 1 for its members (docs/file-format.md). Filled on demand
/// from the lattice's compressed set rows: no per-frame copies.
void add_bodies_and_sets(const meshing::Lattice& lattice, std::size_t n, io::LineGrid& g) {
  if (!lattice.body_names.empty()) g.field_data.push_back({"body_names", {}, {}, lattice.body_names});
  std::vector<std::string> set_arrays;
  for (std::size_t s = 0; s < lattice.num_sets(); ++s) {
    const std::string& name = lattice.set_names[s];
    set_arrays.push_back(is_frame_array(name) ? "set_" + name : name);
    io::ArraySource a;
    a.name = set_arrays.back();
    a.type = io::ScalarType::UInt8;
    a.tuples = n;
    const std::int32_t* first_member = lattice.set_disk.data() + lattice.set_offset[s];
    const std::int32_t* end_member = lattice.set_disk.data() + lattice.set_offset[s + 1];
    a.fill = [first_member, end_member](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<std::uint8_t*>(out);
      std::fill(o, o + count, std::uint8_t{0});
      // Members are ascending within a set (lattice.hpp).
      const auto lo = std::lower_bound(first_member, end_member, static_cast<std::int32_t>(first));
      for (auto it = lo; it != end_member && static_cast<std::size_t>(*it) < first + count; ++it)
        o[static_cast<std::size_t>(*it) - first] = 1;
    };
    g.point_data.push_back(std::move(a));
  }
  if (!set_arrays.empty()) g.field_data.push_back({"boundary_sets", {}, {}, set_arrays});
}

}  // namespace

void make_folder(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir + ": cannot create the output folder (a file of that name exists)");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output folder (" + ec.message() + ")");
}

CsvFile::~CsvFile() {
  if (fd_ >= 0) ::close(fd_);
}

void CsvFile::open(const std::string& path, bool append) {
  path_ = path;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC) | O_CLOEXEC, 0666);
  if (fd_ < 0) throw InputError(path + ": cannot write (" + errno_reason() + ")");
  written_ = 0;
  max_row_ = 0;
  if (append) {
    const off_t end = ::lseek(fd_, 0, SEEK_END);
    if (end < 0) throw InputError(path + ": cannot write (" + errno_reason() + ")");
    written_ = static_cast<std::uint64_t>(end);
  }
}

void CsvFile::flush() {
  // Linux copies a write() page by page and stops at a page boundary when the process is
  // killed, so a kill can cut the file only at the end of a write() or at a 4 KiB boundary of
  // the file. Each write() here stays inside one page, and the rows are laid out so that none
  // straddles a boundary: a row after which the page has less room left than the longest
  // possible row of this file is preceded by spaces (leading blanks of its first number, which ParaView,
  // numpy and Python skip) until it ends exactly at the page's end. A kill then leaves whole rows.
  // The exceptions (docs/file-format.md): the first line of the file is never padded (it is
  // the header), and a file whose rows can be longer than half a page (more than about 110
  // columns) is written unpadded.
  const std::size_t last_newline = buffer_.rfind('\n');
  if (last_newline == std::string::npos) return;  // only whole rows reach the file
  const std::size_t whole = last_newline + 1;
  if (max_row_ == 0) {
    // Every field is a %.10g number (at most 17 characters) or the step (at most 20), with
    // its separator; the first row seen (the header, or a row after a restart) gives the
    // column count.
    const std::string_view first_row(buffer_.data(), buffer_.find('\n'));
    const auto columns = static_cast<std::size_t>(std::count(first_row.begin(), first_row.end(), ',')) + 1;
    max_row_ = columns * 18 + 3 + 1;
  }
  const bool padded = max_row_ <= kPage / 2;
  layout_.clear();
  std::uint64_t pos = written_;
  for (std::size_t begin = 0; begin < whole;) {
    const std::size_t stop = buffer_.find('\n', begin) + 1;
    const std::size_t length = stop - begin;
    const std::uint64_t room = kPage - pos % kPage;
    std::uint64_t pad = 0;
    if (padded && pos != 0 && length <= room && room - length < max_row_) pad = room - length;
    layout_.append(static_cast<std::size_t>(pad), ' ');
    layout_.append(buffer_, begin, length);
    pos += pad + length;
    begin = stop;
  }
  buffer_.erase(0, whole);
  std::size_t done = 0;
  while (done < layout_.size()) {
    const std::size_t room = static_cast<std::size_t>(kPage - written_ % kPage);
    const std::size_t count = std::min(room, layout_.size() - done);
    const ssize_t n = ::write(fd_, layout_.data() + done, count);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw InputError(path_ + ": write failed (" + (n < 0 ? errno_reason() : "no progress") + ")");
    done += static_cast<std::size_t>(n);
    written_ += static_cast<std::uint64_t>(n);
  }
}

void CsvFile::close() {
  if (fd_ < 0) return;
  flush();
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) throw InputError(path_ + ": write failed (" + errno_reason() + ")");
}

io::LineGrid RunOutput::frame_grid(const Solver& solver, ContactCells& contacts) {
  const Model& m = solver.model();
  const std::size_t n = m.num_disks(), nb = m.num_bonds();
  io::LineGrid g;
  g.num_points = n;
  g.num_lines = nb;
  g.line_i = m.bi.data();
  g.line_j = m.bj.data();
  // Points: current centres (x0 + u). Written through a callback: no copies.
  g.point_data.clear();
  auto vec3 = [n](std::string name, auto get) {
    io::ArraySource a;
    a.name = std::move(name);
    a.type = io::ScalarType::Float64;
    a.components = 3;
    a.tuples = n;
    a.fill = [get](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<double*>(out);
      for (std::size_t k = 0; k < count; ++k) {
        const auto [x, y] = get(first + k);
        o[3 * k] = x;
        o[3 * k + 1] = y;
        o[3 * k + 2] = 0.0;
      }
    };
    return a;
  };
  auto scalar = [n](std::string name, auto get) {
    io::ArraySource a;
    a.name = std::move(name);
    a.type = io::ScalarType::Float64;
    a.tuples = n;
    a.fill = [get](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<double*>(out);
      for (std::size_t k = 0; k < count; ++k) o[k] = get(first + k);
    };
    return a;
  };
  const Solver* s = &solver;
  g.points = vec3("Points", [&m](std::size_t i) {
    return std::pair{m.x0[i] + m.ux[i], m.y0[i] + m.uy[i]};
  });
  g.point_data.push_back(io::array_view("radius", m.radius.data(), n));
  if (!m.contact_radius.empty()) g.point_data.push_back(io::array_view("contact_radius", m.contact_radius.data(), n));
  g.point_data.push_back(io::array_view("kind", m.kind.data(), n));
  g.point_data.push_back(io::array_view("body", m.body.data(), n));
  {
    io::ArraySource a;  // the body's material (Model::disk_material)
    a.name = "material";
    a.type = io::ScalarType::Int32;
    a.tuples = n;
    a.fill = [&m](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<std::int32_t*>(out);
      for (std::size_t k = 0; k < count; ++k) o[k] = m.disk_material(first + k);
    };
    g.point_data.push_back(std::move(a));
  }
  g.point_data.push_back(io::array_view("mass", m.mass.data(), n));
  g.point_data.push_back(io::array_view("cell_area", m.cell_area.data(), n));
  if (m.geometry == Geometry::Axisymmetric) g.point_data.push_back(io::array_view("ring_radius", m.weight.data(), n));
  g.point_data.push_back(vec3("displacement", [&m](std::size_t i) { return std::pair{m.ux[i], m.uy[i]}; }));
  g.point_data.push_back(vec3("velocity", [s](std::size_t i) { return std::pair{s->vx_mid(i), s->vy_mid(i)}; }));
  g.point_data.push_back(io::array_view("rotation", m.theta.data(), n));
  g.point_data.push_back(scalar("spin", [s](std::size_t i) { return s->spin_mid(i); }));
  {
    io::ArraySource a;
    a.name = "stress";
    a.type = io::ScalarType::Float64;
    a.components = 9;
    a.tuples = n;
    a.fill = [&m](std::size_t first, std::size_t count, void* out) {
      auto* o = static_cast<double*>(out);
      for (std::size_t k = 0; k < count; ++k) {
        const Stress st = disk_stress(m, first + k);
        double* t = o + 9 * k;
        t[0] = st.xx; t[1] = st.xy; t[2] = 0;
        t[3] = st.xy; t[4] = st.yy; t[5] = 0;
        t[6] = 0;     t[7] = 0;     t[8] = st.zz;
      }
    };
    g.point_data.push_back(std::move(a));
  }
  g.point_data.push_back(scalar("damage", [&m](std::size_t i) {
    if (m.initial_bonds(i) == 0) return 0.0;
    // Broken bonds count 1, cracking bonds of softening materials their damage D.
    double broken = 0;
    for (auto k = m.adj_offset[i]; k < m.adj_offset[i + 1]; ++k) {
      const auto b = m.adj_bond(k);
      broken += !m.bond_intact(b) ? 1.0 : m.bond_damage(b);
    }
    return broken / m.initial_bonds(i);
  }));
  // Axisymmetric softening: the damage of each ring's hoop stress (radial cracks).
  if (!m.hoop_cracks.damage.empty()) g.point_data.push_back(io::array_view("hoop_damage", m.hoop_cracks.damage.data(), n));
  // J2 disks: accumulated equivalent plastic strain, the sum of sqrt(2/3 d(eps_p):d(eps_p)).
  if (m.any_j2) g.point_data.push_back(io::array_view("plastic_strain", m.j2.eps_p_eq.data(), n));
  // Contacts of never-bonded disks that carry force: a second set of lines after the bonds
  // (state 5), so that the bonds keep their order in every frame.
  contacts.i.clear();
  contacts.j.clear();
  contacts.f_n.clear();
  contacts.f_s.clear();
  for (const Solver::Contact& c : solver.contacts()) {
    if (c.f_n == 0 && c.f_s == 0) continue;
    contacts.i.push_back(c.i);
    contacts.j.push_back(c.j);
    contacts.f_n.push_back(c.f_n);
    contacts.f_s.push_back(c.f_s);
  }
  const std::size_t nc = contacts.i.size();
  g.num_extra_lines = nc;
  g.extra_i = contacts.i.data();
  g.extra_j = contacts.j.data();
  // A cell array over bonds then contacts: bond values, then `contact(k)` for contact k.
  auto cells = [nb, nc](std::string name, io::ScalarType type, auto bond, auto contact) {
    io::ArraySource a;
    a.name = std::move(name);
    a.type = type;
    a.tuples = nb + nc;
    a.fill = [nb, type, bond, contact](std::size_t first, std::size_t count, void* out) {
      for (std::size_t k = first; k < first + count; ++k) {
        const double v = k < nb ? bond(k) : contact(k - nb);
        if (type == io::ScalarType::UInt8) {
          static_cast<std::uint8_t*>(out)[k - first] = static_cast<std::uint8_t>(v);
        } else {
          static_cast<double*>(out)[k - first] = v;
        }
      }
    };
    return a;
  };
  const ContactCells* cc = &contacts;
  g.cell_data.push_back(cells("state", io::ScalarType::UInt8, [&m](std::size_t b) { return double(m.state[b]); },
                              [](std::size_t) { return 5.0; }));
  g.cell_data.push_back(cells("normal_force", io::ScalarType::Float64, [&m](std::size_t b) { return bond_force(m, b).f_n; },
                              [cc](std::size_t k) { return cc->f_n[k]; }));
  g.cell_data.push_back(cells("shear_force", io::ScalarType::Float64, [&m](std::size_t b) { return m.f_s[b]; },
                              [cc](std::size_t k) { return cc->f_s[k]; }));
  g.cell_data.push_back(cells("break_time", io::ScalarType::Float64, [&m](std::size_t b) { return m.bond_break_time(b); },
                              [](std::size_t) { return -1.0; }));
  if (m.any_softening)
    g.cell_data.push_back(cells("bond_damage", io::ScalarType::Float64, [&m](std::size_t b) { return m.bond_damage(b); },
                                [](std::size_t) { return 1.0; }));
  g.cell_data.push_back(cells("bond_class", io::ScalarType::UInt8, [&m](std::size_t b) { return double(m.bond_class_of(b)); },
                              [](std::size_t) { return 0.0; }));
  g.field_data.push_back({"time", {solver.time()}, {}, {}});
  g.field_data.push_back({"step", {static_cast<double>(solver.step_index())}, {}, {}});
  g.field_data.push_back({"geometry", {}, geometry_name(m.geometry), {}});
  g.field_data.push_back({"thickness", {m.thickness}, {}, {}});
  if (solver.p_max() > 0) g.field_data.push_back({"p_max", {solver.p_max()}, {}, {}});
  add_bodies_and_sets(solver.lattice(), m.num_disks(), g);
  return g;
}

RunOutput::RunOutput(const Solver& solver, const std::string& dir) : dir_(dir) { open(solver, nullptr); }

RunOutput::RunOutput(const Solver& solver, const std::string& dir, const RunState& resume) : dir_(dir) {
  open(solver, &resume);
}

/// FNV-1a hash of the first `bytes` of a file (fewer if it is shorter).
static std::uint64_t prefix_hash(const std::string& path, std::uint64_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t h = fnv1a(nullptr, 0);
  std::vector<char> buf(1 << 16);
  while (bytes > 0 && in) {
    in.read(buf.data(), static_cast<std::streamsize>(std::min<std::uint64_t>(bytes, buf.size())));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    h = fnv1a(buf.data(), got, h);
    bytes -= got;
  }
  return h;
}

void RunOutput::check_for_restart(const std::string& path, std::uint64_t bytes, std::uint64_t hash) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size < bytes)
    throw InputError(path + ": " + (ec ? std::string("missing") : std::to_string(size) + " bytes") +
                     ", the checkpoint was written after " + std::to_string(bytes) +
                     " bytes of it (restart in the output folder the checkpoint was written for)");
  if (prefix_hash(path, bytes) != hash)
    throw InputError(path + ": its first " + std::to_string(bytes) +
                     " bytes are not the ones the checkpoint's run wrote (another run has written this folder since)");
}

void RunOutput::truncate_for_restart(const std::string& path, std::uint64_t bytes) {
  std::error_code ec;
  fs::resize_file(path, bytes, ec);
  if (ec) throw std::runtime_error(path + ": cannot truncate for the restart (" + ec.message() + ")");
}

void RunOutput::save_state(RunState& state) {
  list_frames(true);  // the .pvd lists what the checkpoint does
  state.frames = pvd_;
  state.last_frame = last_frame_;
  // The size on disk after a flush (tellp() of a stream opened to append is not the size).
  auto bytes = [](CsvFile& f, const std::string& path) -> std::uint64_t {
    if (!f.is_open()) return 0;
    f.flush();
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) throw InputError(path + ": cannot write before the checkpoint (" + ec.message() + ")");
    return static_cast<std::uint64_t>(size);
  };
  state.energy_bytes = bytes(energy_, energy_path_);
  state.probes_bytes = bytes(probes_, probes_path_);
  state.bodies_bytes = bytes(bodies_, bodies_path_);
  state.energy_hash = prefix_hash(energy_path_, state.energy_bytes);
  state.probes_hash = prefix_hash(probes_path_, state.probes_bytes);
  state.bodies_hash = prefix_hash(bodies_path_, state.bodies_bytes);
  state.reactions_bytes = bytes(reactions_, reactions_path_);
  state.reactions_hash = prefix_hash(reactions_path_, state.reactions_bytes);
}

void RunOutput::open(const Solver& solver, const RunState* resume) {
  const Case& c = solver.case_data();
  const Model& m = solver.model();
  name_ = c.name;
  compression_level_ = c.output.compression_level;
  frame_dir_ = (fs::path(dir_) / name_).string();
  pvd_path_ = (fs::path(dir_) / (name_ + ".pvd")).string();
  energy_path_ = (fs::path(dir_) / (name_ + ".energy.csv")).string();
  probes_path_ = (fs::path(dir_) / (name_ + ".probes.csv")).string();
  bodies_path_ = (fs::path(dir_) / (name_ + ".bodies.csv")).string();
  reactions_path_ = (fs::path(dir_) / (name_ + ".reactions.csv")).string();
  status_path_ = (fs::path(dir_) / (name_ + ".status")).string();

  // First every check that can refuse the run; the folder is not touched until all pass, so
  // that a refused run (or restart) leaves a finished folder as it was.
  std::ostringstream probes_header;
  probes_header << "time,step";
  for (const Probe& p : c.probes) {
    const std::size_t best = probe_disk(m, p);  // refused at set-up if it selects none
    std::vector<std::string> fields = p.fields;
    if (fields.empty()) fields = {"displacement", "velocity", "stress", "rotation", "spin"};
    for (const std::string& f : fields) {
      if (f == "displacement" || f == "velocity") {
        probes_header << "," << p.name << "." << f << "_x," << p.name << "." << f << "_y";
      } else if (f == "stress") {
        probes_header << "," << p.name << ".stress_xx," << p.name << ".stress_yy," << p.name << ".stress_xy,"
                      << p.name << ".stress_zz";
      } else {
        probes_header << "," << p.name << "." << f;
      }
    }
    probe_points_.push_back({best, fields});
  }
  probes_header << "\n";

  std::ostringstream bodies_header;
  bodies_header << "time,step";
  {
    // Body index = position in the outline (the lattice's `body` numbers).
    std::vector<std::string> names;
    for (const meshing::BodyOutline& b : c.outline.bodies) names.push_back(b.name);
    body_slot_.assign(names.size(), -1);
    for (const std::string& b : c.output.body_history) {
      // An unknown body or one without disks was refused at set-up (Solver::check_probes).
      const auto at = std::find(names.begin(), names.end(), b);
      HEXDEM_VERIFY(at != names.end(), "body_history body '" + b + "' passed the set-up's check");
      body_slot_[static_cast<std::size_t>(at - names.begin())] = static_cast<int>(body_sums_.size());
      body_sums_.push_back({});
      for (const char* col : {"mass", "x", "y", "vx", "vy", "px", "py", "kinetic"}) bodies_header << "," << b << "." << col;
    }
    bodies_header << "\n";
  }

  // The frames the checkpoint lists (the frames to keep): `<case>/<case>_<step>.vtu` in this
  // folder, as read_checkpoint has checked.
  std::vector<std::string> keep;
  if (resume != nullptr) {
    for (const io::PvdEntry& e : resume->frames) {
      const fs::path rel(e.file);
      const std::string file = rel.filename().string();
      if (!fs::exists(fs::path(dir_) / rel))
        throw InputError((fs::path(dir_) / rel).string() +
                         ": missing, the checkpoint lists it (restart in the output folder the checkpoint was "
                         "written for)");
      keep.push_back(file);
    }
    check_for_restart(energy_path_, resume->energy_bytes, resume->energy_hash);
    if (!c.probes.empty()) check_for_restart(probes_path_, resume->probes_bytes, resume->probes_hash);
    if (!c.output.body_history.empty()) check_for_restart(bodies_path_, resume->bodies_bytes, resume->bodies_hash);
    if (!c.output.reactions.empty())
      check_for_restart(reactions_path_, resume->reactions_bytes, resume->reactions_hash);
  }

  // Every check passed: prepare the folder. The status says "running" before anything of
  // a finished series goes (a status that cannot be written stops the run here).
  make_folder(dir_);
  if (c.output.frames) make_folder(frame_dir_);  // no empty frame folder without frames
  write_status("running");
  std::error_code ec;
  // Old frames of this case would be listed by nobody but could confuse a reader: remove them
  // (on a restart, those after the checkpoint). Only the names hexdem gives its frames,
  // <case>_<step, 9 or more digits>.vtu: other files in the folder are the user's.
  const auto is_frame = [this](const std::string& f) {
    const std::string head = name_ + "_", tail = ".vtu";
    if (f.size() < head.size() + 9 + tail.size() || f.compare(0, head.size(), head) != 0 ||
        f.compare(f.size() - tail.size(), tail.size(), tail) != 0)
      return false;
    return std::all_of(f.begin() + static_cast<std::ptrdiff_t>(head.size()), f.end() - static_cast<std::ptrdiff_t>(tail.size()),
                       [](char ch) { return ch >= '0' && ch <= '9'; });
  };
  if (fs::is_directory(frame_dir_, ec)) {  // none: a first run without frames
    for (fs::directory_iterator it(frame_dir_, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string f = it->path().filename().string();
      std::error_code rm;
      if (is_frame(f) && std::find(keep.begin(), keep.end(), f) == keep.end()) fs::remove(it->path(), rm);
    }
    if (ec) throw InputError(frame_dir_ + ": cannot list the folder (" + ec.message() + ")");
  }
  // The CSVs of a restart continue from the checkpoint; those of a new run start afresh.
  if (resume != nullptr) {
    truncate_for_restart(energy_path_, resume->energy_bytes);
    if (!c.probes.empty()) truncate_for_restart(probes_path_, resume->probes_bytes);
    if (!c.output.body_history.empty()) truncate_for_restart(bodies_path_, resume->bodies_bytes);
    if (!c.output.reactions.empty()) truncate_for_restart(reactions_path_, resume->reactions_bytes);
    pvd_ = resume->frames;
    // The last frame in this folder (the checkpoint's own path names the folder it was
    // written in, which may since have been copied or moved).
    last_frame_ = pvd_.empty() ? std::string() : (fs::path(dir_) / pvd_.back().file).string();
    io::write_pvd(pvd_path_, pvd_);
    pvd_listed_ = pvd_.size();
    pvd_written_ = std::chrono::steady_clock::now();
  } else {
    fs::remove(pvd_path_, ec);
  }

  energy_.open(energy_path_, resume != nullptr);
  if (resume == nullptr)
    energy_ << "time,step,kinetic,elastic,external_work,damping,plastic,fracture,contact_damping,friction,break_kinetic,"
               "input,total,relative_error\n";

  if (resume == nullptr) fs::remove(probes_path_, ec);
  if (!c.probes.empty()) {
    probes_.open(probes_path_, resume != nullptr);
    if (resume == nullptr) probes_ << probes_header.str();
  }

  if (resume == nullptr) fs::remove(bodies_path_, ec);
  if (!c.output.body_history.empty()) {
    bodies_.open(bodies_path_, resume != nullptr);
    if (resume == nullptr) bodies_ << bodies_header.str();
  }

  if (resume == nullptr) fs::remove(reactions_path_, ec);
  if (!c.output.reactions.empty()) {
    // The sets were resolved by the Solver (Solver::setup_reactions), in the order of the list.
    reactions_.open(reactions_path_, resume != nullptr);
    std::string header = "time";
    for (const std::string& set : c.output.reactions) header += "," + set + ".fx," + set + ".fy";
    header += "\n";
    if (resume == nullptr) reactions_ << header;
  }
}

void RunOutput::flush_csvs() {
  for (CsvFile* f : {&energy_, &probes_, &bodies_, &reactions_})
    if (f->is_open()) f->flush();
}

void RunOutput::finish() {
  list_frames(true);
  for (CsvFile* f : {&energy_, &probes_, &bodies_, &reactions_}) f->close();
}

void RunOutput::list_frames(bool all) {
  const std::size_t unlisted = pvd_.size() - pvd_listed_;
  const auto now = std::chrono::steady_clock::now();
  if (unlisted == 0) return;  // the .pvd on disk (or its absence: no frame yet) is up to date
  if (!all && unlisted < std::max<std::size_t>(1, pvd_listed_ / 16) && now - pvd_written_ < std::chrono::seconds(2))
    return;
  io::write_pvd(pvd_path_, pvd_);
  pvd_listed_ = pvd_.size();
  pvd_written_ = now;
}

void RunOutput::write_frame(const Solver& solver) {
  flush_csvs();
  io::LineGrid g = frame_grid(solver, contact_cells_);
  const std::string file = frame_name(name_, solver.step_index());
  const std::string path = (fs::path(frame_dir_) / file).string();
  io::WriteOptions wo;
  wo.compression_level = compression_level_;
  io::write_vtu(path, g, wo);
  pvd_.push_back({solver.time(), name_ + "/" + file});
  last_frame_ = path;
  list_frames(false);
}

void RunOutput::write_energy(const Solver& solver) {
  const EnergyBalance& e = solver.energy();
  csv_number(energy_, solver.time());
  energy_ << "," << solver.step_index();
  for (double v : {e.kinetic, e.elastic, e.external_work, e.damping, e.plastic, e.fracture, e.contact_damping,
                   e.friction, e.break_kinetic, e.input(), e.total(), e.relative_error()}) {
    energy_ << ",";
    csv_number(energy_, v);
  }
  energy_ << "\n";
  flush_csvs();
}

void RunOutput::write_reactions(const Solver& solver) {
  if (!reactions_.is_open()) return;
  csv_number(reactions_, solver.time());
  for (std::size_t k = 0; k < solver.num_reaction_sets(); ++k) {
    const std::array<double, 2> r = solver.reaction(k);
    reactions_ << ",";
    csv_number(reactions_, r[0]);
    reactions_ << ",";
    csv_number(reactions_, r[1]);
  }
  reactions_ << "\n";
}

void RunOutput::write_probes(const Solver& solver) {
  if (probe_points_.empty()) return;
  const Model& m = solver.model();
  csv_number(probes_, solver.time());
  probes_ << "," << solver.step_index();
  for (const ProbePoint& p : probe_points_) {
    const std::size_t i = p.disk;
    for (const std::string& f : p.fields) {
      std::array<double, 4> v{};
      std::size_t count = 1;
      if (f == "displacement") {
        v = {m.ux[i], m.uy[i]};
        count = 2;
      } else if (f == "velocity") {
        v = {solver.vx_mid(i), solver.vy_mid(i)};
        count = 2;
      } else if (f == "stress") {
        const Stress s = disk_stress(m, i);
        v = {s.xx, s.yy, s.xy, s.zz};
        count = 4;
      } else if (f == "rotation") {
        v[0] = m.theta[i];
      } else {
        v[0] = solver.spin_mid(i);
      }
      for (std::size_t k = 0; k < count; ++k) {
        probes_ << ",";
        csv_number(probes_, v[k]);
      }
    }
  }
  probes_ << "\n";
}

void RunOutput::write_bodies(const Solver& solver) {
  if (body_sums_.empty()) return;
  const Model& m = solver.model();
  for (auto& sums : body_sums_) sums.fill(0.0);
  // Serial, in disk order: the sums do not depend on the number of threads.
  for (std::size_t i = 0; i < m.num_disks(); ++i) {
    const int slot = body_slot_[static_cast<std::size_t>(m.body[i])];
    if (slot < 0) continue;
    auto& s = body_sums_[static_cast<std::size_t>(slot)];
    const double mass = m.mass[i];
    const double vx = solver.vx_mid(i), vy = solver.vy_mid(i);
    s[0] += mass;
    s[1] += mass * (m.x0[i] + m.ux[i]);
    s[2] += mass * (m.y0[i] + m.uy[i]);
    s[3] += mass * vx;
    s[4] += mass * vy;
    s[5] += 0.5 * (mass * (m.vx_old[i] * m.vx[i] + m.vy_old[i] * m.vy[i]) +
                   m.disk_inertia(i) * m.omega_old[i] * m.omega[i]);
  }
  csv_number(bodies_, solver.time());
  bodies_ << "," << solver.step_index();
  for (const auto& s : body_sums_) {
    const double inv = s[0] > 0 ? 1.0 / s[0] : 0.0;
    for (double v : {s[0], s[1] * inv, s[2] * inv, s[3] * inv, s[4] * inv, s[3], s[4], s[5]}) {
      bodies_ << ",";
      csv_number(bodies_, v);
    }
  }
  bodies_ << "\n";
}

void RunOutput::write_status(const std::string& line) {
  const std::string tmp = status_path_ + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    f << line << "\n";
    f.flush();
    if (!f) {
      const std::string reason = errno_reason();
      std::error_code rm;
      fs::remove(tmp, rm);  // no stray temporary file
      throw InputError(tmp + ": cannot write (" + reason + ")");
    }
  }
  std::error_code ec;
  fs::rename(tmp, status_path_, ec);
  if (ec) {
    std::error_code rm;
    fs::remove(tmp, rm);
    throw InputError(status_path_ + ": cannot write (" + ec.message() + ")");
  }
}

namespace {

/// SIGINT or SIGTERM during a run: the loop stops after the step, lists its frames, records
/// `interrupted` in the status and exits 128 + the signal; a second signal ends the program
/// at once (the default action).
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void stop_run(int sig) {
  if (g_stop_signal != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_stop_signal = sig;
}

/// Installs stop_run for the run's loop and restores the previous handlers after it.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    int_ = std::signal(SIGINT, stop_run);
    term_ = std::signal(SIGTERM, stop_run);
  }
  ~StopSignals() {
    std::signal(SIGINT, int_ == SIG_ERR ? SIG_DFL : int_);
    std::signal(SIGTERM, term_ == SIG_ERR ? SIG_DFL : term_);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*int_)(int) = SIG_DFL;
  void (*term_)(int) = SIG_DFL;
};

}  // namespace

int run_case(const Case& c, const RunOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (options.threads > 0) omp_set_num_threads(options.threads);
  meshing::GeneratorReport mesh_report;
  meshing::Lattice lattice = mesh_case(c, &mesh_report);
  const std::size_t num_disks = lattice.num_disks(), num_bonds = lattice.num_bonds();
  const auto wall_mesh = std::chrono::steady_clock::now();
  Solver solver(c, std::move(lattice));
  const auto wall_setup = std::chrono::steady_clock::now();
  double output_seconds = 0;
  const TimeStepInfo& ts = solver.time_step();
  // A restart continues in the checkpoint's folder unless told otherwise.
  std::string dir = options.out_dir.empty() ? c.name + "-output" : options.out_dir;
  if (options.out_dir.empty() && !options.restart.empty()) {
    dir = fs::path(options.restart).parent_path().string();
    if (dir.empty()) dir = ".";
  }
  // Checked before Solver::total_steps converts it to an integer (a case file's dt is
  // checked by the reader; this catches a computed one).
  if (const double n = c.time.end / solver.dt(); !(n <= kMaxSteps)) {
    char text[200];
    std::snprintf(text, sizeof text, "[time] end = %.6g s at dt = %.6g s needs %.6g steps, more than %.6g",
                  c.time.end, solver.dt(), n, kMaxSteps);
    throw InputError(c.source + ": " + text + "; lower end or raise dt");
  }
  RunState run;
  const bool restart = !options.restart.empty();
  if (restart) read_checkpoint(options.restart, solver, run);
  RunOutput out = restart ? RunOutput(solver, dir, run) : RunOutput(solver, dir);
  // The case as run, runnable alone: `hexdem run DIR/<case>.case.toml` repeats this run.
  if (!c.effective_toml.empty())
    io::write_file_atomic((fs::path(dir) / (c.name + ".case.toml")).string(), c.effective_toml);
  const std::string checkpoint_path = (fs::path(dir) / (c.name + ".chk")).string();
  const std::string summary_path = (fs::path(dir) / (c.name + ".summary.csv")).string();
  {
    std::error_code ec;
    fs::remove(summary_path, ec);  // written again only if this run completes
  }

  const std::int64_t steps = solver.total_steps();
  const double dt = solver.dt();
  const double frame_dt = c.output.interval;
  const double probe_dt = c.output.probe_interval;
  const double checkpoint_dt = c.output.checkpoint_interval;
  double next_frame = 0.0, next_probe = 0.0, next_checkpoint = checkpoint_dt;
  double max_error = 0;
  if (restart) {
    next_frame = run.next_frame;
    next_probe = run.next_probe;
    next_checkpoint = run.next_checkpoint;
    max_error = run.max_error;
  }
  const std::int64_t first_step = solver.step_index();
  const auto report_interval = std::chrono::milliseconds(500);
  auto last_report = wall0;
  if (!options.quiet) {
    std::printf("hexdem run: %s (%s, %s shear model)\n", c.source.c_str(), geometry_name(c.geometry),
                shear_model_name(c.shear_model));
    std::printf("  disks %zu, bonds %zu, bodies %zu%s\n", num_disks, num_bonds, solver.lattice().body_names.size(),
                c.disk_order == meshing::DiskOrder::Hilbert ? " (numbered along a Hilbert curve: [mesh] order)" : "");
    std::printf("  time step %.6g s (%s; critical %.6g s: Bloch %.6g s, finite model %.6g s; Eq. 24 %.6g s)\n",
                dt, ts.user_dt ? "given" : "safety x critical", ts.dt_critical, ts.dt_bloch, ts.dt_finite,
                ts.dt_eq24);
    if (ts.stiffness_max > 1)
      std::printf("  random stiffness: largest factor %.6g, the critical step is the uniform model's / %.6g\n",
                  ts.stiffness_max, std::sqrt(ts.stiffness_max));
    std::printf("  %lld steps to t = %.6g s, threads %d\n", static_cast<long long>(steps), c.time.end,
                omp_get_max_threads());
    // A step other than the default: the contacts keep the default step's stiffness cap.
    if ((solver.contacts_enabled() || !c.walls.empty()) && std::abs(dt / ts.dt_contact - 1.0) > 1e-3)
      std::printf("  contacts as at the default step: omega <= [contact] resolution / %.6g s (omega dt <= %.3g)\n",
                  ts.dt_contact, c.contact.resolution * dt / ts.dt_contact);
    for (const std::string& line : solver.plasticity_report()) std::printf("  %s\n", line.c_str());
    if (restart)
      std::printf("  restart from %s at step %lld (t = %.6g s)\n", options.restart.c_str(),
                  static_cast<long long>(first_step), solver.time());
    std::fflush(stdout);
  }

  for (const std::string& w : solver.warnings()) std::fprintf(stderr, "hexdem: warning: %s\n", w.c_str());
  bool ok = true;
  bool frame = false, probe = false, energy_row = false, warned = false;
  // Built once: a std::function made per step would allocate per step.
  // The CSV rows of t_n first: write_frame flushes them before the .pvd lists the frame.
  const std::function<void(const Solver&)> at_tn = [&](const Solver& s) {
    const auto t0 = std::chrono::steady_clock::now();
    if (probe) {
      out.write_probes(s);
      out.write_bodies(s);
      out.write_reactions(s);
    }
    if (energy_row) {
      out.write_energy(s);
      max_error = std::max(max_error, std::abs(s.energy().relative_error()));
    }
    if (frame) out.write_frame(s);
    output_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const StopSignals stop_signals;
  int stopped_by = 0;
  try {
    for (std::int64_t n = first_step; n <= steps; ++n) {
      const double t = static_cast<double>(n) * dt;
      const bool last = n == steps;
      frame = c.output.frames && (n == 0 || last || (frame_dt > 0 && t >= next_frame - 0.5 * dt));
      probe = (!c.probes.empty() || !c.output.body_history.empty() || !c.output.reactions.empty()) &&
              (n == 0 || last || t >= next_probe - 0.5 * dt);
      energy_row = frame || last || n == 0 || (frame_dt > 0 && t >= next_frame - 0.5 * dt);
      const bool check = energy_row || n % 50 == 0;
      ok = solver.advance(check, at_tn);
      if (!warned && !solver.energy_warning().empty()) {
        warned = true;
        std::fprintf(stderr, "%shexdem: warning: %s\n", options.progress ? "\n" : "", solver.energy_warning().c_str());
      }
      if (!ok) break;
      if (frame_dt > 0) next_frame = next_output_time(next_frame, frame_dt, t + 0.5 * dt);
      if (probe) next_probe = next_output_time(next_probe, probe_dt > 0 ? probe_dt : dt, t + 0.5 * dt);
      // A checkpoint holds the state after step n (at t_{n+1}), with this step's output done.
      if (checkpoint_dt > 0 && !last && t >= next_checkpoint - 0.5 * dt) {
        next_checkpoint = next_output_time(next_checkpoint, checkpoint_dt, t + 0.5 * dt);
        const auto t0 = std::chrono::steady_clock::now();
        run.next_frame = next_frame;
        run.next_probe = next_probe;
        run.next_checkpoint = next_checkpoint;
        run.max_error = max_error;
        out.save_state(run);
        write_checkpoint(checkpoint_path, solver, run);
        output_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      if (options.progress) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_report >= report_interval || last) {
          last_report = now;
          const double wall = std::chrono::duration<double>(now - wall0).count();
          const double done = static_cast<double>(n - first_step);
          const double eta = done > 0 ? wall / done * static_cast<double>(steps - n) : 0.0;
          std::fprintf(stderr, "\r  step %lld/%lld  t = %.4e s  wall %.1f s  ETA %.1f s   ",
                       static_cast<long long>(n), static_cast<long long>(steps), t, wall, eta);
          if (last) std::fprintf(stderr, "\n");
        }
      }
      if (g_stop_signal != 0 && !last) {
        stopped_by = g_stop_signal;
        break;
      }
    }
  } catch (const InputError& e) {
    // An output that could not be written mid-run: the status says so where it still can
    // (it said "running"), and the error goes on (exit 2, one line).
    try {
      out.finish();
    } catch (const std::exception&) {  // the same full disk: the status below may still fit
    }
    try {
      out.write_status(std::string("failed: ") + e.what());
    } catch (const std::exception&) {
    }
    throw;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (stopped_by != 0) {
    // Stopped by SIGINT or SIGTERM: the series is whole up to its last frame, and says so.
    if (options.progress) std::fprintf(stderr, "\n");
    out.finish();
    const char* name = stopped_by == SIGINT ? "SIGINT" : "SIGTERM";
    std::fprintf(stderr, "hexdem: interrupted by %s at step %lld (t = %.6g s); last frame: %s\n", name,
                 static_cast<long long>(solver.step_index()), solver.time(),
                 out.last_frame().empty() ? "none" : out.last_frame().c_str());
    out.write_status(std::string("interrupted at t = ") + meshing::format_number(solver.time()) + " s (" + name + ")");
    return 128 + stopped_by;
  }
  if (!ok) {
    if (options.progress) std::fprintf(stderr, "\n");
    const BlowUp& b = solver.blow_up();
    // Every frame written passed the checks of its step (Solver::advance checks before it
    // hands the state out), so the last one is good.
    out.finish();
    std::fprintf(stderr,
                 "hexdem: error: %s at step %lld (t = %.6g s): %s; dt = %.6g s, critical %.6g s; "
                 "last good frame: %s\n",
                 b.kind == BlowUp::Kind::EnergyLimit ? "energy balance failure" : "numerical blow-up",
                 static_cast<long long>(b.step), b.time, b.reason.c_str(), dt, ts.dt_critical,
                 out.last_frame().empty() ? "none" : out.last_frame().c_str());
    out.write_status(std::string("failed: ") +
                     (b.kind == BlowUp::Kind::EnergyLimit ? "energy balance failure" : "numerical blow-up") +
                     " at t = " + meshing::format_number(b.time) + " s: " + b.reason);
    return kExitRunFailed;
  }
  out.finish();
  write_run_summary(summary_path, run_summary(solver));
  // A warning (the energy balance passed [time] energy_warning, perhaps before a restart) is
  // carried by the status and the exit code: the series is complete, its numbers may be wrong.
  const std::string& warning = solver.energy_warning();
  out.write_status(warning.empty() ? std::string("completed") : "completed with warning: " + warning);
  if (!options.quiet) {
    const auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    std::printf("  done: %zu frames, max |energy error| %.3g\n", out.frames(), std::max(max_error, solver.max_energy_error()));
    if (!warning.empty()) std::printf("  warning: %s (exit code 3)\n", warning.c_str());
    const double step_seconds = wall - secs(wall0, wall_setup) - output_seconds;
    std::printf("  wall %.2f s: mesh %.2f s, set-up %.2f s, steps %.2f s, output %.2f s\n", wall,
                secs(wall0, wall_mesh), secs(wall_mesh, wall_setup), step_seconds, output_seconds);
    if (solver.contacts_enabled()) {
      std::printf("  contacts: %zu bonds broken, broad phase %.2f s (%.1f %% of the steps)\n", solver.broken_bonds(),
                  solver.detection_seconds(), 100.0 * solver.detection_seconds() / step_seconds);
    }
    std::printf("  series: %s\n  energy: %s\n", out.pvd_path().c_str(), out.energy_path().c_str());
    if (checkpoint_dt > 0 && fs::exists(checkpoint_path)) std::printf("  checkpoint: %s\n", checkpoint_path.c_str());
    if (!c.probes.empty()) std::printf("  probes: %s\n", out.probes_path().c_str());
    if (!c.output.body_history.empty()) std::printf("  bodies: %s\n", out.bodies_path().c_str());
    if (!c.output.reactions.empty()) std::printf("  reactions: %s\n", out.reactions_path().c_str());
  }
  return warning.empty() ? kExitOk : kExitWarning;
}

}  // namespace hexdem::solver
