/// \file outline_dxf.cpp
/// Reads an outline from a DXF drawing (format notes: docs/outline-dxf.md).
///
/// Two passes over the file. A light pre-scan of the group-code pairs checks that the file is
/// an ASCII DXF that dxflib reads as written (complete, lines that fit its buffer, vertex counts
/// that match, numbers where numbers belong) and counts the entity types of the ENTITIES
/// section, so that every type that is skipped (including the ones dxflib does not parse at
/// all) gets one warning line. Then dxflib parses the file and a DL_CreationAdapter collects
/// LINE, ARC, CIRCLE, LWPOLYLINE and POLYLINE entities of model space as "pieces": paths of
/// straight and circular segments in drawing units. Closed pieces are loops by themselves; open
/// pieces are chained end to end into loops. Arcs are flattened, the loops are scaled to metres
/// and nested into bodies and holes.

#include "hexdem/meshing/outline_dxf.hpp"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/lattice_generator.hpp"
#include "hexdem/meshing/point_clusters.hpp"
#include "hexdem/meshing/text.hpp"
#include "hexdem/meshing/toml_values.hpp"

namespace hexdem::meshing {
namespace {

constexpr double kPi = std::numbers::pi;

/// Chaining tolerance relative to the diagonal of the drawing's bounding box [-].
constexpr double kRelativeTolerance = 1e-6;

std::string format_point(Vec2 p) {
  return "(" + format_number(p.x) + ", " + format_number(p.y) + ")";
}

/// Metres per unit for the $INSUNITS codes of the DXF reference, indexed by code
/// (0 = unitless has no factor).
constexpr std::array<double, 25> kInsunitsMetres{
    0.0,                    // 0 unitless
    0.0254,                 // 1 inch
    0.3048,                 // 2 foot
    1609.344,               // 3 mile
    1e-3,                   // 4 millimetre
    1e-2,                   // 5 centimetre
    1.0,                    // 6 metre
    1e3,                    // 7 kilometre
    2.54e-8,                // 8 microinch
    2.54e-5,                // 9 mil (thousandth of an inch)
    0.9144,                 // 10 yard
    1e-10,                  // 11 angstrom
    1e-9,                   // 12 nanometre
    1e-6,                   // 13 micron
    1e-1,                   // 14 decimetre
    1e1,                    // 15 decametre
    1e2,                    // 16 hectometre
    1e9,                    // 17 gigametre
    149597870700.0,         // 18 astronomical unit
    9460730472580800.0,     // 19 light year
    3.0856775814913673e16,  // 20 parsec
    1200.0 / 3937.0,        // 21 US survey foot
    100.0 / 3937.0,         // 22 US survey inch
    3600.0 / 3937.0,        // 23 US survey yard
    6336000.0 / 3937.0,     // 24 US survey mile
};

/// Metres per unit of a $INSUNITS code; nullopt for 0 (unitless) and undefined codes.
std::optional<double> insunits_factor(int code) {
  if (code <= 0 || code >= static_cast<int>(kInsunitsMetres.size())) return std::nullopt;
  return kInsunitsMetres[static_cast<std::size_t>(code)];
}

std::string_view trim(std::string_view s) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

/// Whether a group code carries a real number (DXF reference, "Group code value types").
bool is_real_code(int code) {
  return (code >= 10 && code <= 59) || (code >= 110 && code <= 149) ||
         (code >= 210 && code <= 239) || (code >= 460 && code <= 469) ||
         (code >= 1010 && code <= 1059);
}

/// `value` as a finite real number (dxflib also accepts a decimal comma); nullopt if it is not
/// one.
std::optional<double> finite_real(std::string_view value) {
  std::string text(value);
  std::replace(text.begin(), text.end(), ',', '.');
  const char* first = text.data();
  const char* last = first + text.size();
  if (first != last && *first == '+') ++first;
  double v = 0.0;
  const auto parsed = std::from_chars(first, last, v);
  if (parsed.ec != std::errc() || parsed.ptr != last || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// Whether `value` is written as an integer (optional sign, digits), whatever its size.
bool is_integer(std::string_view value) {
  if (!value.empty() && (value.front() == '+' || value.front() == '-')) value.remove_prefix(1);
  return !value.empty() &&
         std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// `value` (written as an integer) as a 64-bit integer; nullopt beyond that range.
std::optional<std::int64_t> to_int64(std::string_view value) {
  if (!value.empty() && value.front() == '+') value.remove_prefix(1);
  std::int64_t v = 0;
  const auto parsed = std::from_chars(value.data(), value.data() + value.size(), v);
  if (parsed.ec != std::errc() || parsed.ptr != value.data() + value.size()) return std::nullopt;
  return v;
}

/// Longest line dxflib reads whole [characters, without the newline]: it reads each line with
/// fgets into DL_DXF_MAXLINE bytes, which also hold the newline and the terminating NUL. A
/// longer line is read as two, and every pair after it is misread (the entity is lost silently).
constexpr std::size_t kMaxLineLength = DL_DXF_MAXLINE - 2;

/// Largest |bulge| of a polyline segment [-]. Bulge = tan(theta / 4): as it grows, theta tends
/// to a full turn, the arc's radius is about chord * |bulge| / 4 and its ends approach each
/// other; beyond 1 / kRelativeTolerance the gap between the ends (4 / |bulge| of the radius)
/// is below the chaining tolerance, and the segment is no longer a meaningful arc.
constexpr double kMaxBulge = 1.0 / kRelativeTolerance;

/// What the pre-scan learns about the file.
struct ScanResult {
  std::map<std::string, std::int64_t> model_counts;  ///< entities of model space, per type
  std::int64_t paper_count = 0;                      ///< entities of paper space
  std::int64_t entity_count = 0;                     ///< all entities of the ENTITIES section
  /// $INSUNITS of the header as written (an integer), if present. dxflib would read text as 0
  /// and wrap codes beyond int, so the value is taken from here.
  std::optional<std::string> insunits;
};

/// Walks the group-code/value pairs of an ASCII DXF and counts the entities of the ENTITIES
/// section by type (VERTEX, SEQEND and ATTRIB belong to the entity before them). Throws when
/// the text is not a DXF file, or has what dxflib would misread silently: a truncated file, a
/// line too long for its buffer or with a NUL character, a vertex count of an LWPOLYLINE that
/// differs from its vertices (dxflib allocates and reads as many as the count says), a bulge
/// out of range, a $INSUNITS that is not an integer.
ScanResult prescan(const std::string& path, const std::string& text) {
  const std::string not_dxf = path + ": not a DXF file or no entities";
  if (text.rfind("AutoCAD Binary DXF", 0) == 0)
    throw InputError(not_dxf + " (binary DXF is not supported; save the drawing as ASCII DXF)");

  ScanResult result;
  std::size_t pos = 0;
  std::size_t line_number = 0;
  const auto next_line = [&](std::string_view& line) {
    if (pos >= text.size()) return false;
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    line = std::string_view(text).substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    return true;
  };
  const auto at_line = [&](std::size_t line) { return path + ":" + std::to_string(line) + ": "; };

  bool seen_section = false;
  bool seen_eof = false;
  bool expect_section_name = false;
  bool in_entities = false;
  bool in_header = false;
  bool expect_insunits = false;
  std::string current_type;  // entity being read in ENTITIES, empty if none
  bool current_paper = false;
  const auto finish_entity = [&]() {
    if (current_type.empty()) return;
    ++result.entity_count;
    if (current_paper)
      ++result.paper_count;
    else
      ++result.model_counts[current_type];
    current_type.clear();
    current_paper = false;
  };

  // The record being read in any section (the value of its group code 0: an entity, VERTEX,
  // a table entry, ...), its layer, and for an LWPOLYLINE its vertex count and vertices.
  std::string record;
  std::size_t record_line = 0;
  std::optional<std::string> layer;
  std::optional<std::string> lw_count;
  std::size_t lw_count_line = 0;
  std::int64_t lw_vertices = 0;
  bool lw_closed = false;
  const auto record_name = [&]() {
    return record + (layer ? " on layer '" + escape_text(*layer) + "'" : std::string());
  };
  const auto finish_record = [&]() {
    if (record != "LWPOLYLINE") return;
    if (!lw_count)
      throw InputError(at_line(record_line) + record_name() + ": no vertex count (group code 90)");
    if (lw_vertices == 0 && lw_closed && to_int64(*lw_count) != 0)
      throw InputError(at_line(lw_count_line) + "degenerate outline: closed " + record_name() +
                       " has fewer than 3 distinct vertices (it has none; its vertex count (group "
                       "code 90) is " +
                       *lw_count + ")");
    if (to_int64(*lw_count) != lw_vertices)
      throw InputError(at_line(lw_count_line) + record_name() +
                       ": vertex count (group code 90) is " + *lw_count + ", but " +
                       std::to_string(lw_vertices) +
                       (lw_vertices == 1 ? " vertex is" : " vertices are") + " listed");
  };

  std::string_view code_line, value_line;
  while (next_line(code_line)) {
    const std::string_view code_text = trim(code_line);
    if (code_text.empty() && pos >= text.size()) break;  // trailing blank line
    int code = 0;
    const auto parsed =
        std::from_chars(code_text.data(), code_text.data() + code_text.size(), code);
    if (parsed.ec != std::errc() || parsed.ptr != code_text.data() + code_text.size())
      throw InputError(not_dxf + " (line " + std::to_string(line_number) + " is not a group code)");
    if (code_line.size() > kMaxLineLength)
      throw InputError(at_line(line_number) + "line of " + std::to_string(code_line.size()) +
                       " characters (at most " + std::to_string(kMaxLineLength) + " can be read)");
    if (!next_line(value_line)) break;
    const std::string_view value = trim(value_line);
    const auto of_record = [&]() {
      return "group code " + std::to_string(code) + " of " +
             (record.empty() ? std::string("the file") : record) + ": ";
    };
    if (value_line.size() > kMaxLineLength)
      throw InputError(at_line(line_number) + of_record() + "line of " +
                       std::to_string(value_line.size()) + " characters (at most " +
                       std::to_string(kMaxLineLength) + " can be read)");
    if (value_line.find('\0') != std::string_view::npos)
      // dxflib's C strings would end at it (a layer "r\0m" would name the set "r").
      throw InputError(at_line(line_number) + of_record() + "NUL character in the value ('" +
                       escape_text(value.substr(0, 40)) + "')");

    if (expect_insunits && code != 0 && code != 9) {
      // dxflib would read text as 0 (unitless, taken as metres) and wrap codes beyond int.
      expect_insunits = false;
      if (!is_integer(value))
        throw InputError(at_line(line_number) + "header variable $INSUNITS: not an integer (got '" +
                         escape_text(value.substr(0, 40)) + "')");
      result.insunits = std::string(value);
    }
    if (expect_section_name) {
      expect_section_name = false;
      if (code == 2) {
        in_entities = (value == "ENTITIES");
        in_header = (value == "HEADER");
      }
    }
    if (code == 0) {
      finish_record();
      record = std::string(value);
      record_line = line_number;
      layer.reset();
      lw_count.reset();
      lw_vertices = 0;
      lw_closed = false;
      expect_insunits = false;  // a variable without a value
      if (value == "ENDSEC") in_header = false;
      if (value == "SECTION") {
        seen_section = true;
        expect_section_name = true;
        continue;
      }
      if (value == "EOF") {
        seen_eof = true;
        break;
      }
      if (!in_entities) continue;
      if (value == "ENDSEC") {
        finish_entity();
        in_entities = false;
      } else if (value != "VERTEX" && value != "SEQEND" && value != "ATTRIB") {
        finish_entity();
        current_type = std::string(value);
      }
      continue;
    }
    if (code == 9 && in_header) {
      expect_insunits = (value == "$INSUNITS");
      continue;
    }
    if (code == 8) layer = std::string(value);
    if (record == "LWPOLYLINE") {
      if (code == 90) {
        if (lw_count)
          throw InputError(at_line(line_number) + record_name() +
                           ": second vertex count (group code 90)");
        if (!is_integer(value))
          throw InputError(at_line(line_number) + of_record() + "not an integer (got '" +
                           escape_text(value.substr(0, 40)) + "')");
        lw_count = std::string(value);
        lw_count_line = line_number;
      } else if (code == 10) {
        if (!lw_count)
          throw InputError(at_line(line_number) + record_name() +
                           ": vertex (group code 10) before the vertex count (group code 90)");
        ++lw_vertices;
      } else if (code == 70) {
        lw_closed = (to_int64(value).value_or(0) & 1) != 0;  // as dxflib reads it
      } else if (code == 42 && lw_vertices == 0) {
        // dxflib would write it before the start of its vertex array.
        throw InputError(at_line(line_number) + record_name() +
                         ": bulge (group code 42) before the first vertex");
      }
    }
    if (code == 67 && in_entities && !current_type.empty()) {
      current_paper = (value == "1");
    } else if (in_entities && is_real_code(code)) {
      const std::optional<double> number = finite_real(value);
      if (!number)
        // dxflib reads what is not a number as 0, which would silently move the point.
        throw InputError(at_line(line_number) + "group code " + std::to_string(code) + " of " +
                         (current_type.empty() ? std::string("an entity") : current_type) +
                         ": not a finite number (got '" + escape_text(value.substr(0, 40)) + "')");
      if (code == 42 && (record == "LWPOLYLINE" || record == "VERTEX") &&
          std::abs(*number) > kMaxBulge)
        throw InputError(at_line(line_number) + of_record() + "bulge out of range (got '" +
                         escape_text(value.substr(0, 40)) + "'; |bulge| must be at most " +
                         format_number(kMaxBulge) + ")");
    }
  }
  if (!seen_section) throw InputError(not_dxf);
  // dxflib reports an entity when the next group code 0 arrives: without the end marker the
  // last entity would be lost silently, and a file cut short loses whatever follows the cut.
  if (!seen_eof)
    throw InputError(path + ": truncated: no EOF marker (the file ends at line " +
                     std::to_string(line_number) + ")");
  finish_entity();
  if (result.entity_count == 0) throw InputError(not_dxf);
  return result;
}

/// One segment of a piece: straight, or a circular arc about `center` (drawing units).
struct Segment {
  bool arc = false;
  Vec2 center{};
  bool ccw = true;
  double sweep = 0.0;  ///< swept angle of the arc [rad], in (0, 2 pi]
};

/// A path collected from one entity, in drawing units and world coordinates. Segment k joins
/// points[k] to points[k + 1]; in a closed piece the last segment joins back to points[0].
struct Piece {
  std::vector<Vec2> points;
  std::vector<Segment> segments;
  bool closed = false;
  std::string layer;
  std::string type;  ///< entity type, for messages
};

/// Counts of entities the collector drops, per reason and type (for the warnings).
struct Dropped {
  std::map<std::string, std::int64_t> not_planar;  ///< extrusion not along +-z
  std::map<std::string, std::int64_t> mesh;        ///< polygon / polyface mesh POLYLINEs
};

/// Receives dxflib's callbacks and keeps the supported entities of model space.
///
/// dxflib reports an entity when the group code 0 of the next one arrives, and calls
/// processCodeValuePair() for every pair before that, so the record of the entity that is
/// being reported is `previous_`.
class Collector : public DL_CreationAdapter {
 public:
  std::vector<Piece> pieces;
  Dropped dropped;

  void processCodeValuePair(unsigned int code, const std::string& value) override {
    if (code == 0) {
      previous_ = current_;
      current_ = Record{};
      current_.type = std::string(trim(value));
    } else if (code == 67) {
      current_.paper = (trim(value) == "1");
    } else if (code == 70) {
      int flags = 0;
      const std::string_view v = trim(value);
      std::from_chars(v.data(), v.data() + v.size(), flags);
      current_.flags = flags;
    }
  }

  void addBlock(const DL_BlockData& /*data*/) override { in_block_ = true; }
  void endBlock() override { in_block_ = false; }

  void addLine(const DL_LineData& d) override {
    if (!wanted()) return;
    Piece piece = start_piece("LINE");
    piece.points = {{d.x1, d.y1}, {d.x2, d.y2}};
    piece.segments.push_back(Segment{});
    pieces.push_back(std::move(piece));
  }

  /// The first problem found in an entity's values (reported after parsing: an exception
  /// thrown through dxflib would leak its parser state).
  std::string error;

  void addArc(const DL_ArcData& d) override {
    if (!wanted()) return;
    if (!(d.radius > 0.0)) {
      note_error("ARC on layer '" + escape_text(attributes.getLayer()) + "' has radius " +
                 format_number(d.radius) + " (must be > 0)");
      return;
    }
    const auto mirror = ocs_mirror("ARC");
    if (!mirror) return;
    double sweep = std::fmod(d.angle2 - d.angle1, 360.0);
    if (sweep <= 0.0) sweep += 360.0;  // equal angles: a full turn
    const double a1 = d.angle1 * kPi / 180.0;
    const double a2 = a1 + sweep * kPi / 180.0;
    Piece piece = start_piece("ARC");
    piece.points = {
        to_world({d.cx + d.radius * std::cos(a1), d.cy + d.radius * std::sin(a1)}, *mirror),
        to_world({d.cx + d.radius * std::cos(a2), d.cy + d.radius * std::sin(a2)}, *mirror)};
    piece.segments.push_back(
        Segment{true, to_world({d.cx, d.cy}, *mirror), !*mirror, sweep * kPi / 180.0});
    pieces.push_back(std::move(piece));
  }

  void addCircle(const DL_CircleData& d) override {
    if (!wanted()) return;
    if (!(d.radius > 0.0)) {
      note_error("CIRCLE on layer '" + escape_text(attributes.getLayer()) + "' has radius " +
                 format_number(d.radius) + " (must be > 0)");
      return;
    }
    const auto mirror = ocs_mirror("CIRCLE");
    if (!mirror) return;
    // Two half turns, so that no single arc starts and ends at the same point.
    const Vec2 c = to_world({d.cx, d.cy}, *mirror);
    Piece piece = start_piece("CIRCLE");
    piece.closed = true;
    piece.points = {{c.x + d.radius, c.y}, {c.x - d.radius, c.y}};
    piece.segments = {Segment{true, c, true, kPi}, Segment{true, c, true, kPi}};
    pieces.push_back(std::move(piece));
  }

  void addPolyline(const DL_PolylineData& d) override {
    finish_polyline();
    if (!wanted()) return;
    const std::string type = previous_.type == "LWPOLYLINE" ? "LWPOLYLINE" : "POLYLINE";
    if (d.flags & (16 | 64)) {  // polygon mesh or polyface mesh
      ++dropped.mesh[type];
      return;
    }
    // A 3D polyline (flag 8) has world coordinates and no extrusion; 2D ones use the OCS.
    std::optional<bool> mirror = false;
    if (!(d.flags & 8)) mirror = ocs_mirror(type);
    if (!mirror) return;
    polyline_ = start_piece(type);
    polyline_->closed = (d.flags & 1) != 0;
    polyline_mirror_ = *mirror;
    polyline_classic_ = (type == "POLYLINE");
    bulges_.clear();
  }

  void addVertex(const DL_VertexData& d) override {
    if (!polyline_) return;
    // Spline frame control points (vertex flag 16) are not on the curve.
    if (polyline_classic_ && previous_.type == "VERTEX" && (previous_.flags & 16)) return;
    polyline_->points.push_back(to_world({d.x, d.y}, polyline_mirror_));
    bulges_.push_back(polyline_mirror_ ? -d.bulge : d.bulge);
  }

  void endEntity() override { finish_polyline(); }
  void endSequence() override { finish_polyline(); }

  /// Completes a polyline that the file left open (call after parsing).
  void finish() { finish_polyline(); }

 private:
  struct Record {
    std::string type;
    bool paper = false;
    int flags = 0;
  };
  Record current_, previous_;
  bool in_block_ = false;
  std::optional<Piece> polyline_;
  bool polyline_mirror_ = false;
  bool polyline_classic_ = false;
  std::vector<double> bulges_;

  void note_error(const std::string& problem) {
    if (error.empty()) error = problem;
  }

  /// Model-space entities only: not inside a block definition, not in paper space.
  [[nodiscard]] bool wanted() const { return !in_block_ && !previous_.paper; }

  Piece start_piece(const std::string& type) const {
    Piece piece;
    piece.layer = attributes.getLayer();
    piece.type = type;
    return piece;
  }

  /// Whether the entity's object coordinate system mirrors x (extrusion (0,0,-1)); nullopt,
  /// counted as dropped, if the entity does not lie in a plane parallel to the XY plane.
  std::optional<bool> ocs_mirror(const std::string& type) {
    const double* n = extrusion->getDirection();
    // The largest component, not the length: the squares of (0, 0, 1e-300) underflow to 0.
    const double len = std::max({std::abs(n[0]), std::abs(n[1]), std::abs(n[2])});
    if (!(len > 0.0) || std::abs(n[0]) > 1e-9 * len || std::abs(n[1]) > 1e-9 * len) {
      ++dropped.not_planar[type];
      return std::nullopt;
    }
    // Arbitrary-axis algorithm of the DXF reference: for N = (0,0,-1) the OCS x axis is -x.
    return n[2] < 0.0;
  }

  static Vec2 to_world(Vec2 p, bool mirror) { return mirror ? Vec2{-p.x, p.y} : p; }

  void finish_polyline() {
    if (!polyline_) return;
    Piece piece = std::move(*polyline_);
    polyline_.reset();
    const std::size_t n = piece.points.size();
    if (n == 0) {
      // Kept so that the reader reports it: a closed polyline without vertices is degenerate,
      // an open one is skipped like a zero-length entity.
      pieces.push_back(std::move(piece));
      return;
    }
    const std::size_t nseg = piece.closed ? n : n - 1;
    for (std::size_t k = 0; k < nseg; ++k) {
      const double bulge = bulges_[k];
      if (bulge == 0.0) {
        piece.segments.push_back(Segment{});
        continue;
      }
      // Bulge = tan(theta / 4), theta the included angle, positive counter-clockwise. The
      // centre lies on the chord's perpendicular bisector, (c / 2) / tan(theta / 2) to the left.
      const Vec2 a = piece.points[k];
      const Vec2 b = piece.points[(k + 1) % n];
      const double theta = 4.0 * std::atan(bulge);
      const double offset = 0.5 / std::tan(0.5 * theta);
      const Vec2 center{0.5 * (a.x + b.x) - offset * (b.y - a.y),
                        0.5 * (a.y + b.y) + offset * (b.x - a.x)};
      piece.segments.push_back(Segment{true, center, bulge > 0.0, std::abs(theta)});
    }
    pieces.push_back(std::move(piece));
  }
};

double distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

/// Whether the segment from `a` to `b` has no length within `tol` (an arc whose ends meet
/// has length when it makes a full turn).
bool zero_length(Vec2 a, Vec2 b, const Segment& s, double tol) {
  if (distance(a, b) > tol) return false;
  return !s.arc || distance(a, s.center) * s.sweep <= tol;
}

/// Removes the segments of no length (within `tol`) together with the vertex they end at;
/// in a closed piece, a last vertex that repeats the first goes too. Returns false when
/// nothing of non-zero length remains.
bool drop_short_segments(Piece& piece, double tol) {
  std::vector<Vec2> points{piece.points.front()};
  std::vector<Segment> segments;
  const std::size_t n = piece.points.size();
  for (std::size_t k = 1; k < n; ++k) {
    // Segment k-1 ends at vertex k; if it has no length, segment k starts at the kept vertex.
    if (zero_length(points.back(), piece.points[k], piece.segments[k - 1], tol)) continue;
    segments.push_back(piece.segments[k - 1]);
    points.push_back(piece.points[k]);
  }
  if (piece.closed) {
    if (points.size() > 1 &&
        zero_length(points.back(), points.front(), piece.segments.back(), tol)) {
      // The last kept vertex repeats the first: the segment that ends there now closes.
      points.pop_back();
    } else {
      segments.push_back(piece.segments.back());
    }
  }
  piece.points = std::move(points);
  piece.segments = std::move(segments);
  if (piece.closed) {
    // Needs three vertices, or two joined by at least one arc (a circle drawn as a polyline).
    const bool has_arc = std::any_of(piece.segments.begin(), piece.segments.end(),
                                     [](const Segment& s) { return s.arc; });
    return piece.points.size() >= 3 || (piece.points.size() == 2 && has_arc);
  }
  return piece.points.size() >= 2;
}

/// A loop in drawing units before flattening: a cycle of piece traversals.
struct Traversal {
  std::size_t piece;       ///< index into the pieces
  std::size_t open_index;  ///< index among the open pieces (open pieces only)
  bool forward;
};

/// A flattened loop in drawing units, with the layer of each edge.
struct RawLoop {
  std::vector<Vec2> points;
  std::vector<std::string> layers;
  std::vector<std::uint8_t> straight;
};

std::string quoted(const std::string& layer) {
  return "'" + escape_text(layer) + "'";
}

class Reader {
 public:
  Reader(std::string path, const ReadOptions& options, std::vector<std::string>* warnings)
      : path_(std::move(path)), options_(options), warnings_(warnings) {}

  Outline read() {
    std::string text = read_text_file(path_);
    if (!options_.radius) throw InputError(path_ + ": no disk radius (give --radius)");
    const double radius = *options_.radius;
    if (!(radius > 0.0) || !std::isfinite(radius))
      throw InputError(path_ + ": disk radius must be > 0 (" + format_number(radius) + ")");
    if (!(options_.chord_fraction > 0.0) || !std::isfinite(options_.chord_fraction))
      throw InputError(path_ + ": chord fraction must be > 0 (" +
                       format_number(options_.chord_fraction) + ")");

    const ScanResult scan = prescan(path_, text);
    text.clear();
    text.shrink_to_fit();

    Collector collector;
    DL_Dxf dxf;
    if (!dxf.in(path_, &collector)) throw InputError(path_ + ": cannot open file");
    collector.finish();
    if (!collector.error.empty()) throw InputError(path_ + ": " + collector.error);

    warn_skipped(scan, collector.dropped);
    scale_ = drawing_scale(scan.insunits);
    chord_error_ = options_.chord_fraction * radius / scale_;

    std::vector<Piece> pieces = std::move(collector.pieces);
    for (const Piece& piece : pieces) check_finite(piece);
    tolerance_ = tolerance(pieces);
    std::int64_t empty_pieces = 0;
    std::vector<Piece> kept;
    kept.reserve(pieces.size());
    for (Piece& piece : pieces) {
      if (piece.points.empty()) {  // a polyline without vertices
        if (piece.closed)
          throw InputError(path_ + ": degenerate outline: closed " + piece.type + " on layer " +
                           quoted(piece.layer) +
                           " has fewer than 3 distinct vertices (it has none)");
        ++empty_pieces;
        continue;
      }
      // A closed polyline of one vertex is degenerate too; one whose vertices all coincide
      // has no length.
      const bool one_vertex = piece.points.size() == 1;
      if (drop_short_segments(piece, tolerance_)) {
        kept.push_back(std::move(piece));
      } else if (piece.closed && (piece.points.size() >= 2 || one_vertex)) {
        throw InputError(path_ + ": degenerate outline: closed " + piece.type + " on layer " +
                         quoted(piece.layer) + " at " + format_point(piece.points.front()) +
                         " has fewer than 3 distinct vertices");
      } else {
        ++empty_pieces;
      }
    }
    if (empty_pieces > 0)
      note_skipped("skipped " + std::to_string(empty_pieces) + " zero-length " +
                   (empty_pieces == 1 ? "entity" : "entities"));

    std::vector<RawLoop> loops;
    try {
      loops = build_loops(kept);
    } catch (const InputError& e) {
      const std::string what = e.what();
      if (what.rfind(path_, 0) == 0) throw;
      throw InputError(path_ + ": " + what);  // from flatten_arc
    }
    if (loops.empty()) {
      // The program prints the warnings only after a successful read, so the entities that
      // were skipped (often the reason nothing is left) are named in the error itself.
      std::string message = path_ + ": no closed outline";
      for (const std::string& reason : skipped_) message += "; " + reason;
      throw InputError(message);
    }
    Outline outline = nest(loops);
    check_lattice_size(outline, reader_size_limit(options_.max_disks, options_.max_disks_hint));
    validate_and_orient(outline);
    return outline;
  }

 private:
  std::string path_;
  const ReadOptions& options_;
  std::vector<std::string>* warnings_;
  double scale_ = 1.0;        ///< metres per drawing unit
  double chord_error_ = 0.0;  ///< max sagitta of the chords [drawing units]
  double tolerance_ = 0.0;    ///< end-point matching distance [drawing units]

  void check_finite(const Piece& piece) const {
    const auto finite = [](Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); };
    bool ok = std::all_of(piece.points.begin(), piece.points.end(), finite);
    for (const Segment& s : piece.segments)
      ok = ok && (!s.arc || (finite(s.center) && std::isfinite(s.sweep)));
    if (!ok)
      throw InputError(path_ + ": " + piece.type + " on layer " + quoted(piece.layer) +
                       " has a coordinate that is not a finite number");
  }

  /// The "skipped ..." warnings without the file name, for the "no closed outline" error.
  std::vector<std::string> skipped_;

  void warn(const std::string& line) {
    if (warnings_) warnings_->push_back(line);
  }

  /// Warns that entities were skipped (`what`: "skipped N TYPE entities (reason)").
  void note_skipped(const std::string& what) {
    skipped_.push_back(what);
    warn(path_ + ": " + what);
  }

  static std::string entities(std::int64_t n, const std::string& type) {
    return std::to_string(n) + " " + type + (n == 1 ? " entity" : " entities");
  }

  void warn_skipped(const ScanResult& scan, const Dropped& dropped) {
    static const char* const supported[] = {"LINE", "ARC", "CIRCLE", "LWPOLYLINE", "POLYLINE"};
    for (const auto& [type, count] : scan.model_counts) {
      if (std::find(std::begin(supported), std::end(supported), type) != std::end(supported))
        continue;
      std::string reason = "unsupported";
      if (type == "INSERT") reason = "unsupported: block references are not expanded";
      note_skipped("skipped " + entities(count, type) + " (" + reason + ")");
    }
    for (const auto& [type, count] : dropped.mesh)
      note_skipped("skipped " + entities(count, type) + " (unsupported: polygon or polyface mesh)");
    for (const auto& [type, count] : dropped.not_planar)
      note_skipped("skipped " + entities(count, type) + " (not parallel to the XY plane)");
    if (scan.paper_count > 0)
      note_skipped("skipped " + std::to_string(scan.paper_count) +
                   (scan.paper_count == 1 ? " entity" : " entities") + " in paper space");
  }

  /// `insunits`: the header's $INSUNITS as written (checked to be an integer by the pre-scan).
  double drawing_scale(const std::optional<std::string>& insunits) {
    if (options_.scale > 0.0) return options_.scale;
    if (!insunits) return 1.0;
    const std::optional<std::int64_t> code = to_int64(*insunits);
    if (code == 0) return 1.0;
    const std::optional<double> factor =
        code && *code > 0 && *code < static_cast<std::int64_t>(kInsunitsMetres.size())
            ? insunits_factor(static_cast<int>(*code))
            : std::nullopt;
    if (factor) return *factor;
    warn(path_ + ": unknown $INSUNITS code " + escape_text(*insunits) +
         "; taking 1 drawing unit = 1 m");
    return 1.0;
  }

  /// kRelativeTolerance times the diagonal of the bounding box of all pieces.
  static double tolerance(const std::vector<Piece>& pieces) {
    double xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
    const auto grow = [&](Vec2 p) {
      xmin = std::min(xmin, p.x);
      ymin = std::min(ymin, p.y);
      xmax = std::max(xmax, p.x);
      ymax = std::max(ymax, p.y);
    };
    for (const Piece& piece : pieces) {
      for (const Vec2& p : piece.points) grow(p);
      for (std::size_t k = 0; k < piece.segments.size(); ++k) {
        const Segment& s = piece.segments[k];
        if (!s.arc) continue;
        // The arc's circle bounds it; close enough for a tolerance.
        const double r = distance(s.center, piece.points[k]);
        grow({s.center.x - r, s.center.y - r});
        grow({s.center.x + r, s.center.y + r});
      }
    }
    if (!(xmax >= xmin)) return 0.0;
    return kRelativeTolerance * std::hypot(xmax - xmin, ymax - ymin);
  }

  /// Chains the open pieces into cycles and returns all loops, flattened, in the order of
  /// their first entity in the file.
  std::vector<RawLoop> build_loops(const std::vector<Piece>& pieces) {
    // Piece ends: 2 i is the start of open piece i, 2 i + 1 its end.
    std::vector<std::size_t> open;
    for (std::size_t i = 0; i < pieces.size(); ++i)
      if (!pieces[i].closed) open.push_back(i);
    const std::size_t nends = 2 * open.size();
    const auto end_point = [&](std::size_t e) {
      const Piece& p = pieces[open[e / 2]];
      return e % 2 == 0 ? p.points.front() : p.points.back();
    };

    // Nodes: clusters of ends within the tolerance (a hash grid with cells of its size),
    // numbered in order of first appearance, at the ends' mean.
    std::size_t nodes = 0;
    const std::vector<std::size_t> node_of = cluster_points(
        nends, end_point, tolerance_ > 0.0 ? tolerance_ : 1.0,
        [&](std::size_t a, std::size_t b) { return distance(end_point(a), end_point(b)) <= tolerance_; }, nodes);
    std::vector<std::vector<std::size_t>> node_ends(nodes);
    for (std::size_t e = 0; e < nends; ++e) node_ends[node_of[e]].push_back(e);
    std::vector<Vec2> node_point(node_ends.size());
    for (std::size_t v = 0; v < node_ends.size(); ++v) {
      Vec2 sum{};
      for (const std::size_t e : node_ends[v]) {
        sum.x += end_point(e).x;
        sum.y += end_point(e).y;
      }
      const double n = static_cast<double>(node_ends[v].size());
      node_point[v] = {sum.x / n, sum.y / n};
    }
    for (std::size_t v = 0; v < node_ends.size(); ++v) {
      const auto& ends = node_ends[v];
      if (ends.size() == 1) throw_open_chain(pieces, open, node_ends, node_point, v);
      if (ends.size() > 2) {
        std::vector<std::string> layers;
        for (const std::size_t e : ends) {
          const std::string q = quoted(pieces[open[e / 2]].layer);
          if (std::find(layers.begin(), layers.end(), q) == layers.end()) layers.push_back(q);
        }
        std::string names;
        for (const std::string& q : layers) names += (names.empty() ? "" : ", ") + q;
        throw InputError(path_ + ": branching outline: " + std::to_string(ends.size()) +
                         " entity ends meet at " + format_point(node_point[v]) + " on layer" +
                         (layers.size() > 1 ? "s " : " ") + names +
                         " (each point must join exactly two ends)");
      }
    }

    // Cycles, and closed pieces, each keyed by its first piece for the file order.
    std::vector<std::pair<std::size_t, std::vector<Traversal>>> cycles;
    for (std::size_t i = 0; i < pieces.size(); ++i)
      if (pieces[i].closed) cycles.push_back({i, {Traversal{i, 0, true}}});
    std::vector<bool> used(open.size(), false);
    for (std::size_t k = 0; k < open.size(); ++k) {
      if (used[k]) continue;
      std::vector<Traversal> cycle;
      const std::size_t first_end = 2 * k;
      std::size_t entry = first_end;  // the end through which the current piece is entered
      while (true) {
        used[entry / 2] = true;
        cycle.push_back(Traversal{open[entry / 2], entry / 2, entry % 2 == 0});
        const std::size_t leave = entry ^ 1U;
        const auto& ends = node_ends[node_of[leave]];
        const std::size_t next = ends[0] == leave ? ends[1] : ends[0];
        if (next == first_end) break;
        entry = next;
      }
      cycles.push_back({open[k], std::move(cycle)});
    }
    std::stable_sort(cycles.begin(), cycles.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });

    std::vector<RawLoop> loops;
    loops.reserve(cycles.size());
    for (const auto& [first, cycle] : cycles) {
      RawLoop loop;
      for (const Traversal& t : cycle) {
        const Piece& piece = pieces[t.piece];
        if (piece.closed) {
          const std::size_t n = piece.points.size();
          for (std::size_t k = 0; k < n; ++k)
            append_segment(loop, piece.points[k], piece.points[(k + 1) % n], piece.segments[k],
                           piece.layer);
          continue;
        }
        // An open piece runs between two nodes; use the node points at both ends.
        const std::size_t k_open = t.open_index;
        std::vector<Vec2> pts = piece.points;
        pts.front() = node_point[node_of[2 * k_open]];
        pts.back() = node_point[node_of[2 * k_open + 1]];
        const std::size_t nseg = piece.segments.size();
        for (std::size_t s = 0; s < nseg; ++s) {
          if (t.forward) {
            append_segment(loop, pts[s], pts[s + 1], piece.segments[s], piece.layer);
          } else {
            Segment seg = piece.segments[nseg - 1 - s];
            seg.ccw = !seg.ccw;
            append_segment(loop, pts[nseg - s], pts[nseg - 1 - s], seg, piece.layer);
          }
        }
      }
      loops.push_back(std::move(loop));
    }
    return loops;
  }

  [[noreturn]] void throw_open_chain(const std::vector<Piece>& pieces,
                                     const std::vector<std::size_t>& open,
                                     const std::vector<std::vector<std::size_t>>& node_ends,
                                     const std::vector<Vec2>& node_point, std::size_t v) const {
    const Vec2 p = node_point[v];
    std::string message = path_ + ": open outline: chain on layer " +
                          quoted(pieces[open[node_ends[v][0] / 2]].layer) + " ends at " +
                          format_point(p) + " with no continuation";
    // The nearest other loose end tells whether a gap is just wider than the tolerance.
    std::optional<std::size_t> nearest;
    for (std::size_t w = 0; w < node_ends.size(); ++w) {
      if (w == v || node_ends[w].size() != 1) continue;
      if (!nearest || distance(p, node_point[w]) < distance(p, node_point[*nearest])) nearest = w;
    }
    if (nearest)
      message += " (nearest loose end " + format_point(node_point[*nearest]) + ", " +
                 format_number(distance(p, node_point[*nearest])) + " away)";
    throw InputError(message);
  }

  /// Appends the edges from `a` towards `b` (b itself is the start of the next segment).
  void append_segment(RawLoop& loop, Vec2 a, Vec2 b, const Segment& seg,
                      const std::string& layer) const {
    const auto add = [&](Vec2 p, std::uint8_t straight) {
      loop.points.push_back(p);
      loop.layers.push_back(layer);
      loop.straight.push_back(straight);
    };
    if (!seg.arc) {
      add(a, 1);
      return;
    }
    // Split the arc into parts of at most half a turn, so that start, end and direction
    // determine each part, and flatten each part; a part whose sagitta is already within the
    // chord error is one chord.
    const double r = 0.5 * (distance(a, seg.center) + distance(b, seg.center));
    const auto parts = static_cast<int>(std::max(1.0, std::ceil(seg.sweep / kPi - 1e-9)));
    const double step = (seg.ccw ? 1.0 : -1.0) * seg.sweep / parts;
    const double angle_a = std::atan2(a.y - seg.center.y, a.x - seg.center.x);
    Vec2 from = a;
    for (int k = 1; k <= parts; ++k) {
      const double angle = angle_a + step * k;
      const Vec2 to =
          k == parts ? b
                     : Vec2{seg.center.x + r * std::cos(angle), seg.center.y + r * std::sin(angle)};
      add(from, 0);
      const double sagitta = r * (1.0 - std::cos(0.5 * std::abs(step)));
      if (sagitta > chord_error_) {
        std::vector<Vec2> chords = flatten_arc(from, to, seg.center, seg.ccw, chord_error_);
        chords.pop_back();  // `to` starts the next part or segment
        for (const Vec2& q : chords) add(q, 0);
      }
      from = to;
    }
  }

  /// Scales the loops to metres and sorts them into bodies (even nesting depth) and holes
  /// (odd depth): see docs/outline-dxf.md, "Nesting".
  Outline nest(const std::vector<RawLoop>& raw) {
    Outline outline;
    outline.source = path_;
    const std::size_t n = raw.size();
    std::vector<Loop> loops(n);
    std::vector<double> area(n);
    struct Box {
      double xmin, ymin, xmax, ymax;
    };
    std::vector<Box> box(n);
    for (std::size_t i = 0; i < n; ++i) {
      Loop& loop = loops[i];
      std::vector<std::string> names;
      Box b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
      for (std::size_t k = 0; k < raw[i].points.size(); ++k) {
        const Vec2 p{raw[i].points[k].x * scale_, raw[i].points[k].y * scale_};
        loop.points.push_back(p);
        b = {std::min(b.xmin, p.x), std::min(b.ymin, p.y), std::max(b.xmax, p.x),
             std::max(b.ymax, p.y)};
        const std::string& layer = raw[i].layers[k];
        loop.edge_set.push_back(layer == "0" ? -1 : outline.boundary_index(layer));
        loop.edge_straight.push_back(raw[i].straight[k]);
        if (std::find(names.begin(), names.end(), layer) == names.end()) names.push_back(layer);
      }
      std::string layers;
      for (const std::string& name : names) layers += (layers.empty() ? "" : ", ") + quoted(name);
      loop.where = path_ + ": layer" + (names.size() > 1 ? "s " : " ") + layers + " loop " +
                   std::to_string(i + 1);
      area[i] = std::abs(signed_area(loop));
      box[i] = b;
    }

    // Largest first; the parent of a loop is the smallest larger loop that contains it.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return area[a] > area[b]; });
    const double tol_m = tolerance_ * scale_;
    std::vector<int> depth(n, 0);
    std::vector<std::optional<std::size_t>> parent(n);
    for (std::size_t oi = 0; oi < n; ++oi) {
      const std::size_t i = order[oi];
      for (std::size_t oj = oi; oj-- > 0;) {
        const std::size_t j = order[oj];
        if (!(area[j] > area[i])) continue;
        if (box[i].xmin < box[j].xmin || box[i].xmax > box[j].xmax || box[i].ymin < box[j].ymin ||
            box[i].ymax > box[j].ymax)
          continue;
        if (contains(loops[j], loops[i], tol_m)) {
          parent[i] = j;
          depth[i] = depth[j] + 1;
          break;
        }
      }
    }

    std::vector<std::optional<std::size_t>> body_of(n);
    for (const std::size_t i : order) {
      if (depth[i] % 2 != 0) continue;
      BodyOutline body;
      body.name = "body" + std::to_string(outline.bodies.size() + 1);
      body.material = static_cast<int>(outline.bodies.size() + 1);
      body.radius = options_.radius;
      body.angle_deg = options_.angle_deg.value_or(0.0);
      body.origin = options_.origin.value_or(Vec2{0.0, 0.0});
      body.where = path_ + ": " + body.name;
      body.outers.push_back(std::move(loops[i]));
      body_of[i] = outline.bodies.size();
      outline.bodies.push_back(std::move(body));
    }
    for (const std::size_t i : order)
      if (depth[i] % 2 != 0)
        outline.bodies[*body_of[*parent[i]]].holes.push_back(std::move(loops[i]));
    return outline;
  }

  /// Whether `inner` lies inside `outer`, judged at the first vertex of `inner` that is not
  /// within `tol` of the boundary of `outer` (loops are checked not to cross later).
  static bool contains(const Loop& outer, const Loop& inner, double tol) {
    const std::size_t n = outer.points.size();
    for (const Vec2& p : inner.points) {
      bool inside = false;
      bool on_boundary = false;
      for (std::size_t k = 0, l = n - 1; k < n; l = k++) {
        const Vec2 a = outer.points[l], b = outer.points[k];
        if (segment_distance(p, a, b) <= tol) {
          on_boundary = true;
          break;
        }
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
          inside = !inside;
      }
      if (!on_boundary) return inside;
    }
    return false;
  }

  static double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
  }
};

}  // namespace

double dxf_insunits_to_metres(int code) {
  return insunits_factor(code).value_or(1.0);
}

Outline read_outline_dxf(const std::string& path, const ReadOptions& options,
                         std::vector<std::string>* warnings) {
  return Reader(path, options, warnings).read();
}

}  // namespace hexdem::meshing
