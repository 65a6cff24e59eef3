/// \file outline_toml.cpp
/// Reads outlines from TOML (format: docs/outline-format.md).

#include "hexdem/meshing/outline_toml.hpp"
#include "hexdem/meshing/outline_toml_table.hpp"
#include "hexdem/meshing/toml_values.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/text.hpp"

namespace hexdem::meshing {
namespace {

/// Relative tolerance for "the same point" in a path's closure and an arc's radii.
constexpr double kRelativeTolerance = 1e-9;

std::string format_point(Vec2 p) {
  std::string text = "(";
  text.append(format_number(p.x)).append(", ").append(format_number(p.y)).append(")");
  return text;
}

/// Metres per unit for the `units` key, or 0 when the unit is unknown.
double unit_factor(std::string_view unit) {
  constexpr std::array<std::pair<std::string_view, double>, 6> units{{
      {"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"in", 0.0254}, {"ft", 0.3048}}};
  for (const auto& [name, factor] : units) {
    if (name == unit) return factor;
  }
  return 0.0;
}

Vec2 scaled(Vec2 p, double factor) { return {p.x * factor, p.y * factor}; }

/// One reading of one file. Geometry is built in file units and scaled to metres at the end
/// of each shape, so that messages quote the numbers as written.
class Reader : public TomlValues {
public:
  Reader(std::string source, const ReadOptions& options)
      : TomlValues(std::move(source)), options_(options) {}

  Outline read(const toml::table& root);

private:
  /// Lattice settings of the [lattice] table [m, deg].
  struct Defaults {
    std::optional<double> radius;
    std::optional<double> angle_deg;
    std::optional<Vec2> origin;
  };

  void check_keys(const toml::table& table, const std::string& path,
                  std::initializer_list<std::string_view> allowed) const;
  const toml::node& required(const toml::table& table, std::string_view key,
                             const std::string& path) const;
  Vec2 point(const toml::node& node, const std::string& path) const;
  const toml::array& table_array(const toml::node& node, const std::string& path,
                                 std::string_view what) const;
  std::int32_t boundary(const toml::node& node, const std::string& path);

  Defaults read_lattice(const toml::table& lattice) const;
  void read_body(const toml::table& table, std::size_t index, const Defaults& defaults);
  Loop read_shape(const toml::table& shape, const std::string& path, const std::string& type,
                  double chord_error);
  Loop read_rectangle(const toml::table& shape, const std::string& path);
  Loop read_polygon(const toml::table& shape, const std::string& path);
  Loop read_circle(const toml::table& shape, const std::string& path, double chord_error);
  Loop read_path(const toml::table& shape, const std::string& path, double chord_error);

  const ReadOptions& options_;
  double factor_ = 1.0;  ///< metres per file unit
  Outline outline_;
};

void Reader::check_keys(const toml::table& table, const std::string& path,
                        std::initializer_list<std::string_view> allowed) const {
  for (const auto& [key, node] : table) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    std::string list;
    for (std::string_view name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
    fail(key.source(), path, "unknown key '" + escape_text(key.str()) + "' (allowed: " + list + ")");
  }
}

const toml::node& Reader::required(const toml::table& table, std::string_view key,
                                   const std::string& path) const {
  const toml::node* node = table.get(key);
  if (node == nullptr) fail(table, path, "missing key '" + std::string(key) + "'");
  return *node;
}

Vec2 Reader::point(const toml::node& node, const std::string& path) const {
  const toml::array* array = node.as_array();
  if (array == nullptr || array->size() != 2)
    fail(node, path, "expected a point [x, y] (got " + describe(node) + ")");
  return {number(*array->get(0), path + "[0]"), number(*array->get(1), path + "[1]")};
}

const toml::array& Reader::table_array(const toml::node& node, const std::string& path,
                                       std::string_view what) const {
  const toml::array* array = node.as_array();
  if (array == nullptr || !array->is_array_of_tables())
    fail(node, path, "expected " + std::string(what) + " (got " + describe(node) + ")");
  return *array;
}

/// A boundary name: "" is no set (-1).
std::int32_t Reader::boundary(const toml::node& node, const std::string& path) {
  const std::string set = name(node, path);
  if (has_csv_special(set))
    fail(node, path, "a boundary set name must not hold a comma or a double quote (it names CSV columns) (got " +
                         describe(node) + ")");
  return set.empty() ? -1 : outline_.boundary_index(set);
}

Outline Reader::read(const toml::table& root) {
  check_keys(root, "", {"units", "lattice", "body"});
  if (const toml::node* units = root.get("units")) {
    const std::string unit = text(*units, "units");
    factor_ = unit_factor(unit);
    if (factor_ == 0.0)
      fail(*units, "units",
           "unknown unit \"" + escape_text(unit) + "\" (expected \"m\", \"cm\", \"mm\", \"um\", \"in\" or \"ft\")");
  }
  if (options_.scale > 0.0) factor_ = options_.scale;
  if (!(options_.chord_fraction > 0.0 && std::isfinite(options_.chord_fraction)))
    throw InputError(source_ + ": chord fraction must be > 0 (got " +
                     format_number(options_.chord_fraction) + ")");
  if (options_.radius && !(*options_.radius > 0.0 && std::isfinite(*options_.radius)))
    throw InputError(source_ + ": disk radius from the command line must be > 0 (got " +
                     format_number(*options_.radius) + ")");

  Defaults defaults;
  if (const toml::node* lattice = root.get("lattice")) {
    const toml::table* table = lattice->as_table();
    if (table == nullptr) fail(*lattice, "lattice", "expected a table (got " + describe(*lattice) + ")");
    defaults = read_lattice(*table);
  }

  const toml::node* bodies = root.get("body");
  if (bodies == nullptr || (bodies->is_array() && bodies->as_array()->empty()))
    throw InputError(source_ + ": no [[body]] in outline");
  const toml::array& list = table_array(*bodies, "body", "[[body]] tables");
  for (std::size_t i = 0; i < list.size(); ++i) read_body(*list.get(i)->as_table(), i, defaults);

  outline_.source = source_;
  check_lattice_size(outline_, reader_size_limit(options_.max_disks, options_.max_disks_hint));
  validate_and_orient(outline_);
  return std::move(outline_);
}

Reader::Defaults Reader::read_lattice(const toml::table& lattice) const {
  check_keys(lattice, "lattice", {"radius", "angle", "origin"});
  Defaults defaults;
  if (const toml::node* n = lattice.get("radius"))
    defaults.radius = positive(*n, "lattice.radius") * factor_;
  if (const toml::node* n = lattice.get("angle")) defaults.angle_deg = angle(*n, "lattice.angle");
  if (const toml::node* n = lattice.get("origin"))
    defaults.origin = scaled(point(*n, "lattice.origin"), factor_);
  return defaults;
}

void Reader::read_body(const toml::table& table, std::size_t index, const Defaults& defaults) {
  const std::string path = "body[" + std::to_string(index) + "]";
  check_keys(table, path, {"name", "material", "radius", "radius_factor", "angle", "origin", "shape"});

  BodyOutline body;
  const toml::node& name = required(table, "name", path);
  body.name = TomlValues::name(name, path + ".name");
  if (body.name.empty()) fail(name, path + ".name", "must not be empty");
  if (has_csv_special(body.name))
    fail(name, path + ".name",
         "a body name must not hold a comma or a double quote (it names CSV columns) (got " + describe(name) + ")");
  for (const BodyOutline& other : outline_.bodies) {
    if (other.name == body.name)
      fail(name, path + ".name", "duplicate body name (got " + describe(name) + ")");
  }
  body.where = source_ + ":" + std::to_string(table.source().begin.line) + ": body '" +
               escape_text(body.name) + "'";

  if (const toml::node* n = table.get("material")) {
    const auto* id = n->as_integer();
    if (id == nullptr || id->get() < 0 || id->get() > INT_MAX)
      fail(*n, path + ".material", "expected an integer from 0 to " + std::to_string(INT_MAX) + " (got " + describe(*n) + ")");
    body.material = static_cast<int>(id->get());
  }

  // Resolution: the body's own key, then the command line, then [lattice]; radius_factor
  // scales the last two, so that a body refined against the others stays so at any --radius.
  const toml::node* own_radius = table.get("radius");
  const toml::node* radius_factor = table.get("radius_factor");
  if (own_radius != nullptr && radius_factor != nullptr)
    fail(*radius_factor, path + ".radius_factor",
         "give the body's radius or its radius_factor, not both (got radius_factor = " +
             describe(*radius_factor) + ")");
  if (own_radius != nullptr) {
    body.radius = positive(*own_radius, path + ".radius") * factor_;
  } else {
    body.radius = options_.radius ? options_.radius : defaults.radius;
  }
  if (!body.radius)
    throw InputError(source_ + ": body '" + escape_text(body.name) +
                     "': no disk radius (give --radius or [lattice] radius)");
  if (radius_factor != nullptr) {
    const double f = positive(*radius_factor, path + ".radius_factor");
    if (f < kMinRadiusFactor || f > kMaxRadiusFactor)
      fail(*radius_factor, path + ".radius_factor",
           "must be in [" + format_number(kMinRadiusFactor) + ", " + format_number(kMaxRadiusFactor) +
               "] (got " + describe(*radius_factor) + ")");
    body.radius = *body.radius * f;
  }
  if (const toml::node* n = table.get("angle")) {
    body.angle_deg = angle(*n, path + ".angle");
  } else {
    body.angle_deg = options_.angle_deg ? options_.angle_deg : defaults.angle_deg;
  }
  if (!body.angle_deg) body.angle_deg = 0.0;
  if (const toml::node* n = table.get("origin")) {
    body.origin = scaled(point(*n, path + ".origin"), factor_);
  } else {
    body.origin = options_.origin ? options_.origin : defaults.origin;
  }
  if (!body.origin) body.origin = Vec2{0.0, 0.0};

  const toml::node* shapes = table.get("shape");
  if (shapes == nullptr || (shapes->is_array() && shapes->as_array()->empty()))
    fail(table, path, "no [[body.shape]] (a body needs at least one shape)");
  const toml::array& list = table_array(*shapes, path + ".shape", "[[body.shape]] tables");
  // Arc flattening works in file units.
  const double chord_error = options_.chord_fraction * *body.radius / factor_;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const toml::table& shape = *list.get(i)->as_table();
    const std::string shape_path = path + ".shape[" + std::to_string(i) + "]";
    if (shape.get("type") == nullptr) {
      // Report a misspelt key before the missing type it may hide.
      check_keys(shape, shape_path,
                 {"type", "role", "boundary", "min", "max", "points", "center", "radius", "start",
                  "segments"});
    }
    const std::string type = text(required(shape, "type", shape_path), shape_path + ".type");
    bool hole = false;
    if (const toml::node* role = shape.get("role")) {
      const std::string value = text(*role, shape_path + ".role");
      if (value != "outer" && value != "hole")
        fail(*role, shape_path + ".role",
             "expected \"outer\" or \"hole\" (got " + describe(*role) + ")");
      hole = value == "hole";
    }
    Loop loop;
    try {
      loop = read_shape(shape, shape_path, type, chord_error);
    } catch (const InputError& e) {
      const std::string what = e.what();
      if (what.rfind(source_, 0) == 0) throw;
      fail(shape, shape_path, what);  // from flatten_arc: add the file and the shape
    }
    for (Vec2& p : loop.points) p = scaled(p, factor_);
    loop.where = source_ + ":" + std::to_string(shape.source().begin.line) + ": body '" +
                 escape_text(body.name) + "' shape[" + std::to_string(i) + "] (" + type + ")";
    (hole ? body.holes : body.outers).push_back(std::move(loop));
  }
  outline_.bodies.push_back(std::move(body));
}

Loop Reader::read_shape(const toml::table& shape, const std::string& path,
                        const std::string& type, double chord_error) {
  if (type == "rectangle") return read_rectangle(shape, path);
  if (type == "polygon") return read_polygon(shape, path);
  if (type == "circle") return read_circle(shape, path, chord_error);
  if (type == "path") return read_path(shape, path, chord_error);
  const toml::node& node = *shape.get("type");
  fail(node, path + ".type",
       "unknown shape type " + describe(node) +
           " (expected \"rectangle\", \"polygon\", \"circle\" or \"path\")");
}

Loop Reader::read_rectangle(const toml::table& shape, const std::string& path) {
  check_keys(shape, path, {"type", "role", "boundary", "min", "max"});
  const Vec2 lo = point(required(shape, "min", path), path + ".min");
  const toml::node& max = required(shape, "max", path);
  const Vec2 hi = point(max, path + ".max");
  if (!(hi.x > lo.x && hi.y > lo.y))
    fail(max, path + ".max",
         "must exceed min in x and y (got " + format_point(hi) + ", min " + format_point(lo) + ")");

  // Counter-clockwise from min: bottom, right, top, left.
  Loop loop;
  loop.points = {{lo.x, lo.y}, {hi.x, lo.y}, {hi.x, hi.y}, {lo.x, hi.y}};
  loop.edge_set.assign(4, -1);
  loop.edge_straight.assign(4, 1);
  if (const toml::node* names = shape.get("boundary")) {
    const std::string names_path = path + ".boundary";
    if (const toml::table* sides = names->as_table()) {
      constexpr std::array<std::string_view, 4> side_names{"bottom", "right", "top", "left"};
      check_keys(*sides, names_path, {"bottom", "right", "top", "left"});
      for (std::size_t k = 0; k < side_names.size(); ++k) {
        if (const toml::node* n = sides->get(side_names[k]))
          loop.edge_set[k] = boundary(*n, names_path + "." + std::string(side_names[k]));
      }
    } else if (names->is_string()) {
      loop.edge_set.assign(4, boundary(*names, names_path));
    } else {
      fail(*names, names_path,
           "expected a name or a table { bottom, right, top, left } (got " + describe(*names) + ")");
    }
  }
  return loop;
}

Loop Reader::read_polygon(const toml::table& shape, const std::string& path) {
  check_keys(shape, path, {"type", "role", "boundary", "points"});
  const toml::node& points = required(shape, "points", path);
  const toml::array* list = points.as_array();
  if (list == nullptr || list->size() < 3)
    fail(points, path + ".points",
         "expected at least 3 points [[x, y], ...] (got " + describe(points) + ")");

  Loop loop;
  for (std::size_t k = 0; k < list->size(); ++k)
    loop.points.push_back(point(*list->get(k), path + ".points[" + std::to_string(k) + "]"));
  const std::size_t n = loop.points.size();
  loop.edge_set.assign(n, -1);
  loop.edge_straight.assign(n, 1);
  if (const toml::node* names = shape.get("boundary")) {
    const std::string names_path = path + ".boundary";
    if (const toml::array* per_edge = names->as_array()) {
      if (per_edge->size() != n)
        fail(*names, names_path,
             "expected one name per edge, " + std::to_string(n) + " (got " +
                 std::to_string(per_edge->size()) + ")");
      for (std::size_t k = 0; k < n; ++k)
        loop.edge_set[k] =
            boundary(*per_edge->get(k), names_path + "[" + std::to_string(k) + "]");
    } else {
      loop.edge_set.assign(n, boundary(*names, names_path));
    }
  }
  return loop;
}

Loop Reader::read_circle(const toml::table& shape, const std::string& path, double chord_error) {
  check_keys(shape, path, {"type", "role", "boundary", "center", "radius"});
  const Vec2 c = point(required(shape, "center", path), path + ".center");
  const double r = positive(required(shape, "radius", path), path + ".radius");
  std::int32_t set = -1;
  if (const toml::node* names = shape.get("boundary")) set = boundary(*names, path + ".boundary");

  // Four quarter arcs, so that the extreme points c +- r lie exactly on the outline.
  const std::array<Vec2, 4> quarter{{{c.x + r, c.y}, {c.x, c.y + r}, {c.x - r, c.y}, {c.x, c.y - r}}};
  Loop loop;
  loop.points.push_back(quarter[0]);
  for (std::size_t k = 0; k < quarter.size(); ++k) {
    const auto arc = flatten_arc(quarter[k], quarter[(k + 1) % 4], c, true, chord_error);
    loop.points.insert(loop.points.end(), arc.begin(), arc.end());
  }
  loop.points.pop_back();  // back at quarter[0]
  loop.edge_set.assign(loop.points.size(), set);
  loop.edge_straight.assign(loop.points.size(), 0);
  return loop;
}

Loop Reader::read_path(const toml::table& shape, const std::string& path, double chord_error) {
  check_keys(shape, path, {"type", "role", "boundary", "start", "segments"});
  const Vec2 start = point(required(shape, "start", path), path + ".start");
  std::int32_t default_set = -1;
  if (const toml::node* names = shape.get("boundary"))
    default_set = boundary(*names, path + ".boundary");
  const toml::node& segments_node = required(shape, "segments", path);
  const toml::array* segments = segments_node.as_array();
  if (segments == nullptr || segments->empty())
    fail(segments_node, path + ".segments",
         "expected an array of segments { to = [x, y], ... } (got " + describe(segments_node) + ")");

  Loop loop;
  loop.points.push_back(start);
  const toml::node* last_to = nullptr;
  for (std::size_t i = 0; i < segments->size(); ++i) {
    const std::string seg_path = path + ".segments[" + std::to_string(i) + "]";
    const toml::table* segment = segments->get(i)->as_table();
    if (segment == nullptr)
      fail(*segments->get(i), seg_path,
           "expected a segment { to = [x, y], ... } (got " + describe(*segments->get(i)) + ")");
    check_keys(*segment, seg_path, {"to", "boundary", "center", "direction", "bulge"});
    const Vec2 from = loop.points.back();
    last_to = &required(*segment, "to", seg_path);
    const Vec2 to = point(*last_to, seg_path + ".to");
    std::int32_t set = default_set;
    if (const toml::node* names = segment->get("boundary"))
      set = boundary(*names, seg_path + ".boundary");

    const toml::node* center_node = segment->get("center");
    const toml::node* direction_node = segment->get("direction");
    const toml::node* bulge_node = segment->get("bulge");
    if (center_node != nullptr && bulge_node != nullptr)
      fail(*bulge_node, seg_path + ".bulge", "give either center or bulge, not both");
    if (direction_node != nullptr && center_node == nullptr)
      fail(*direction_node, seg_path + ".direction", "direction needs a center");

    std::vector<Vec2> points{to};
    std::uint8_t straight = 1;
    if (center_node != nullptr) {
      const Vec2 c = point(*center_node, seg_path + ".center");
      if (direction_node == nullptr)
        fail(*segment, seg_path, "missing key 'direction' (\"ccw\" or \"cw\") for an arc");
      const std::string direction = text(*direction_node, seg_path + ".direction");
      if (direction != "ccw" && direction != "cw")
        fail(*direction_node, seg_path + ".direction",
             "expected \"ccw\" or \"cw\" (got " + describe(*direction_node) + ")");
      const double r_from = std::hypot(from.x - c.x, from.y - c.y);
      const double r_to = std::hypot(to.x - c.x, to.y - c.y);
      if (r_from == 0.0 || (from.x == to.x && from.y == to.y))
        fail(*center_node, seg_path + ".center",
             "arc needs distinct start, end and centre (start " + format_point(from) + ", to " +
                 format_point(to) + ", center " + format_point(c) + ")");
      if (std::abs(r_from - r_to) > kRelativeTolerance * std::max(r_from, r_to))
        fail(*center_node, seg_path + ".center",
             "arc centre is not equidistant from the arc's ends (|start - center| = " +
                 format_number(r_from) + ", |to - center| = " + format_number(r_to) + ")");
      points = flatten_arc(from, to, c, direction == "ccw", chord_error);
      straight = 0;
    } else if (bulge_node != nullptr) {
      const double bulge = number(*bulge_node, seg_path + ".bulge");
      if (bulge != 0.0) {
        if (from.x == to.x && from.y == to.y)
          fail(*bulge_node, seg_path + ".bulge",
               "a bulged arc needs distinct ends (both at " + format_point(to) + ")");
        // bulge = tan(theta / 4) for the included angle theta (positive counter-clockwise).
        // The centre lies off the chord midpoint, along the chord's left normal, by
        // (chord / 2) / tan(theta / 2) = (chord / 2) (1 - bulge^2) / (2 bulge).
        const double offset = (1.0 - bulge * bulge) / (4.0 * bulge);
        const Vec2 c{0.5 * (from.x + to.x) - offset * (to.y - from.y),
                     0.5 * (from.y + to.y) + offset * (to.x - from.x)};
        if (!std::isfinite(c.x) || !std::isfinite(c.y))
          fail(*bulge_node, seg_path + ".bulge",
               "too large: the arc's centre is not a finite point (got " + describe(*bulge_node) +
                   ")");
        points = flatten_arc(from, to, c, bulge > 0.0, chord_error);
        straight = 0;
      }
    }
    for (const Vec2& p : points) {
      loop.points.push_back(p);
      loop.edge_set.push_back(set);
      loop.edge_straight.push_back(straight);
    }
  }

  // The path must come back to its start; the start then stands for the end point.
  double extent = 0.0;
  for (const Vec2& p : loop.points)
    extent = std::max({extent, std::abs(p.x - start.x), std::abs(p.y - start.y)});
  const Vec2 end = loop.points.back();
  if (std::hypot(end.x - start.x, end.y - start.y) > kRelativeTolerance * extent)
    fail(*last_to, path + ".segments[" + std::to_string(segments->size() - 1) + "].to",
         "open outline (the path ends at " + format_point(end) + " but starts at " +
             format_point(start) + ")");
  loop.points.pop_back();
  return loop;
}

}  // namespace

Outline parse_outline_toml(std::string_view text, const std::string& source_name,
                           const ReadOptions& options) {
  return Reader(source_name, options).read(parse_toml(text, source_name));
}

Outline outline_from_toml(const toml::table& root, const std::string& source,
                          const ReadOptions& options) {
  return Reader(source, options).read(root);
}

Outline read_outline_toml(const std::string& path, const ReadOptions& options) {
  return parse_outline_toml(read_text_file(path), path, options);
}

}  // namespace hexdem::meshing
