/// \file outline_validate.cpp
/// Checks and orients outlines with CGAL's exact predicates (validate_and_orient).

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/outline.hpp"

namespace hexdem::meshing {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_2;
using Segment = K::Segment_2;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using EdgeBox = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::size_t>;

/// Nine significant digits: computed points and areas, not echoes of the input.
std::string format_number(double value) {
  char buffer[32];
  const auto result =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 9);
  return std::string(buffer, result.ptr);
}

std::string format_point(double x, double y) {
  std::string text = "(";
  text.append(format_number(x)).append(", ").append(format_number(y)).append(")");
  return text;
}

std::string format_point(const Point& p) {
  return format_point(CGAL::to_double(p.x()), CGAL::to_double(p.y()));
}

/// Throws the one-line message "<where>: <problem> (<value>)".
[[noreturn]] void fail(const std::string& where, const std::string& problem,
                       const std::string& value) {
  throw InputError(where + ": " + problem + " (" + value + ")");
}

/// Removes exactly repeated consecutive vertices (and a repeated closing vertex) together
/// with the zero-length edges that start at them, keeping the per-edge arrays aligned.
void drop_repeated_vertices(Loop& loop) {
  std::vector<Vec2> points;
  std::vector<std::int32_t> edge_set;
  std::vector<std::uint8_t> edge_straight;
  const auto same = [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; };
  for (std::size_t k = 0; k < loop.points.size(); ++k) {
    if (!points.empty() && same(points.back(), loop.points[k])) {
      // Edge k-1 has zero length: edge k continues from the kept vertex instead.
      edge_set.back() = loop.edge_set[k];
      edge_straight.back() = loop.edge_straight[k];
      continue;
    }
    points.push_back(loop.points[k]);
    edge_set.push_back(loop.edge_set[k]);
    edge_straight.push_back(loop.edge_straight[k]);
  }
  // A repeated closing vertex starts the zero-length closing edge; the edge before it closes.
  while (points.size() > 1 && same(points.back(), points.front())) {
    points.pop_back();
    edge_set.pop_back();
    edge_straight.pop_back();
  }
  loop.points = std::move(points);
  loop.edge_set = std::move(edge_set);
  loop.edge_straight = std::move(edge_straight);
}

/// Reverses the direction of travel, keeping points[0] first. Edge k runs
/// points[k] -> points[k+1]; the new order p0, p(n-1), ..., p1 makes new edge k the old
/// edge n-1-k traversed backwards, so the per-edge arrays are reversed whole.
void reverse_loop(Loop& loop) {
  std::reverse(loop.points.begin() + 1, loop.points.end());
  std::reverse(loop.edge_set.begin(), loop.edge_set.end());
  std::reverse(loop.edge_straight.begin(), loop.edge_straight.end());
}

/// An edge of one loop in a group of loops.
struct EdgeRef {
  std::size_t loop = 0;
  std::size_t edge = 0;
};

/// Two edges that meet where they must not, and a point where they meet.
struct Contact {
  EdgeRef a;
  EdgeRef b;
  Point at;
};

/// Whether neighbouring edges u-v and v-w of one loop overlap (fold back along a line)
/// rather than meet only at their shared vertex v.
bool folds_back(const Point& u, const Point& v, const Point& w) {
  return CGAL::collinear(u, v, w) && !CGAL::collinear_are_ordered_along_line(u, v, w);
}

/// A point common to two segments known to intersect.
Point common_point(const Segment& a, const Segment& b) {
  const auto result = CGAL::intersection(a, b);
  if (const Point* p = boost::get<Point>(&*result)) return *p;
  return boost::get<Segment>(*result).source();
}

/// Finds the first (lowest loop and edge indices) pair of edges that meet improperly.
/// With `within_loops`, only pairs of edges of the same loop are examined and neighbouring
/// edges may share their common vertex; otherwise only pairs from different loops are
/// examined and any common point is a contact. Candidate pairs come from a box-intersection
/// search on the edges' bounding boxes, so the search is fast unless many edges overlap.
/// The bounding box of every edge of `loops`, each with its index in `refs` (loop, edge): the
/// input of a box-intersection search over the edges.
void edge_boxes(const std::vector<const Polygon*>& loops, std::vector<EdgeRef>& refs, std::vector<EdgeBox>& boxes) {
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const Polygon& polygon = *loops[l];
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      boxes.emplace_back(polygon.edge(k).bbox(), refs.size());
      refs.push_back({l, k});
    }
  }
}

std::optional<Contact> find_contact(const std::vector<const Polygon*>& loops,
                                    bool within_loops) {
  std::vector<EdgeRef> refs;
  std::vector<EdgeBox> boxes;
  edge_boxes(loops, refs, boxes);

  std::optional<std::tuple<std::size_t, std::size_t, std::size_t, std::size_t>> best;
  const auto examine = [&](const EdgeBox& box_a, const EdgeBox& box_b) {
    EdgeRef a = refs[box_a.info()];
    EdgeRef b = refs[box_b.info()];
    if ((a.loop == b.loop) != within_loops) return;
    if (std::tie(b.loop, b.edge) < std::tie(a.loop, a.edge)) std::swap(a, b);
    const auto key = std::make_tuple(a.loop, a.edge, b.loop, b.edge);
    if (best && *best <= key) return;
    const Polygon& pa = *loops[a.loop];
    const Polygon& pb = *loops[b.loop];
    const Segment sa = pa.edge(a.edge);
    const Segment sb = pb.edge(b.edge);
    if (!CGAL::do_intersect(sa, sb)) return;
    if (within_loops) {
      const std::size_t n = pa.size();
      if ((a.edge + 1) % n == b.edge && !folds_back(sa.source(), sa.target(), sb.target())) return;
      if ((b.edge + 1) % n == a.edge && !folds_back(sb.source(), sb.target(), sa.target())) return;
    }
    best = key;
  };
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), examine);

  if (!best) return std::nullopt;
  const auto [loop_a, edge_a, loop_b, edge_b] = *best;
  const Segment sa = loops[loop_a]->edge(edge_a);
  const Segment sb = loops[loop_b]->edge(edge_b);
  return Contact{{loop_a, edge_a}, {loop_b, edge_b}, common_point(sa, sb)};
}

/// Cleans one loop, checks that it is a simple polygon of non-zero area, orients it
/// (counter-clockwise if outer, clockwise if a hole) and returns it as a CGAL polygon.
Polygon prepare_loop(Loop& loop, bool hole) {
  const std::size_t count = loop.points.size();
  HEXDEM_VERIFY(loop.edge_set.size() == count && loop.edge_straight.size() == count,
                loop.where + ": per-edge arrays must have one entry per point");
  for (std::size_t k = 0; k < count; ++k) {
    if (!std::isfinite(loop.points[k].x) || !std::isfinite(loop.points[k].y))
      fail(loop.where, "non-finite coordinate", "point " + std::to_string(k));
  }
  drop_repeated_vertices(loop);
  const std::size_t n = loop.points.size();
  if (n < 3) fail(loop.where, "fewer than 3 distinct vertices", "got " + std::to_string(n));

  Polygon polygon;
  for (const Vec2& p : loop.points) polygon.push_back(Point(p.x, p.y));

  const bool all_collinear = std::all_of(
      polygon.vertices_begin() + 2, polygon.vertices_end(),
      [&](const Point& p) { return CGAL::collinear(polygon[0], polygon[1], p); });
  if (all_collinear)
    fail(loop.where, "zero area", "all " + std::to_string(n) + " vertices lie on one line");

  if (!polygon.is_simple()) {
    const auto contact = find_contact({&polygon}, true);
    if (!contact) fail(loop.where, "self-intersecting outline", "not a simple polygon");
    fail(loop.where, "self-intersecting outline",
         "edges " + std::to_string(contact->a.edge) + " and " + std::to_string(contact->b.edge) +
             " meet at " + format_point(contact->at));
  }

  const CGAL::Orientation wanted = hole ? CGAL::CLOCKWISE : CGAL::COUNTERCLOCKWISE;
  if (polygon.orientation() != wanted) {
    reverse_loop(loop);
    polygon.reverse_orientation();
  }
  return polygon;
}

/// One oriented loop of a body.
struct BodyLoop {
  const Loop* loop;
  Polygon polygon;
  bool hole;
};

/// For each loop, the other loops that strictly contain its first vertex, by the crossing
/// rule: a ray from the vertex towards +x crosses an odd number of a loop's edges iff the
/// loop contains it (half-open in y, so a ray through a vertex counts it once; exact
/// predicates). No two loops meet (find_contact ran first), so the vertex lies on no other
/// loop. The edges are bucketed in horizontal bands and each ray reads the edges of its band
/// only: about O(edges + loops x band size), where one point-in-polygon test per pair of
/// loops took minutes on outlines of thousands of holes or hundreds of nested rings.
std::vector<std::vector<std::size_t>> containing_loops(const std::vector<BodyLoop>& loops) {
  struct Edge {
    double ylo, yhi;  // the edge's bounding box in y (outward rounded by CGAL) [m]
    std::size_t loop, k;
  };
  std::vector<Edge> edges;
  double ymin = std::numeric_limits<double>::infinity(), ymax = -ymin;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const Polygon& polygon = loops[l].polygon;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const CGAL::Bbox_2 box = polygon.edge(k).bbox();
      edges.push_back({box.ymin(), box.ymax(), l, k});
      ymin = std::min(ymin, box.ymin());
      ymax = std::max(ymax, box.ymax());
    }
  }
  std::vector<std::vector<std::size_t>> inside(loops.size());
  if (edges.empty() || !(ymax > ymin)) return inside;
  // Bands: about one per 4 edges, halved while the entries (an edge in every band it spans)
  // exceed 16 per edge (long edges: a comb of full-height teeth).
  std::size_t nb = std::max<std::size_t>(1, edges.size() / 4);
  std::vector<std::size_t> start;
  double inv = 0;
  const auto band_of = [&](double y) {
    const double t = (y - ymin) * inv;
    if (!(t > 0)) return std::size_t{0};
    return t >= static_cast<double>(nb - 1) ? nb - 1 : static_cast<std::size_t>(t);
  };
  for (;;) {
    inv = static_cast<double>(nb) / (ymax - ymin);
    start.assign(nb + 1, 0);
    std::size_t entries = 0;
    for (const Edge& e : edges) {
      const std::size_t b0 = band_of(e.ylo), b1 = band_of(e.yhi);
      entries += b1 - b0 + 1;
      for (std::size_t b = b0; b <= b1; ++b) ++start[b + 1];
    }
    if (entries <= 16 * edges.size() || nb == 1) break;
    nb = std::max<std::size_t>(1, nb / 2);
  }
  for (std::size_t b = 0; b < nb; ++b) start[b + 1] += start[b];
  std::vector<std::size_t> fill(start.begin(), start.end() - 1), in_band(start[nb]);
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t b = band_of(edges[e].ylo); b <= band_of(edges[e].yhi); ++b) in_band[fill[b]++] = e;

  std::vector<std::uint8_t> parity(loops.size(), 0);
  std::vector<std::size_t> touched;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const Point& p = loops[i].polygon[0];
    const double py = CGAL::to_double(p.y());
    if (!(py >= ymin && py <= ymax)) continue;
    const std::size_t b = band_of(py);
    touched.clear();
    for (std::size_t n = start[b]; n < start[b + 1]; ++n) {
      const Edge& e = edges[in_band[n]];
      if (e.loop == i || py < e.ylo || py > e.yhi) continue;
      const Polygon& polygon = loops[e.loop].polygon;
      const Point& u = polygon[e.k];
      const Point& v = polygon[(e.k + 1) % polygon.size()];
      const CGAL::Comparison_result uv = CGAL::compare_y(u, v);
      if (uv == CGAL::EQUAL) continue;  // horizontal: the ray never crosses it
      const Point& lo = uv == CGAL::SMALLER ? u : v;
      const Point& hi = uv == CGAL::SMALLER ? v : u;
      if (CGAL::compare_y(lo, p) == CGAL::LARGER || CGAL::compare_y(p, hi) != CGAL::SMALLER) continue;
      if (CGAL::orientation(lo, hi, p) != CGAL::LEFT_TURN) continue;  // p right of the edge
      if (parity[e.loop] == 0) touched.push_back(e.loop);
      parity[e.loop] ^= 1;
    }
    for (const std::size_t l : touched) {
      if (parity[l] != 0) inside[i].push_back(l);
      parity[l] = 0;
    }
    std::sort(inside[i].begin(), inside[i].end());
  }
  return inside;
}

/// Checks that the loops of one body neither touch nor overlap and that every hole lies in
/// the body; returns the body as polygons with holes (each hole in its innermost outer).
std::vector<PolygonWithHoles> assemble_body(const BodyOutline& body,
                                            const std::vector<BodyLoop>& loops) {
  std::vector<const Polygon*> polygons;
  for (const BodyLoop& l : loops) polygons.push_back(&l.polygon);
  if (const auto contact = find_contact(polygons, false)) {
    // Name the hole when one is involved: it is the loop the user most likely misplaced.
    EdgeRef mine = contact->b, other = contact->a;
    if (loops[mine.loop].hole == false && loops[other.loop].hole) std::swap(mine, other);
    const BodyLoop& m = loops[mine.loop];
    const BodyLoop& o = loops[other.loop];
    fail(m.loop->where,
         std::string(m.hole ? "hole" : "outer boundary") + " touches or crosses " +
             (o.hole ? "hole " : "outer boundary ") + o.loop->where,
         "its edge " + std::to_string(mine.edge) + " meets edge " + std::to_string(other.edge) +
             " at " + format_point(contact->at));
  }

  // No two loops meet, so each is either inside or outside each other one, and one vertex
  // decides. The body's region at a point is (outers around it) - (holes around it): 1 inside
  // the body, 0 outside.
  std::vector<std::size_t> owner(loops.size(), loops.size());
  const std::vector<std::vector<std::size_t>> around = containing_loops(loops);
  std::vector<K::FT> area(loops.size());  // |area| of each outer, once (nested rings compare it often)
  for (std::size_t j = 0; j < loops.size(); ++j)
    if (!loops[j].hole) area[j] = CGAL::abs(loops[j].polygon.area());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const Point& p = loops[i].polygon[0];
    int outers_around = 0;
    int holes_around = 0;
    std::size_t innermost = loops.size();
    for (const std::size_t j : around[i]) {
      if (loops[j].hole) {
        ++holes_around;
      } else {
        ++outers_around;
        if (innermost == loops.size() || area[j] < area[innermost]) innermost = j;
      }
    }
    const int depth = outers_around - holes_around;
    const std::string vertex = "its vertex " + format_point(p);
    if (loops[i].hole) {
      if (outers_around == 0)
        fail(loops[i].loop->where, "hole is not inside an outer boundary of body '" + body.name + "'",
             vertex + " is outside");
      if (depth != 1) fail(loops[i].loop->where, "hole lies inside another hole", vertex);
      owner[i] = innermost;
    } else if (depth != 0) {
      fail(loops[i].loop->where, "outer boundary overlaps another outer boundary of body '" +
                                     body.name + "'",
           vertex + " is inside it");
    }
  }

  std::vector<PolygonWithHoles> result;
  std::vector<std::size_t> slot(loops.size(), 0);
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].hole) continue;
    slot[i] = result.size();
    result.emplace_back(loops[i].polygon);
  }
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].hole) result[slot[owner[i]]].add_hole(loops[i].polygon);
  }
  return result;
}

/// Total area of a set of polygons with holes [m^2].
double total_area(const std::vector<PolygonWithHoles>& parts) {
  double area = 0.0;
  for (const PolygonWithHoles& part : parts) {
    area += CGAL::to_double(part.outer_boundary().area());
    for (auto h = part.holes_begin(); h != part.holes_end(); ++h) area += CGAL::to_double(h->area());
  }
  return area;
}

/// The pairs of bodies (a < b; each body a list of parts) that may overlap: those whose edges
/// meet (a box search over every edge), and those whose boundaries are apart but one lies in
/// the other's region (a loop of one is then wholly inside the other's region or wholly
/// outside it, so one vertex per loop decides, by the rays of containing_loops). Testing every
/// pair whose boxes overlap took minutes on hundreds of nested islands.
std::set<std::pair<std::size_t, std::size_t>> bodies_that_may_overlap(
    const std::vector<std::vector<const PolygonWithHoles*>>& parts_of) {
  std::vector<BodyLoop> all;
  std::vector<std::size_t> body_of;
  for (std::size_t a = 0; a < parts_of.size(); ++a)
    for (const PolygonWithHoles* part : parts_of[a]) {
      all.push_back({nullptr, part->outer_boundary(), false});
      body_of.push_back(a);
      for (auto h = part->holes_begin(); h != part->holes_end(); ++h) {
        all.push_back({nullptr, *h, true});
        body_of.push_back(a);
      }
    }
  std::set<std::pair<std::size_t, std::size_t>> suspect;
  const auto add = [&](std::size_t a, std::size_t b) { suspect.insert({std::min(a, b), std::max(a, b)}); };
  std::vector<const Polygon*> polygons;
  for (const BodyLoop& l : all) polygons.push_back(&l.polygon);
  std::vector<EdgeRef> refs;
  std::vector<EdgeBox> boxes;
  edge_boxes(polygons, refs, boxes);
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const EdgeBox& x, const EdgeBox& y) {
    const EdgeRef& ex = refs[x.info()];
    const EdgeRef& ey = refs[y.info()];
    const std::size_t ba = body_of[ex.loop], bb = body_of[ey.loop];
    if (ba == bb || suspect.count({std::min(ba, bb), std::max(ba, bb)}) != 0) return;
    if (CGAL::do_intersect(polygons[ex.loop]->edge(ex.edge), polygons[ey.loop]->edge(ey.edge))) add(ba, bb);
  });
  const std::vector<std::vector<std::size_t>> around = containing_loops(all);
  std::vector<int> depth(parts_of.size(), 0);  // region of each body at the vertex: 1 inside
  for (std::size_t l = 0; l < all.size(); ++l) {
    for (const std::size_t j : around[l]) depth[body_of[j]] += all[j].hole ? -1 : 1;
    for (const std::size_t j : around[l])
      if (depth[body_of[j]] > 0 && body_of[j] != body_of[l]) add(body_of[j], body_of[l]);
    for (const std::size_t j : around[l]) depth[body_of[j]] = 0;
  }
  return suspect;
}

bool boxes_overlap(const CGAL::Bbox_2& a, const CGAL::Bbox_2& b) {
  return a.xmin() < b.xmax() && b.xmin() < a.xmax() && a.ymin() < b.ymax() && b.ymin() < a.ymax();
}

}  // namespace

void validate_and_orient(Outline& outline) {
  struct BodyParts {
    std::vector<PolygonWithHoles> parts;
    std::vector<CGAL::Bbox_2> box;  ///< of each part's outer boundary, computed once
    std::vector<const Loop*> outer_of_part;
  };
  std::vector<BodyParts> bodies;
  for (const BodyOutline& body : outline.bodies) {
    for (const auto* loops : {&body.outers, &body.holes})
      for (const Loop& loop : *loops)
        for (const Vec2& p : loop.points)
          if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate))
            fail(loop.where, "coordinate out of range: |x| and |y| must be at most " +
                                 format_number(kMaxCoordinate) + " m",
                 format_point(p.x, p.y));
  }
  for (BodyOutline& body : outline.bodies) {
    if (body.outers.empty())
      fail(body.where, "body has no outer boundary",
           std::to_string(body.holes.size()) + " holes");
    std::vector<BodyLoop> loops;
    for (Loop& loop : body.outers) loops.push_back({&loop, prepare_loop(loop, false), false});
    for (Loop& loop : body.holes) loops.push_back({&loop, prepare_loop(loop, true), true});
    BodyParts parts;
    parts.parts = assemble_body(body, loops);
    for (const PolygonWithHoles& part : parts.parts) parts.box.push_back(part.outer_boundary().bbox());
    for (const BodyLoop& l : loops) {
      if (!l.hole) parts.outer_of_part.push_back(l.loop);
    }
    bodies.push_back(std::move(parts));
  }

  // Bodies may touch (share boundary) but must not overlap: the regularized intersection
  // of any two must have zero area. The exact test (a Boolean operation per pair of parts)
  // runs only on the pairs that can overlap (bodies_that_may_overlap).
  std::vector<std::vector<const PolygonWithHoles*>> parts_of(bodies.size());
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (const PolygonWithHoles& part : bodies[a].parts) parts_of[a].push_back(&part);
  for (const auto& [a, b] : bodies_that_may_overlap(parts_of)) {
    for (std::size_t i = 0; i < bodies[a].parts.size(); ++i) {
      for (std::size_t j = 0; j < bodies[b].parts.size(); ++j) {
        const PolygonWithHoles& pa = bodies[a].parts[i];
        const PolygonWithHoles& pb = bodies[b].parts[j];
        if (!boxes_overlap(bodies[a].box[i], bodies[b].box[j])) continue;
        if (!CGAL::do_intersect(pa, pb)) continue;
        std::vector<PolygonWithHoles> overlap;
        CGAL::intersection(pa, pb, std::back_inserter(overlap));
        fail(bodies[b].outer_of_part[j]->where,
             "overlaps " + bodies[a].outer_of_part[i]->where,
             "overlap area " + format_number(total_area(overlap)) + " m^2, one corner at " +
                 format_point(overlap.front().outer_boundary()[0]));
      }
    }
  }
}

}  // namespace hexdem::meshing
