/// \file outline.cpp
/// Plain geometry on outlines: boundary-name registry, loop area and arc flattening.

#include "hexdem/meshing/outline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "hexdem/error.hpp"

namespace hexdem::meshing {

std::int32_t Outline::boundary_index(const std::string& name) {
  const auto it = std::find(boundary_names.begin(), boundary_names.end(), name);
  if (it != boundary_names.end()) return static_cast<std::int32_t>(it - boundary_names.begin());
  boundary_names.push_back(name);
  return static_cast<std::int32_t>(boundary_names.size() - 1);
}

double signed_area(const Loop& loop) {
  // Shoelace formula, with coordinates taken relative to the first vertex to limit
  // cancellation for loops far from the origin.
  const std::size_t n = loop.points.size();
  if (n < 3) return 0.0;
  const Vec2 o = loop.points[0];
  double twice_area = 0.0;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double ax = loop.points[k].x - o.x, ay = loop.points[k].y - o.y;
    const double bx = loop.points[k + 1].x - o.x, by = loop.points[k + 1].y - o.y;
    twice_area += ax * by - ay * bx;
  }
  return 0.5 * twice_area;
}

std::vector<Vec2> flatten_arc(Vec2 a, Vec2 b, Vec2 center, bool ccw, double chord_error) {
  HEXDEM_VERIFY(chord_error > 0.0 && std::isfinite(chord_error), "chord error must be > 0");
  constexpr double two_pi = 2.0 * std::numbers::pi;
  const double radius = std::hypot(a.x - center.x, a.y - center.y);
  const double angle_a = std::atan2(a.y - center.y, a.x - center.x);
  const double angle_b = std::atan2(b.y - center.y, b.x - center.x);

  // Swept angle in the direction of travel, in [0, 2 pi).
  double sweep = ccw ? angle_b - angle_a : angle_a - angle_b;
  sweep = std::fmod(sweep, two_pi);
  if (sweep < 0.0) sweep += two_pi;

  // A chord subtending phi has sagitta radius * (1 - cos(phi / 2)); keep it <= chord_error,
  // and never let one chord span more than half a turn.
  const double max_step = chord_error >= radius ? std::numbers::pi
                                                : 2.0 * std::acos(1.0 - chord_error / radius);
  const double chords = std::ceil(sweep / max_step);
  if (!(chords <= kMaxArcChords)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "an arc of radius %.6g would need more than %.0f chords at a chord error of %.6g "
                  "(the disk radius is too small for the arc)",
                  radius, kMaxArcChords, chord_error);
    throw InputError(text);
  }
  const auto segments = std::max<std::size_t>(1, static_cast<std::size_t>(chords));
  const double step = (ccw ? sweep : -sweep) / static_cast<double>(segments);

  std::vector<Vec2> points;
  points.reserve(segments);
  for (std::size_t k = 1; k < segments; ++k) {
    const double angle = angle_a + step * static_cast<double>(k);
    points.push_back({center.x + radius * std::cos(angle), center.y + radius * std::sin(angle)});
  }
  points.push_back(b);
  return points;
}

}  // namespace hexdem::meshing
