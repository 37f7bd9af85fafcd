// hull_cap_points (morph_skeleton.hpp): free points just outside the flat
// sides of an input's convex hull that bridge what lies outside it.
#include "morph_skeleton.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace animanifold {

namespace {

// How high a cap point may stand over its side, as a fraction of the square
// root of the side's area (it stays lower where the hull's other planes
// require, see below). On 15 shape pairs 0.15 leaves more vertices held
// back than 0.3, and 0.6 more bubbles.
constexpr double kCapHeight = 0.3;

// Hull triangles in one plane to this fraction of the size are one side.
constexpr double kCoplanar = 1e-9;

// An input face this close to a side's plane (fraction of the size) lies in
// it: float32 bends a quad by ~1e-8 of the size.
constexpr double kOnSurface = 1e-6;

// Lower than this (of the size) a cap point would make slivers with its
// side, and the skeleton's perturbation (1e-4 of the size) could take it
// inside the hull.
constexpr double kLowest = 1e-2;

struct HullTriangle {
  std::array<Eigen::Vector3d, 3> corner;
  Eigen::Vector3d normal;  // outward, unit
  double area = 0;
  bool input_face = false;  // one of the input's own triangles
  int side = -1;            // the flat side it belongs to (bridging triangles only)
  std::array<Index, 3> ids{};  // its corners, sorted
};

// The hull's triangles, those that are the input's own marked, in an order
// of their own (CGAL's changes from call to call).
std::vector<HullTriangle> hull_triangles(const PointMatrix& V, const SimplexMatrix& F) {
  std::set<std::array<Index, 3>> faces;
  for (Index f = 0; f < F.rows(); ++f) {
    std::array<Index, 3> t{F(f, 0), F(f, 1), F(f, 2)};
    std::sort(t.begin(), t.end());
    faces.insert(t);
  }
  std::vector<HullTriangle> triangles;
  for (const std::array<Index, 3>& ids : convex_hull_triangles(V)) {
    HullTriangle t;
    for (int i = 0; i < 3; ++i) t.corner[i] = V.row(ids[i]).transpose();
    const Eigen::Vector3d cross = (t.corner[1] - t.corner[0]).cross(t.corner[2] - t.corner[0]);
    t.area = 0.5 * cross.norm();
    if (!(t.area > 0)) continue;
    t.normal = cross.normalized();
    t.ids = ids;
    std::sort(t.ids.begin(), t.ids.end());
    t.input_face = faces.count(t.ids) > 0;
    triangles.push_back(t);
  }
  std::sort(triangles.begin(), triangles.end(), [](const HullTriangle& a, const HullTriangle& b) { return a.ids < b.ids; });
  return triangles;
}

// Bridging triangles (not the input's own) grouped into flat sides; returns
// how many sides there are.
int group_flat_sides(std::vector<HullTriangle>& triangles, double size) {
  int sides = 0;
  for (size_t a = 0; a < triangles.size(); ++a) {
    if (triangles[a].input_face || triangles[a].side >= 0) continue;
    triangles[a].side = sides;
    for (size_t b = a + 1; b < triangles.size(); ++b)
      if (!triangles[b].input_face && triangles[b].side < 0 && triangles[a].normal.dot(triangles[b].normal) > 1 - kCoplanar &&
          std::abs(triangles[a].normal.dot(triangles[b].corner[0] - triangles[a].corner[0])) <= kCoplanar * size)
        triangles[b].side = sides;
    ++sides;
  }
  return sides;
}

// Each flat side's area and how much of it the input's faces in its plane
// cover. A side bridges something where they do not cover it (faces in the
// plane lie in the side: it is the hull's part of the plane). A bent quad
// the hull triangulates by its other diagonal, or a voxel model's full side,
// is covered; a torus's disc has none, and a voxel ring's top only its
// frame. (Points spread over the side, tested for lying on the input, missed
// the ring's hole between them.)
struct SideCover {
  std::vector<double> area, covered;
  std::vector<int> count;
  std::vector<size_t> first;              // a triangle of each side
  std::vector<std::vector<Index>> in_plane;  // the input's faces in each flat side
  // Flat sides only (two triangles or more: four points or more in one
  // plane). Single bridging triangles of a curved hull (3holes: thousands)
  // gained nothing, and their points on the hull let frames run through
  // themselves (5 of 5 checked).
  std::vector<int> flat_sides;
  std::vector<bool> bridges;

  SideCover(const std::vector<HullTriangle>& triangles, int sides, const PointMatrix& V, const SimplexMatrix& F,
            double size)
      : area(static_cast<size_t>(sides), 0.0), covered(static_cast<size_t>(sides), 0.0),
        count(static_cast<size_t>(sides), 0), first(static_cast<size_t>(sides), 0),
        in_plane(static_cast<size_t>(sides)), bridges(static_cast<size_t>(sides), false) {
    for (size_t t = triangles.size(); t-- > 0;)
      if (triangles[t].side >= 0) {
        const size_t s = static_cast<size_t>(triangles[t].side);
        area[s] += triangles[t].area, ++count[s], first[s] = t;
      }
    for (int s = 0; s < sides; ++s)
      if (count[static_cast<size_t>(s)] >= 2) flat_sides.push_back(s);
    for (Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
      for (const int s : flat_sides) {
        const HullTriangle& h = triangles[first[static_cast<size_t>(s)]];
        const double tolerance = kOnSurface * size;
        if (std::abs(h.normal.dot(a - h.corner[0])) <= tolerance && std::abs(h.normal.dot(b - h.corner[0])) <= tolerance &&
            std::abs(h.normal.dot(c - h.corner[0])) <= tolerance) {
          covered[static_cast<size_t>(s)] += 0.5 * (b - a).cross(c - a).norm();
          in_plane[static_cast<size_t>(s)].push_back(f);
        }
      }
    }
    for (const int s : flat_sides)
      bridges[static_cast<size_t>(s)] = covered[static_cast<size_t>(s)] < (1 - 1e-3) * area[static_cast<size_t>(s)];
  }
};

// The height of a cap point over side `s` at `centre`: low enough to see
// only its own side, half way to the nearest other hull plane it would rise
// through, so that its hull faces end at the side's rim. Standing higher,
// they lean on the curved input beyond the rim (a torus's top ring), and the
// thin wedges between hold the free points there at the plane: the cap
// stayed solid, and the hole with it.
double cap_height(const std::vector<HullTriangle>& triangles, int s, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& normal, double area, double size) {
  double height = kCapHeight * std::sqrt(area);
  for (const HullTriangle& h : triangles) {
    if (h.side == s) continue;
    const double rise = h.normal.dot(normal);
    const double room = h.normal.dot(h.corner[0] - centre);
    if (rise <= kCoplanar) continue;
    if (rise > 1 - kOnSurface && std::abs(room) <= kOnSurface * size) continue;  // the side's own plane
    height = std::min(height, 0.5 * room / rise);
  }
  return height;
}

// The covered part's boundary: edges of its faces without their twin,
// chained into closed loops.
std::vector<std::vector<Index>> boundary_loops(const SimplexMatrix& F, const std::vector<Index>& in_plane) {
  std::map<Index, Index> next;
  std::set<std::pair<Index, Index>> directed;
  for (const Index f : in_plane)
    for (int e = 0; e < 3; ++e) directed.insert({F(f, e), F(f, (e + 1) % 3)});
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) next[a] = b;
  std::vector<std::vector<Index>> loops;
  while (!next.empty()) {
    std::vector<Index> loop{next.begin()->first};
    while (next.count(loop.back()) && (loop.size() == 1 || loop.back() != loop.front())) {
      const Index v = loop.back();
      loop.push_back(next.at(v));
      next.erase(v);
    }
    if (loop.size() < 4 || loop.back() != loop.front()) continue;  // not closed: nothing to place
    loop.pop_back();
    loops.push_back(std::move(loop));
  }
  return loops;
}

// On a grid (a power of two near 1e-7 of the size): the hull's
// triangulation of a flat side changes from call to call (CGAL), the sums
// round differently, and a point one unit in the last place off is
// perturbed quite otherwise (perturbation.hpp hashes its bits): the same
// morph twice gave 5,249 and 5,391 simplices.
PointMatrix on_grid(const std::vector<Eigen::Vector3d>& points, double size) {
  PointMatrix out(static_cast<Index>(points.size()), 3);
  for (size_t p = 0; p < points.size(); ++p) out.row(static_cast<Index>(p)) = points[p].transpose();
  const double step = std::exp2(std::floor(std::log2(1e-7 * size)));
  for (Index r = 0; r < out.rows(); ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = std::round(out(r, c) / step) * step;
  return out;
}

}  // namespace

PointMatrix hull_cap_points(const PointMatrix& V, const SimplexMatrix& F) {
  if (V.cols() != 3 || V.rows() < 4) return PointMatrix(0, V.cols());
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  std::vector<HullTriangle> triangles = hull_triangles(V, F);
  const int sides = group_flat_sides(triangles, size);
  const SideCover cover(triangles, sides, V, F, size);
  std::vector<size_t> bridging;
  for (size_t t = 0; t < triangles.size(); ++t)
    if (triangles[t].side >= 0) bridging.push_back(t);

  // One point over each hole in a side's covered part (a voxel plate's top
  // has three: one point over the middle left the outer two closed), and
  // one over the side's centre where uncovered area is left beyond them (a
  // torus's disc, covered nowhere).
  std::vector<Eigen::Vector3d> points;
  auto place = [&](int s, const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double area) {
    const double height = cap_height(triangles, s, centre, normal, area, size);
    if (height > kLowest * size) points.push_back(centre + height * normal);  // else no room: left as it is
  };
  for (const int s : cover.flat_sides) {
    if (!cover.bridges[static_cast<size_t>(s)]) continue;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    double area = 0;
    for (const size_t t : bridging)
      if (triangles[t].side == s) {
        const HullTriangle& h = triangles[t];
        centre += h.area * (h.corner[0] + h.corner[1] + h.corner[2]) / 3;
        normal += h.area * h.normal;
        area += h.area;
      }
    centre /= area;
    normal.normalize();
    double holes = 0;
    for (const std::vector<Index>& loop : boundary_loops(F, cover.in_plane[static_cast<size_t>(s)])) {
      Eigen::Vector3d twice_area = Eigen::Vector3d::Zero(), middle = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < loop.size(); ++i) {
        const Eigen::Vector3d p = V.row(loop[i]).transpose(), q = V.row(loop[(i + 1) % loop.size()]).transpose();
        twice_area += p.cross(q);
        middle += p;
      }
      const double signed_area = 0.5 * twice_area.dot(normal);
      if (signed_area >= 0) continue;  // the outer rim; holes turn clockwise seen from outside
      holes -= signed_area;
      place(s, middle / static_cast<double>(loop.size()), normal, -signed_area);
    }
    if (cover.area[static_cast<size_t>(s)] - cover.covered[static_cast<size_t>(s)] - holes >
        1e-3 * cover.area[static_cast<size_t>(s)])
      place(s, centre, normal, area);
  }
  return on_grid(points, size);
}

}  // namespace animanifold
