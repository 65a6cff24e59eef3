// Lattice generator: fills outlines with disks and semi-disks on a hexagonal lattice.
// Ref: Liu, Gao, Tanimura (2004), Section 2 and Eq. 9; physics.md section 1.
#include "hexdem/meshing/lattice_generator.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "hexdem/error.hpp"
#include "hexdem/meshing/text.hpp"

namespace hexdem::meshing {
namespace {

constexpr double kSqrt3 = 1.7320508075688772935;
constexpr double kPi = 3.14159265358979323846;

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
Vec2 sub(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 add(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 scale(Vec2 a, double s) { return {a.x * s, a.y * s}; }
double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

/// Distance from p to the segment [a, b].
double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = sub(b, a);
  const double len2 = dot(ab, ab);
  double t = len2 > 0 ? dot(sub(p, a), ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const Vec2 q = add(a, scale(ab, t));
  return std::hypot(p.x - q.x, p.y - q.y);
}

/// The lattice of one body. Lattice frame: x along the lattice axis, origin at a lattice
/// point. Lattice point (j, i): X = i d + (j odd ? r : 0), Y = j h, with d = 2r, h = sqrt(3) r.
struct Frame {
  double r = 0, d = 0, h = 0;
  double hex_circumradius = 0;  ///< 2r/sqrt(3): centre to hexagon vertex
  double hex_area = 0;          ///< 2 sqrt(3) r^2 (Eq. 9)
  double cos_t = 1, sin_t = 0;
  Vec2 origin;

  Frame(double radius, double angle_deg, Vec2 o) : r(radius), origin(o) {
    d = 2 * r;
    h = kSqrt3 * r;
    hex_circumradius = 2 * r / kSqrt3;
    hex_area = 2 * kSqrt3 * r * r;
    const double t = angle_deg * kPi / 180.0;
    cos_t = std::cos(t);
    sin_t = std::sin(t);
  }
  [[nodiscard]] Vec2 to_lattice(Vec2 p) const {
    const Vec2 q = sub(p, origin);
    return {cos_t * q.x + sin_t * q.y, -sin_t * q.x + cos_t * q.y};
  }
  [[nodiscard]] Vec2 to_global(Vec2 q) const {
    return {origin.x + cos_t * q.x - sin_t * q.y, origin.y + sin_t * q.x + cos_t * q.y};
  }
  [[nodiscard]] double row_y(std::int64_t j) const { return static_cast<double>(j) * h; }
  [[nodiscard]] double col_offset(std::int64_t j) const { return (j & 1) ? r : 0.0; }
  [[nodiscard]] Vec2 point(std::int64_t j, std::int64_t i) const {
    return {static_cast<double>(i) * d + col_offset(j), row_y(j)};
  }
};

/// An outline edge in the lattice frame. `a`, `b` are shifted by a tiny generic offset
/// (see kPerturbation) so that no lattice point or hexagon vertex lies exactly on an edge;
/// `a0`, `b0` are the true positions, used for the tolerance tests.
struct Edge {
  Vec2 a, b;
  Vec2 a0, b0;
  std::int32_t set = -1;
  bool neat = false;
};

/// Symbolic-perturbation offset of the outline, in units of d. Region edges that pass exactly
/// through lattice points or hexagon vertices (common: outlines drawn on lattice rows) would
/// make inside/outside decisions ambiguous; shifting the outline by a generic 1e-7 d removes
/// every such tie while changing areas by ~1e-7 relative. Decisions that must respect the true
/// outline (semi-disks on neat edges, points on the boundary) use a0/b0 with kTolerance.
constexpr double kPerturbX = 0.75487766624669276e-7;
constexpr double kPerturbY = 0.56984029099805327e-7;
/// Geometric tolerance in units of d (lattice_generator.hpp).
constexpr double kTolerance = kBoundaryTolerance;

/// A lattice point whose hexagon meets the outline.
struct BoundaryPoint {
  std::int32_t j = 0, i = 0;
  std::int32_t edge_begin = 0, edge_end = 0;  ///< range in local_edges
  bool inside_scan = false;   ///< centre inside the (perturbed) region
  bool inside = false;        ///< becomes a disk (inside_scan or on the true boundary)
  bool semi = false;          ///< on a neat edge
  double area = 0;            ///< area of hexagon intersected with the region
  double mx = 0, my = 0;      ///< first moments of that area about the lattice point
  std::int32_t face_begin = 0, face_end = 0;  ///< range in faces
  std::int64_t disk = -1;     ///< disk that owns the area (self, or the receiver of an orphan)
};

/// Length of a named outline edge lying on a cell boundary.
struct Face {
  std::int32_t set;
  std::int32_t edge;  ///< the outline edge (index into edges_)
  double length;
  double nx, ny;  ///< length times outward unit normal (lattice frame)
  double mx, my;  ///< length times the face's midpoint (lattice frame)
};

struct Run {
  std::int32_t i0, i1;   ///< inclusive lattice column range
  std::int64_t first_id; ///< disk id of column i0
};

class BodyFiller {
public:
  BodyFiller(const BodyOutline& body, std::int32_t body_index, GeometryMode mode, Lattice& out,
             GeneratorReport& report)
      : body_(body), body_index_(body_index), mode_(mode), out_(out), report_(report),
        f_(*body.radius, body.angle_deg.value_or(0.0), body.origin.value_or(Vec2{})) {}

  void fill() {
    build_edges();
    build_rows();
    collect_boundary_points();
    clip_boundary_cells();
    create_disks();
    assign_orphans();
    create_bonds();
    collect_sets();
  }

private:
  const BodyOutline& body_;
  std::int32_t body_index_;
  GeometryMode mode_;
  Lattice& out_;
  GeneratorReport& report_;
  Frame f_;

  std::vector<Edge> edges_;
  double region_area_ = 0;
  std::int64_t jmin_ = 0, jmax_ = -1;
  std::vector<std::int64_t> cross_offset_;  ///< per row: crossings (CSR), sorted
  std::vector<double> cross_x_;
  std::vector<BoundaryPoint> bpoints_;      ///< sorted by (j, i)
  std::vector<std::int32_t> local_edges_;
  std::vector<Face> faces_;
  std::vector<std::int64_t> run_offset_;    ///< per row: disk runs (CSR)
  std::vector<Run> runs_;
  std::int64_t first_disk_ = 0;
  std::vector<std::int32_t> bpoint_of_disk_;  ///< per disk of this body: index in bpoints_ or -1
  std::vector<std::vector<Face>> extra_faces_;  ///< faces of orphans, per receiving bpoint

  // ---- set-up --------------------------------------------------------------------------
  void build_edges() {
    const double d = f_.d;
    const Vec2 delta{kPerturbX * d, kPerturbY * d};
    auto add_loop = [&](const Loop& loop) {
      const std::size_t n = loop.points.size();
      region_area_ += signed_area(loop);
      for (std::size_t k = 0; k < n; ++k) {
        Edge e;
        e.a0 = f_.to_lattice(loop.points[k]);
        e.b0 = f_.to_lattice(loop.points[(k + 1) % n]);
        e.a = add(e.a0, delta);
        e.b = add(e.b0, delta);
        e.set = k < loop.edge_set.size() ? loop.edge_set[k] : -1;
        const bool straight = k < loop.edge_straight.size() ? loop.edge_straight[k] != 0 : true;
        e.neat = straight && is_neat(e.a0, e.b0);
        edges_.push_back(e);
      }
    };
    for (const Loop& l : body_.outers) add_loop(l);
    for (const Loop& l : body_.holes) add_loop(l);

    // The region's extent, perturbed (the rows below) and unperturbed (w, h: its size, which
    // the perturbation, a fraction of d, swamps for a region far smaller than d).
    double ymin = std::numeric_limits<double>::infinity(), ymax = -ymin;
    double xmin = ymin, xmax = -ymin;
    double w_min = ymin, w_max = -ymin, h_min = ymin, h_max = -ymin;
    for (const Edge& e : edges_) {
      ymin = std::min({ymin, e.a.y, e.b.y});
      ymax = std::max({ymax, e.a.y, e.b.y});
      xmin = std::min({xmin, e.a.x, e.b.x});
      xmax = std::max({xmax, e.a.x, e.b.x});
      w_min = std::min({w_min, e.a0.x, e.b0.x});
      w_max = std::max({w_max, e.a0.x, e.b0.x});
      h_min = std::min({h_min, e.a0.y, e.b0.y});
      h_max = std::max({h_max, e.a0.y, e.b0.y});
    }
    // A region narrower than one disk in every lattice direction cannot hold a disk.
    if (std::min(xmax - xmin, ymax - ymin) < d || std::min(w_max - w_min, h_max - h_min) < d) {
      throw InputError(body_.where + ": disk radius " + fmt(f_.r) +
                       " m is too large for the region (" + fmt(w_max - w_min) + " x " +
                       fmt(h_max - h_min) + " m in the lattice frame)");
    }
    jmin_ = static_cast<std::int64_t>(std::floor((ymin - f_.hex_circumradius) / f_.h)) - 1;
    jmax_ = static_cast<std::int64_t>(std::ceil((ymax + f_.hex_circumradius) / f_.h)) + 1;
  }

  /// True if the segment lies (within tolerance) on one lattice line: a row (0 deg) or one of
  /// the 60 / 120 degree lines through lattice points.
  [[nodiscard]] bool is_neat(Vec2 a, Vec2 b) const {
    // Oblique coordinates: p = u (d, 0) + v (r, h).
    auto coords = [&](Vec2 p) {
      const double v = p.y / f_.h;
      const double u = (p.x - v * f_.r) / f_.d;
      return std::array<double, 3>{v, u, u + v};
    };
    const auto ca = coords(a), cb = coords(b);
    const double tol = kTolerance * f_.d / f_.h;  // line spacing is h in all three families
    for (int fam = 0; fam < 3; ++fam) {
      const double na = std::round(ca[fam]), nb = std::round(cb[fam]);
      if (na == nb && std::abs(ca[fam] - na) < tol && std::abs(cb[fam] - nb) < tol) return true;
    }
    return false;
  }

  /// Crossings of every row with the (perturbed) outline, half-open rule, sorted per row.
  void build_rows() {
    const std::int64_t nrows = jmax_ - jmin_ + 1;
    std::vector<std::int32_t> order(edges_.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<std::int32_t>(k);
    auto ylo = [&](std::int32_t k) { return std::min(edges_[k].a.y, edges_[k].b.y); };
    std::sort(order.begin(), order.end(), [&](auto p, auto q) { return ylo(p) < ylo(q); });

    cross_offset_.assign(nrows + 1, 0);
    cross_x_.clear();
    std::vector<std::int32_t> active;
    std::size_t next = 0;
    for (std::int64_t row = 0; row < nrows; ++row) {
      const double y = f_.row_y(jmin_ + row);
      while (next < order.size() && ylo(order[next]) <= y) active.push_back(order[next++]);
      std::size_t keep = 0;
      const auto first = static_cast<std::ptrdiff_t>(cross_x_.size());
      for (std::int32_t k : active) {
        const Edge& e = edges_[k];
        const double lo = std::min(e.a.y, e.b.y), hi = std::max(e.a.y, e.b.y);
        if (hi <= y) continue;  // finished: drop from the active list
        active[keep++] = k;
        if (lo <= y && y < hi) {
          cross_x_.push_back(e.a.x + (y - e.a.y) * (e.b.x - e.a.x) / (e.b.y - e.a.y));
        }
      }
      active.resize(keep);
      std::sort(cross_x_.begin() + first, cross_x_.end());
      cross_offset_[row + 1] = static_cast<std::int64_t>(cross_x_.size());
    }
  }

  [[nodiscard]] bool inside_scan(std::int64_t j, double x) const {
    const std::int64_t row = j - jmin_;
    if (row < 0 || row >= jmax_ - jmin_ + 1) return false;
    const auto b = cross_x_.begin() + cross_offset_[row];
    const auto e = cross_x_.begin() + cross_offset_[row + 1];
    return ((std::upper_bound(b, e, x) - b) & 1) != 0;
  }

  /// Every lattice point within the hexagon circumradius of an edge, with its edges.
  void collect_boundary_points() {
    struct Hit { std::int32_t j, i, edge; };
    std::vector<Hit> hits;
    const double R = f_.hex_circumradius * (1 + 1e-9);
    for (std::size_t k = 0; k < edges_.size(); ++k) {
      const Edge& e = edges_[k];
      const double ylo = std::min(e.a.y, e.b.y) - R, yhi = std::max(e.a.y, e.b.y) + R;
      const auto j0 = static_cast<std::int64_t>(std::ceil(ylo / f_.h));
      const auto j1 = static_cast<std::int64_t>(std::floor(yhi / f_.h));
      for (std::int64_t j = j0; j <= j1; ++j) {
        const double y = f_.row_y(j);
        // x-range of the part of the segment within the band |Y - y| <= R.
        double t0 = 0, t1 = 1;
        const double dy = e.b.y - e.a.y;
        if (std::abs(dy) > 0) {
          double ta = (y - R - e.a.y) / dy, tb = (y + R - e.a.y) / dy;
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          if (t0 > t1) continue;
        }
        const double xa = e.a.x + t0 * (e.b.x - e.a.x), xb = e.a.x + t1 * (e.b.x - e.a.x);
        const double off = f_.col_offset(j);
        const auto i0 = static_cast<std::int64_t>(std::ceil((std::min(xa, xb) - R - off) / f_.d));
        const auto i1 = static_cast<std::int64_t>(std::floor((std::max(xa, xb) + R - off) / f_.d));
        for (std::int64_t i = i0; i <= i1; ++i) {
          if (segment_distance(f_.point(j, i), e.a, e.b) <= R) {
            hits.push_back({static_cast<std::int32_t>(j), static_cast<std::int32_t>(i),
                            static_cast<std::int32_t>(k)});
          }
        }
      }
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& p, const Hit& q) {
      return p.j != q.j ? p.j < q.j : (p.i != q.i ? p.i < q.i : p.edge < q.edge);
    });
    local_edges_.resize(hits.size());
    for (std::size_t k = 0; k < hits.size(); ++k) {
      local_edges_[k] = hits[k].edge;
      if (k == 0 || hits[k].j != hits[k - 1].j || hits[k].i != hits[k - 1].i) {
        BoundaryPoint bp;
        bp.j = hits[k].j;
        bp.i = hits[k].i;
        bp.edge_begin = static_cast<std::int32_t>(k);
        bpoints_.push_back(bp);
      }
      bpoints_.back().edge_end = static_cast<std::int32_t>(k + 1);
    }
  }

  // ---- boundary cells -------------------------------------------------------------------
  /// Clips each boundary point's hexagon by the region: area and first moments by Green's
  /// theorem over the boundary of (hexagon intersected with region), which consists of the
  /// region's edges inside the hexagon and the hexagon's sides inside the region. Vertex
  /// states come from the centre state and the crossings of the centre-vertex segments.
  void clip_boundary_cells() {
    const double r = f_.r, R = f_.hex_circumradius;
    const double tol = kTolerance * f_.d;
    std::array<Vec2, 6> hv{};   // hexagon vertices relative to the centre, CCW from 30 deg
    std::array<Vec2, 6> hn{};   // outward face normals, face k between vertices k-1 and k
    for (int k = 0; k < 6; ++k) {
      const double av = (30.0 + 60.0 * k) * kPi / 180.0, an = (60.0 * k) * kPi / 180.0;
      hv[k] = {R * std::cos(av), R * std::sin(av)};
      hn[k] = {std::cos(an), std::sin(an)};
    }
    std::vector<double> ts;
    for (BoundaryPoint& bp : bpoints_) {
      const Vec2 c = f_.point(bp.j, bp.i);
      bp.inside_scan = inside_scan(bp.j, c.x);
      // Tolerance tests against the true outline.
      double dmin = std::numeric_limits<double>::infinity();
      bool near_neat = false;
      for (std::int32_t q = bp.edge_begin; q < bp.edge_end; ++q) {
        const Edge& e = edges_[local_edges_[q]];
        const double dist = segment_distance(c, e.a0, e.b0);
        dmin = std::min(dmin, dist);
        if (e.neat && dist < tol) near_neat = true;
      }
      bp.inside = bp.inside_scan || dmin < tol;
      bp.semi = bp.inside && near_neat;

      // Green's theorem sums relative to c: A = 1/2 sum p x q, M = 1/6 sum (p + q)(p x q).
      double area2 = 0, mx6 = 0, my6 = 0;
      auto segment = [&](Vec2 p, Vec2 q) {
        const double w = cross(p, q);
        area2 += w;
        mx6 += (p.x + q.x) * w;
        my6 += (p.y + q.y) * w;
      };
      bp.face_begin = static_cast<std::int32_t>(faces_.size());
      // (a) region edges clipped to the hexagon (Liang-Barsky against the six half-planes).
      for (std::int32_t q = bp.edge_begin; q < bp.edge_end; ++q) {
        const Edge& e = edges_[local_edges_[q]];
        const Vec2 a = sub(e.a, c), ab = sub(e.b, e.a);
        double t0 = 0, t1 = 1;
        bool empty = false;
        for (int k = 0; k < 6 && !empty; ++k) {
          const double num = r - dot(hn[k], a), den = dot(hn[k], ab);
          if (den == 0) {
            empty = num < 0;
          } else if (den > 0) {
            t1 = std::min(t1, num / den);
          } else {
            t0 = std::max(t0, num / den);
          }
          if (t0 >= t1) empty = true;
        }
        if (empty) continue;
        const Vec2 p = add(a, scale(ab, t0)), qq = add(a, scale(ab, t1));
        segment(p, qq);
        if (e.set >= 0) {
          const double len = std::hypot(ab.x, ab.y);
          const double l = (t1 - t0) * len;
          // Region interior is on the left of every edge: outward normal is on the right.
          const Vec2 mid = add(c, scale(add(p, qq), 0.5));
          faces_.push_back({e.set, local_edges_[q], l, l * ab.y / len, -l * ab.x / len, l * mid.x, l * mid.y});
        }
      }
      bp.face_end = static_cast<std::int32_t>(faces_.size());
      // (b) hexagon sides inside the region.
      std::array<bool, 6> vin{};
      for (int k = 0; k < 6; ++k) {
        vin[k] = bp.inside_scan ^ (crossings(bp, c, add(c, hv[k]), nullptr) & 1);
      }
      for (int k = 0; k < 6; ++k) {
        const Vec2 p = add(c, hv[k]), q = add(c, hv[(k + 1) % 6]);
        ts.clear();
        crossings(bp, p, q, &ts);
        std::sort(ts.begin(), ts.end());
        bool in = vin[k];
        double t_prev = 0;
        ts.push_back(1.0);
        for (double t : ts) {
          if (in) segment(add(hv[k], scale(sub(hv[(k + 1) % 6], hv[k]), t_prev)),
                          add(hv[k], scale(sub(hv[(k + 1) % 6], hv[k]), t)));
          in = !in;
          t_prev = t;
        }
      }
      bp.area = 0.5 * area2;
      bp.mx = mx6 / 6.0;
      bp.my = my6 / 6.0;
      // Guard against round-off: a clipped cell lies between 0 and the full hexagon.
      if (bp.area < 0) bp.area = 0;
      if (bp.area > f_.hex_area) bp.area = f_.hex_area;
    }
  }

  /// Number of crossings of segment [p, q] with the point's local edges (edge parameter
  /// half-open [0, 1) so that a shared vertex counts once); parameters along [p, q] appended
  /// to `ts` if given.
  int crossings(const BoundaryPoint& bp, Vec2 p, Vec2 q,
                std::vector<double>* ts) const {
    int n = 0;
    const Vec2 pq = sub(q, p);
    for (std::int32_t k = bp.edge_begin; k < bp.edge_end; ++k) {
      const Edge& e = edges_[local_edges_[k]];
      const Vec2 ab = sub(e.b, e.a);
      const double den = cross(pq, ab);
      if (den == 0) continue;
      const Vec2 ap = sub(e.a, p);
      const double t = cross(ap, ab) / den;
      const double s = cross(ap, pq) / den;
      if (t >= 0 && t < 1 && s >= 0 && s < 1) {
        ++n;
        if (ts) ts->push_back(t);
      }
    }
    return n;
  }

  [[nodiscard]] const BoundaryPoint* find_bpoint(std::int64_t j, std::int64_t i) const {
    auto it = std::lower_bound(bpoints_.begin(), bpoints_.end(), std::make_pair(j, i),
                               [](const BoundaryPoint& b, const std::pair<std::int64_t, std::int64_t>& k) {
                                 return b.j != k.first ? b.j < k.first : b.i < k.second;
                               });
    if (it != bpoints_.end() && it->j == j && it->i == i) return &*it;
    return nullptr;
  }

  // ---- disks ----------------------------------------------------------------------------
  void create_disks() {
    const std::int64_t nrows = jmax_ - jmin_ + 1;
    run_offset_.assign(nrows + 1, 0);
    first_disk_ = static_cast<std::int64_t>(out_.x.size());
    std::int64_t next_id = first_disk_;
    std::size_t bp = 0;
    std::vector<std::int32_t> cols;
    for (std::int64_t row = 0; row < nrows; ++row) {
      const std::int64_t j = jmin_ + row;
      const double off = f_.col_offset(j);
      // Runs from the crossings: lattice columns strictly between pairs of crossings.
      std::vector<Run> row_runs;
      for (std::int64_t k = cross_offset_[row]; k + 1 < cross_offset_[row + 1]; k += 2) {
        const auto i0 = static_cast<std::int64_t>(std::ceil((cross_x_[k] - off) / f_.d));
        const auto i1 = static_cast<std::int64_t>(std::floor((cross_x_[k + 1] - off) / f_.d));
        if (i0 <= i1) row_runs.push_back({static_cast<std::int32_t>(i0), static_cast<std::int32_t>(i1), 0});
      }
      // Boundary points of this row decide for themselves (tolerance may add some).
      cols.clear();
      while (bp < bpoints_.size() && bpoints_[bp].j < j) ++bp;
      std::size_t bp_end = bp;
      while (bp_end < bpoints_.size() && bpoints_[bp_end].j == j) {
        if (bpoints_[bp_end].inside) cols.push_back(bpoints_[bp_end].i);
        ++bp_end;
      }
      std::vector<Run> merged;
      merge_runs(row_runs, cols, merged);
      run_offset_[row] = static_cast<std::int64_t>(runs_.size());
      for (Run& run : merged) {
        run.first_id = next_id;
        runs_.push_back(run);
        for (std::int32_t i = run.i0; i <= run.i1; ++i) add_disk(f_.point(j, i));
        next_id += run.i1 - run.i0 + 1;
      }
      bp = bp_end;
    }
    run_offset_[nrows] = static_cast<std::int64_t>(runs_.size());
    const std::int64_t ndisks = next_id - first_disk_;
    if (ndisks == 0) {
      throw InputError(body_.where + ": no disk fits: disk radius " + fmt(f_.r) +
                       " m is too large for the region");
    }
    // Boundary cells.
    bpoint_of_disk_.assign(static_cast<std::size_t>(ndisks), -1);
    extra_faces_.assign(bpoints_.size(), {});
    for (std::size_t k = 0; k < bpoints_.size(); ++k) {
      BoundaryPoint& b = bpoints_[k];
      if (!b.inside) continue;
      b.disk = lookup(b.j, b.i);
      HEXDEM_VERIFY(b.disk >= 0, "boundary disk not created");
      bpoint_of_disk_[b.disk - first_disk_] = static_cast<std::int32_t>(k);
      set_cell(b.disk, b.area, b.mx, b.my, f_.point(b.j, b.i));
      if (b.semi) out_.kind[b.disk] = static_cast<std::uint8_t>(DiskKind::SemiDisk);
    }
  }

  static void merge_runs(const std::vector<Run>& runs, const std::vector<std::int32_t>& cols,
                         std::vector<Run>& merged) {
    std::vector<Run> all = runs;
    for (std::int32_t c : cols) all.push_back({c, c, 0});
    std::sort(all.begin(), all.end(), [](const Run& a, const Run& b) { return a.i0 < b.i0; });
    for (const Run& r : all) {
      if (!merged.empty() && r.i0 <= merged.back().i1 + 1) {
        merged.back().i1 = std::max(merged.back().i1, r.i1);
      } else {
        merged.push_back(r);
      }
    }
  }

  void add_disk(Vec2 p) {
    const Vec2 g = f_.to_global(p);
    out_.x.push_back(g.x);
    out_.y.push_back(g.y);
    out_.radius.push_back(f_.r);
    out_.cell_area.push_back(f_.hex_area);
    out_.cell_cx.push_back(g.x);
    out_.cell_cy.push_back(g.y);
    out_.kind.push_back(static_cast<std::uint8_t>(DiskKind::Disk));
    out_.body.push_back(body_index_);
    out_.material.push_back(body_.material);
  }

  /// Sets a disk's cell from an area and first moments about lattice point c (lattice frame).
  void set_cell(std::int64_t disk, double area, double mx, double my, Vec2 c) {
    out_.cell_area[disk] = area;
    const Vec2 centroid = area > 0 ? Vec2{c.x + mx / area, c.y + my / area} : c;
    const Vec2 g = f_.to_global(centroid);
    out_.cell_cx[disk] = g.x;
    out_.cell_cy[disk] = g.y;
  }

  [[nodiscard]] std::int64_t lookup(std::int64_t j, std::int64_t i) const {
    const std::int64_t row = j - jmin_;
    if (row < 0 || row > jmax_ - jmin_) return -1;
    const auto b = runs_.begin() + run_offset_[row], e = runs_.begin() + run_offset_[row + 1];
    auto it = std::upper_bound(b, e, i, [](std::int64_t v, const Run& r) { return v < r.i0; });
    if (it == b) return -1;
    --it;
    return i <= it->i1 ? it->first_id + (i - it->i0) : -1;
  }

  /// Region pieces in the hexagons of lattice points outside the region are given to the
  /// inside lattice neighbour nearest to the piece's centroid (first ring, then second).
  void assign_orphans() {
    static constexpr std::array<std::array<int, 2>, 6> ring1_even{{{0, 1}, {0, -1}, {1, 0}, {1, -1}, {-1, 0}, {-1, -1}}};
    static constexpr std::array<std::array<int, 2>, 6> ring1_odd{{{0, 1}, {0, -1}, {1, 1}, {1, 0}, {-1, 1}, {-1, 0}}};
    const double tiny = 1e-12 * f_.hex_area;
    for (BoundaryPoint& b : bpoints_) {
      if (b.inside || b.area <= tiny) continue;
      const Vec2 c = f_.point(b.j, b.i);
      const Vec2 centroid{c.x + b.mx / b.area, c.y + b.my / b.area};
      std::int64_t best = -1;
      double best_d = std::numeric_limits<double>::infinity();
      auto consider = [&](std::int64_t jj, std::int64_t ii) {
        const std::int64_t id = lookup(jj, ii);
        if (id < 0) return;
        const Vec2 p = f_.point(jj, ii);
        const double dist = std::hypot(p.x - centroid.x, p.y - centroid.y);
        if (dist < best_d) { best_d = dist; best = id; }
      };
      const auto& ring = (b.j & 1) ? ring1_odd : ring1_even;
      for (const auto& o : ring) consider(b.j + o[0], b.i + o[1]);
      if (best < 0) {  // second ring: every lattice point within 2d
        for (std::int64_t dj = -2; dj <= 2; ++dj)
          for (std::int64_t di = -3; di <= 3; ++di) {
            const Vec2 p = f_.point(b.j + dj, b.i + di);
            if (std::hypot(p.x - c.x, p.y - c.y) <= 2 * f_.d * (1 + 1e-9)) consider(b.j + dj, b.i + di);
          }
      }
      if (best < 0) {
        report_.lost_area += b.area;
        continue;
      }
      b.disk = best;
      // Merge area and moments into the receiving cell (moments about its own centre).
      const std::int32_t recv = bpoint_of_disk_[best - first_disk_];
      const Vec2 rc = f_.to_lattice({out_.x[best], out_.y[best]});
      const double a_old = out_.cell_area[best];
      const Vec2 cen_old = f_.to_lattice({out_.cell_cx[best], out_.cell_cy[best]});
      const double a_new = a_old + b.area;
      const Vec2 cen_new{(cen_old.x * a_old + centroid.x * b.area) / a_new,
                         (cen_old.y * a_old + centroid.y * b.area) / a_new};
      set_cell(best, a_new, (cen_new.x - rc.x) * a_new, (cen_new.y - rc.y) * a_new, rc);
      if (recv >= 0) {
        for (std::int32_t q = b.face_begin; q < b.face_end; ++q) extra_faces_[recv].push_back(faces_[q]);
      } else {
        // An interior disk received an orphan (only possible with very thin region parts):
        // record it as a boundary point of its own so that its faces are kept.
        orphan_faces_interior_.push_back({best, b.face_begin, b.face_end});
      }
    }
  }

  struct InteriorFaces { std::int64_t disk; std::int32_t begin, end; };
  std::vector<InteriorFaces> orphan_faces_interior_;

  // ---- bonds ----------------------------------------------------------------------------
  /// True if the bond between lattice points p and q clearly crosses an outline edge: its
  /// ends lie on opposite sides of the edge's (true) line, farther than the tolerance, and the
  /// crossing is inside the edge, not at a vertex (a bond may touch a reflex corner). Only
  /// boundary points can have such bonds: an edge crossing a bond lies within d/2 of one end.
  [[nodiscard]] bool bond_blocked(std::int32_t bp_a, std::int32_t bp_b, Vec2 p, Vec2 q) const {
    const double tol = kTolerance * f_.d;
    for (std::int32_t which : {bp_a, bp_b}) {
      if (which < 0) continue;
      const BoundaryPoint& bp = bpoints_[which];
      for (std::int32_t k = bp.edge_begin; k < bp.edge_end; ++k) {
        const Edge& e = edges_[local_edges_[k]];
        const Vec2 ab = sub(e.b0, e.a0);
        const double len = std::hypot(ab.x, ab.y);
        if (len == 0) continue;
        const double dp = cross(ab, sub(p, e.a0)) / len, dq = cross(ab, sub(q, e.a0)) / len;
        if (dp * dq >= 0 || std::abs(dp) < tol || std::abs(dq) < tol) continue;
        const Vec2 pq = sub(q, p);
        const double s = cross(sub(p, e.a0), pq) / cross(ab, pq);
        if (s > 1e-9 && s < 1 - 1e-9) return true;
      }
    }
    return false;
  }

  /// True if the bond p-q lies on a neat outline edge (both ends on it): such a bond has
  /// only half its tributary area inside the region.
  [[nodiscard]] bool along_neat_edge(std::int32_t bp, Vec2 p, Vec2 q) const {
    const BoundaryPoint& b = bpoints_[bp];
    if (!b.semi) return false;
    const double tol = kTolerance * f_.d;
    for (std::int32_t k = b.edge_begin; k < b.edge_end; ++k) {
      const Edge& e = edges_[local_edges_[k]];
      if (e.neat && segment_distance(p, e.a0, e.b0) < tol && segment_distance(q, e.a0, e.b0) < tol) return true;
    }
    return false;
  }

  void create_bonds() {
    const std::int64_t nrows = jmax_ - jmin_ + 1;
    for (std::int64_t row = 0; row < nrows; ++row) {
      const std::int64_t j = jmin_ + row;
      const std::int64_t par = j & 1;
      for (std::int64_t k = run_offset_[row]; k < run_offset_[row + 1]; ++k) {
        const Run run = runs_[k];
        for (std::int64_t i = run.i0; i <= run.i1; ++i) {
          const std::int64_t a = run.first_id + (i - run.i0);
          const std::int32_t bpa = bpoint_of_disk_[a - first_disk_];
          const Vec2 pa = f_.point(j, i);
          const std::array<std::array<std::int64_t, 3>, 3> nbrs{{{j, i + 1, 1},
                                                                 {j + 1, i + par, 2},
                                                                 {j + 1, i + par - 1, 2}}};
          for (const auto& nb : nbrs) {
            const std::int64_t b = lookup(nb[0], nb[1]);
            if (b < 0) continue;
            const std::int32_t bpb = bpoint_of_disk_[b - first_disk_];
            if ((bpa >= 0 || bpb >= 0) && bond_blocked(bpa, bpb, pa, f_.point(nb[0], nb[1]))) continue;
            out_.bond_i.push_back(static_cast<std::int32_t>(a));
            out_.bond_j.push_back(static_cast<std::int32_t>(b));
            out_.bond_class.push_back(static_cast<std::uint8_t>(nb[2]));
            out_.bond_on_edge.push_back(bpa >= 0 && bpb >= 0 &&
                                        along_neat_edge(bpa, pa, f_.point(nb[0], nb[1])));
            if (mode_ == GeometryMode::Axisymmetric) out_.bond_b.push_back(0.5 * (out_.x[a] + out_.x[b]));
          }
        }
      }
    }
  }

  // ---- boundary sets --------------------------------------------------------------------
  struct SetEntry { std::int32_t set; std::int32_t disk; double length, nx, ny, distance, mx, my; };
  std::vector<SetEntry> set_entries_;

  void collect_sets() {
    auto add_face = [&](std::int64_t disk, const Face& fc) {
      // Normal back to the global frame.
      const Vec2 n{f_.cos_t * fc.nx - f_.sin_t * fc.ny, f_.sin_t * fc.nx + f_.cos_t * fc.ny};
      // Distance from the disk centre to the (true) edge, for boundary conditions.
      const Edge& e = edges_[fc.edge];
      const double dist = segment_distance(f_.to_lattice({out_.x[disk], out_.y[disk]}), e.a0, e.b0);
      const Vec2 mid = fc.length > 0 ? f_.to_global({fc.mx / fc.length, fc.my / fc.length}) : Vec2{};
      set_entries_.push_back({fc.set, static_cast<std::int32_t>(disk), fc.length, n.x, n.y, dist,
                              fc.length * mid.x, fc.length * mid.y});
    };
    for (std::size_t k = 0; k < bpoints_.size(); ++k) {
      const BoundaryPoint& b = bpoints_[k];
      if (!b.inside) continue;
      for (std::int32_t q = b.face_begin; q < b.face_end; ++q) add_face(b.disk, faces_[q]);
      for (const Face& fc : extra_faces_[k]) add_face(b.disk, fc);
    }
    for (const InteriorFaces& inf : orphan_faces_interior_)
      for (std::int32_t q = inf.begin; q < inf.end; ++q) add_face(inf.disk, faces_[q]);
  }

public:
  [[nodiscard]] double region_area() const { return region_area_; }
  [[nodiscard]] const std::vector<SetEntry>& set_entries() const { return set_entries_; }
};

}  // namespace

namespace {

BodyOutline resolved_body(const BodyOutline& in, const GeneratorOptions& options) {
  BodyOutline body = in;
  if (!body.radius) body.radius = options.lattice.radius;
  if (!body.angle_deg) body.angle_deg = options.lattice.angle_deg;
  if (!body.origin) body.origin = options.lattice.origin;
  if (!(*body.radius > 0) || !std::isfinite(*body.radius)) {
    throw InputError(body.where + ": disk radius must be > 0 (got " + fmt(*body.radius) + ")");
  }
  if (!std::isfinite(*body.angle_deg) || !std::isfinite(body.origin->x) ||
      !std::isfinite(body.origin->y)) {
    throw InputError(body.where + ": lattice angle and origin must be finite");
  }
  return body;
}

/// Largest lattice row or column index the generator handles (they are stored as int32).
constexpr double kMaxLatticeIndex = 1073741824.0;  // 2^30

}  // namespace

GeneratorOptions reader_size_limit(std::int64_t max_disks, const std::string& hint) {
  GeneratorOptions limit;
  const bool caller = max_disks > 0 && max_disks < kMaxDisksCeiling;
  limit.max_disks = caller ? max_disks : kMaxDisksCeiling;
  limit.max_disks_hint = caller ? hint : std::string();
  return limit;
}

void check_lattice_size(const Outline& outline, const GeneratorOptions& options) {
  for (const BodyOutline& body : outline.bodies)
    for (const auto* loops : {&body.outers, &body.holes})
      for (const Loop& loop : *loops)
        for (const Vec2& p : loop.points)
          if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate))
            throw InputError(loop.where + ": coordinate out of range: |x| and |y| must be at most " +
                             fmt(kMaxCoordinate) + " m ((" + fmt(p.x) + ", " + fmt(p.y) + "))");
  double total = 0.0;
  std::string largest;
  double largest_count = -1.0;
  for (const BodyOutline& in : outline.bodies) {
    const BodyOutline body = resolved_body(in, options);
    const Frame f(*body.radius, *body.angle_deg, *body.origin);
    double area = 0.0, xmax = 0.0, ymax = 0.0;
    double ylo = std::numeric_limits<double>::infinity(), yhi = -ylo;
    for (const Loop& loop : body.outers) {
      area += std::abs(signed_area(loop));
      for (const Vec2& p : loop.points) {
        const Vec2 q = f.to_lattice(p);
        xmax = std::max(xmax, std::abs(q.x));
        ymax = std::max(ymax, std::abs(q.y));
        ylo = std::min(ylo, q.y);
        yhi = std::max(yhi, q.y);
      }
    }
    if (!std::isfinite(area) || !std::isfinite(xmax) || !std::isfinite(ymax)) {
      throw InputError(body.where + ": region too large to compute with (area " + fmt(area) +
                       " m^2)");
    }
    const double reach = std::max(xmax / f.d, ymax / f.h) + 4.0;
    if (reach > kMaxLatticeIndex) {
      throw InputError(body.where + ": the region reaches " + fmt(reach) +
                       " lattice spacings from the lattice origin at disk radius " + fmt(f.r) +
                       " m (limit 2^30); use a larger radius or put the lattice origin near the region");
    }
    const double rows = yhi > ylo ? (yhi - ylo) / f.h + 4.0 : 0.0;
    const double count = std::max(area / f.hex_area, rows);
    total += count;
    if (count > largest_count) {
      largest_count = count;
      largest = "body '" + escape_text(body.name) + "': " + fmt(count) + " at r = " + fmt(f.r) +
                " m on " + fmt(area) + " m^2";
    }
  }
  if (total > static_cast<double>(options.max_disks)) {
    const double gigabytes = total * kLatticeBytesPerDisk / 1e9;
    throw InputError(outline.source + ": about " + fmt(total) + " disks (" + largest +
                     "), more than the limit of " + std::to_string(options.max_disks) +
                     " (the mesh alone would need about " + fmt(gigabytes) +
                     " GB); use a larger disk radius or check the units of the outline" +
                     (options.max_disks_hint.empty() ? std::string()
                                                     : ", or raise the limit with " + options.max_disks_hint));
  }
}

bool is_reserved_array_name(const std::string& name) {
  // Point arrays of mesh files (lattice_vtu.cpp) and of result frames (solver/src/output.cpp).
  static const char* const reserved[] = {
      "radius",   "kind",         "cell_area", "body",   "material", "ring_radius",
      "mass",     "displacement", "velocity",  "rotation", "spin",   "stress",
      "damage",   "plastic_strain"};
  return std::find(std::begin(reserved), std::end(reserved), name) != std::end(reserved);
}

Lattice generate_lattice(const Outline& outline, const GeneratorOptions& options,
                         GeneratorReport* report_out) {
  const auto t_start = std::chrono::steady_clock::now();
  GeneratorReport report;
  Lattice lat;
  lat.mode = options.mode;
  lat.set_names = outline.boundary_names;
  for (const std::string& name : outline.boundary_names) {
    if (is_reserved_array_name(name)) {
      throw InputError(outline.source + ": boundary set (layer) name '" + name +
                       "' is reserved: it is the name of a point array of the mesh (radius, kind, "
                       "cell_area, body, material, ...); rename the boundary or layer");
    }
    if (name.empty() || has_control_character(name)) {
      throw InputError(outline.source + ": boundary set name '" + escape_text(name) +
                       "' must not be empty or hold control characters");
    }
    if (has_csv_special(name)) {  // a DXF layer (a TOML outline refuses it where it names it)
      throw InputError(outline.source + ": boundary set (layer) name '" + escape_text(name) +
                       "' must not hold a comma or a double quote (it names CSV columns); rename the layer");
    }
  }
  for (const BodyOutline& body : outline.bodies) {
    if (body.name.empty() || has_control_character(body.name)) {
      throw InputError(body.where + ": body name '" + escape_text(body.name) +
                       "' must not be empty or hold control characters");
    }
    if (has_csv_special(body.name)) {
      throw InputError(body.where + ": body name '" + escape_text(body.name) +
                       "' must not hold a comma or a double quote (it names CSV columns)");
    }
  }
  if (options.max_disks < 1) {
    throw InputError("the disk limit must be >= 1 (got " + std::to_string(options.max_disks) + ")");
  }
  check_lattice_size(outline, options);

  struct Entry { std::int32_t set, disk; double length, nx, ny, distance, mx, my; };
  std::vector<Entry> entries;
  for (std::size_t b = 0; b < outline.bodies.size(); ++b) {
    const BodyOutline body = resolved_body(outline.bodies[b], options);
    if (options.mode == GeometryMode::Axisymmetric) {
      const double tol = kTolerance * 2 * *body.radius;
      for (const Loop& l : body.outers)
        for (const Vec2& p : l.points)
          if (p.x < -tol) {
            throw InputError(l.where + ": axisymmetric region must lie in r >= 0 (point (" +
                             fmt(p.x) + ", " + fmt(p.y) + "))");
          }
    }
    const std::size_t first = lat.x.size();
    BodyFiller filler(body, static_cast<std::int32_t>(b), options.mode, lat, report);
    filler.fill();
    lat.body_names.push_back(body.name);
    lat.body_region_area.push_back(filler.region_area());
    report.region_area += filler.region_area();
    for (const auto& e : filler.set_entries()) entries.push_back({e.set, e.disk, e.length, e.nx, e.ny, e.distance, e.mx, e.my});
    if (options.mode == GeometryMode::Axisymmetric) {
      for (std::size_t k = first; k < lat.x.size(); ++k) {
        if (!(lat.cell_cx[k] > 0)) {
          throw InputError(body.where + ": disk at (" + fmt(lat.x[k]) + ", " + fmt(lat.y[k]) +
                           ") has zero weight on the axis (shift the lattice origin)");
        }
      }
    }
  }

  // Boundary sets: merge the faces of each (set, disk) pair.
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.set != b.set ? a.set < b.set : a.disk < b.disk;
  });
  lat.set_offset.assign(lat.set_names.size() + 1, 0);
  for (std::size_t k = 0; k < entries.size();) {
    std::size_t e = k;
    double len = 0, nx = 0, ny = 0, mx = 0, my = 0, dist = std::numeric_limits<double>::infinity();
    while (e < entries.size() && entries[e].set == entries[k].set && entries[e].disk == entries[k].disk) {
      dist = std::min(dist, entries[e].distance);
      len += entries[e].length;
      mx += entries[e].mx;
      my += entries[e].my;
      nx += entries[e].nx;
      ny += entries[e].ny;
      ++e;
    }
    const double nn = std::hypot(nx, ny);
    lat.set_disk.push_back(entries[k].disk);
    lat.set_length.push_back(len);
    lat.set_nx.push_back(nn > 0 ? nx / nn : 0.0);
    lat.set_ny.push_back(nn > 0 ? ny / nn : 0.0);
    lat.set_distance.push_back(dist);
    lat.set_cx.push_back(len > 0 ? mx / len : lat.x[entries[k].disk]);
    lat.set_cy.push_back(len > 0 ? my / len : lat.y[entries[k].disk]);
    lat.set_offset[entries[k].set + 1] += 1;
    k = e;
  }
  for (std::size_t s = 0; s < lat.set_names.size(); ++s) lat.set_offset[s + 1] += lat.set_offset[s];

  // A disk without a bond in a body of several disks is loose debris the outline did not ask
  // for: a feature narrower than the lattice (docs/outline-format.md, "Features narrower than
  // the lattice"). Refused, like a region no disk fits.
  {
    std::vector<std::uint8_t> bonded(lat.num_disks(), 0);
    for (std::size_t b = 0; b < lat.num_bonds(); ++b) {
      bonded[static_cast<std::size_t>(lat.bond_i[b])] = 1;
      bonded[static_cast<std::size_t>(lat.bond_j[b])] = 1;
    }
    std::vector<std::int64_t> per_body(lat.body_names.size(), 0), loose(lat.body_names.size(), 0);
    std::vector<std::size_t> first_loose(lat.body_names.size(), 0);
    for (std::size_t k = 0; k < lat.num_disks(); ++k) {
      const auto b = static_cast<std::size_t>(lat.body[k]);
      ++per_body[b];
      if (!bonded[k] && loose[b]++ == 0) first_loose[b] = k;
    }
    for (std::size_t b = 0; b < per_body.size(); ++b) {
      if (loose[b] == 0 || per_body[b] < 2) continue;
      const std::size_t k = first_loose[b];
      throw InputError(outline.bodies[b].where + ": " + std::to_string(loose[b]) + " of the body's " +
                       std::to_string(per_body[b]) + " disks have no bond to any other disk (the first at (" +
                       fmt(lat.x[k]) + ", " + fmt(lat.y[k]) + ") m, radius " + fmt(lat.radius[k]) +
                       " m): a part of the outline is narrower than the lattice and would be loose debris; use "
                       "a smaller radius or widen the part");
    }
  }

  report.disks = static_cast<std::int64_t>(lat.num_disks());
  report.bonds = static_cast<std::int64_t>(lat.num_bonds());
  report.min_cell_fraction = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < lat.num_disks(); ++k) {
    report.semi_disks += lat.kind[k] == static_cast<std::uint8_t>(DiskKind::SemiDisk);
    report.cell_area_sum += lat.cell_area[k];
    const double full = 2 * kSqrt3 * lat.radius[k] * lat.radius[k];
    report.min_cell_fraction = std::min(report.min_cell_fraction, lat.cell_area[k] / full);
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (report_out) *report_out = report;
  return lat;
}

}  // namespace hexdem::meshing
