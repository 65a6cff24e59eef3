#pragma once
/// \file outline.hpp
/// Region descriptions that the lattice generator fills: closed loops of straight edges
/// (arcs and circles are already flattened to chords), grouped into bodies.
/// All lengths are metres. Readers: outline_toml.hpp (TOML), outline_dxf.hpp (DXF).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hexdem::meshing {

/// A point or vector in the plane [m]. In axisymmetric mode x is the radius r, y the axial z.
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

/// A closed loop of straight edges. Edge k runs from points[k] to points[(k+1) % n]; the
/// closing point is not repeated.
struct Loop {
  std::vector<Vec2> points;                ///< vertices [m], at least 3
  std::vector<std::int32_t> edge_set;      ///< per edge: index into Outline::boundary_names, -1 none
  std::vector<std::uint8_t> edge_straight; ///< per edge: 1 straight edge of the drawing, 0 a chord
                                           ///< of an arc or circle (never a "neat" edge)
  std::string where;                       ///< origin for messages, e.g. "case.toml: body 'disc' shape 2"
};

/// Options that may be set per body (the command line gives the defaults).
struct LatticeOptions {
  double radius = 0.0;        ///< disk radius r [m]; lattice spacing d = 2r
  double angle_deg = 0.0;     ///< lattice axis angle from the x axis [degrees]
  Vec2 origin{0.0, 0.0};      ///< a lattice point [m]
};

/// Range of a body's `radius_factor` (its disk radius as a multiple of the lattice's, from
/// the command line or [lattice]): refining one body 100 times is as far as a mesh goes.
inline constexpr double kMinRadiusFactor = 0.01;
inline constexpr double kMaxRadiusFactor = 100.0;

/// One body: the region bounded by its outer loops minus its holes.
struct BodyOutline {
  std::string name;                   ///< body name (unique in the outline)
  int material = 1;                   ///< material id (refers to the case's materials)
  std::vector<Loop> outers;           ///< disjoint outer boundaries
  std::vector<Loop> holes;            ///< holes, each inside one outer boundary
  std::optional<double> radius;       ///< overrides LatticeOptions::radius [m] (the TOML
                                      ///< reader folds a body's radius_factor into it)
  std::optional<double> angle_deg;    ///< overrides LatticeOptions::angle_deg [deg]
  std::optional<Vec2> origin;         ///< overrides LatticeOptions::origin [m]
  std::string where;                  ///< origin for messages
};

/// Everything one outline file describes.
struct Outline {
  std::string source;                        ///< file the outline was read from
  std::vector<std::string> boundary_names;   ///< named boundary sets (edge_set indexes this)
  std::vector<BodyOutline> bodies;

  /// Index of a boundary name, adding it if new.
  std::int32_t boundary_index(const std::string& name);
};

/// Signed area of a loop [m^2] (positive when counter-clockwise).
double signed_area(const Loop& loop);

/// Most chords flatten_arc makes of one arc.
inline constexpr double kMaxArcChords = 1e6;

/// Flattens a circular arc from `a` to `b` about `center` (counter-clockwise if ccw) into
/// chords whose sagitta is at most `chord_error` [m]. Returns the points after `a`, ending
/// with `b` exactly. Throws InputError (without a file name: callers add it) when the arc
/// would need more than kMaxArcChords chords.
std::vector<Vec2> flatten_arc(Vec2 a, Vec2 b, Vec2 center, bool ccw, double chord_error);

/// Largest coordinate magnitude of an outline point [m] that validate_and_orient accepts.
inline constexpr double kMaxCoordinate = 1e15;

/// Orients outers counter-clockwise and holes clockwise, and checks, with CGAL's exact
/// predicates, that every loop is simple (no self-intersection, at least 3 distinct
/// vertices, non-zero area), every hole lies inside one outer loop of its body, loops of a
/// body do not cross or overlap, that no two bodies overlap and that every coordinate is
/// finite and at most kMaxCoordinate in magnitude. Throws InputError naming the loop
/// (Loop::where) and the offending point.
void validate_and_orient(Outline& outline);

}  // namespace hexdem::meshing
