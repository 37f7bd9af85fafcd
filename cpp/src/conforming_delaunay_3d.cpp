// Conforming Delaunay tetrahedralization through TetGen (-p -D), checked
// against Qhull's Delaunay triangulation and refined until it conforms.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"

#include <tetgen.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace animanifold {

namespace {

struct TetgenSurface {
  PointMatrix points;            // input points first, then TetGen's Steiner points
  SimplexMatrix subfaces;        // refined constraint triangles
  IndexVector subface_parent;    // index into the faces given to TetGen
};

// One run of TetGen (-p -D) on constraint triangles; reads the refined
// constraints back from its subfaces (marker = face + 1).
TetgenSurface run_tetgen(const PointMatrix& points, const std::vector<std::array<Index, 3>>& faces) {
  const Index n = static_cast<Index>(points.rows());
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = n;
  in.pointlist = new REAL[static_cast<size_t>(n) * 3];
  std::copy(points.data(), points.data() + static_cast<size_t>(n) * 3, in.pointlist);
  in.numberoffacets = static_cast<int>(faces.size());
  in.facetlist = new tetgenio::facet[faces.size()];
  in.facetmarkerlist = new int[faces.size()];
  for (size_t f = 0; f < faces.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3]{faces[f][0], faces[f][1], faces[f][2]};
    in.facetmarkerlist[f] = static_cast<int>(f) + 1;  // 0 is left for hull faces that constrain nothing
  }
  // p: mesh the PLC; D: conforming Delaunay; c: keep the convex hull (points
  // off the surface, such as a skeleton, lie outside it); z: number from
  // zero; Q: quiet.
  char switches[] = "pDczQ";
  try {
    tetrahedralize(switches, &in, &out);
  } catch (int code) {
    fail<std::runtime_error>("TetGen could not build a conforming Delaunay tetrahedralization (error ", code,
                             code == 3 ? ": the constraints intersect each other" : code == 1 ? ": out of memory" : "",
                             ")");
  }
  TetgenSurface result;
  result.points.resize(out.numberofpoints, 3);
  std::copy(out.pointlist, out.pointlist + 3 * static_cast<size_t>(out.numberofpoints), result.points.data());
  // TetGen keeps input points first, in order; check rather than assume.
  for (Index v = 0; v < n; ++v)
    if ((result.points.row(v) - points.row(v)).squaredNorm() != 0)
      fail<std::runtime_error>("TetGen moved input point ", v, " (duplicate points in the input?)");
  std::vector<int> rows;
  for (int f = 0; f < out.numberoftrifaces; ++f)
    if (out.trifacemarkerlist && out.trifacemarkerlist[f] > 0) rows.push_back(f);
  result.subfaces.resize(static_cast<Index>(rows.size()), 3);
  result.subface_parent.resize(static_cast<Index>(rows.size()));
  for (size_t r = 0; r < rows.size(); ++r) {
    const int f = rows[r];
    for (int c = 0; c < 3; ++c) result.subfaces(static_cast<Index>(r), c) = out.trifacelist[3 * f + c];
    result.subface_parent(static_cast<Index>(r)) = out.trifacemarkerlist[f] - 1;
  }
  return result;
}

// Splits the given edges at their midpoints in every triangle that has them
// (orientation kept); a triangle with several such edges is split repeatedly.
void split_edges(PointMatrix& points, std::vector<std::array<Index, 3>>& faces, std::vector<Index>& origin,
                 const std::set<std::pair<Index, Index>>& edges) {
  std::map<std::pair<Index, Index>, Index> midpoint;
  Index next = static_cast<Index>(points.rows());
  points.conservativeResize(next + static_cast<Index>(edges.size()), 3);
  for (const auto& e : edges) {
    points.row(next) = 0.5 * (points.row(e.first) + points.row(e.second));
    midpoint[e] = next++;
  }
  std::vector<std::array<Index, 3>> out_faces;
  std::vector<Index> out_origin;
  std::vector<std::pair<std::array<Index, 3>, Index>> stack;
  for (size_t f = 0; f < faces.size(); ++f) {
    stack.push_back({faces[f], origin[f]});
    while (!stack.empty()) {
      auto [tri, from] = stack.back();
      stack.pop_back();
      int split = -1;
      for (int i = 0; i < 3 && split < 0; ++i)
        if (midpoint.count(std::minmax(tri[i], tri[(i + 1) % 3]))) split = i;
      if (split < 0) {
        out_faces.push_back(tri);
        out_origin.push_back(from);
        continue;
      }
      const Index a = tri[split], b = tri[(split + 1) % 3], c = tri[(split + 2) % 3];
      const Index m = midpoint.at(std::minmax(a, b));
      stack.push_back({{a, m, c}, from});
      stack.push_back({{m, b, c}, from});
    }
  }
  faces = std::move(out_faces);
  origin = std::move(out_origin);
}

}  // namespace

ConformingDelaunay conforming_delaunay_3d(const PointMatrix& points, const SimplexMatrix& faces) {
  if (points.cols() != 3) fail<InputError>("conforming Delaunay in 3D needs 3D points, got ", points.cols(), "D");
  if (faces.cols() != 3) fail<InputError>("constraints in 3D must be triangles, got ", faces.cols(), " corners");
  const Index n = static_cast<Index>(points.rows());
  if (n < 4) fail<InputError>("a tetrahedralization needs at least 4 points, got ", n);
  for (Index r = 0; r < n; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(points(r, c))) fail<InputError>("point ", r, " has a non-finite coordinate");
  for (Index f = 0; f < faces.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (faces(f, c) < 0 || faces(f, c) >= n)
        fail<InputError>("constraint triangle ", f, " refers to point ", faces(f, c), ", outside 0..", n - 1);

  // TetGen's -D may return a constrained rather than conforming result (the
  // dissertation met this too, §8.7.1). Each constraint is checked against
  // Qhull's Delaunay triangulation of the points; triangles whose pieces are
  // missing get their longest edge split at its midpoint (which stays on the
  // surface) and TetGen runs again, a few rounds at most.
  PointMatrix current = points;
  std::vector<std::array<Index, 3>> current_faces(faces.rows());
  std::vector<Index> origin(faces.rows());
  for (Index f = 0; f < faces.rows(); ++f) {
    current_faces[f] = {faces(f, 0), faces(f, 1), faces(f, 2)};
    origin[f] = f;
  }
  constexpr int max_rounds = 8;
  TetgenSurface surface;
  DelaunayTriangulation dt;
  IndexVector missing;
  for (int round = 0;; ++round) {
    surface = run_tetgen(current, current_faces);
    dt = delaunay(surface.points);
    missing = missing_facets(dt.simplices, surface.subfaces);
    if (missing.size() == 0 || round + 1 == max_rounds) break;
    std::set<std::pair<Index, Index>> edges;
    for (const Index s : missing) {
      const auto& tri = current_faces[surface.subface_parent(s)];
      int longest = 0;
      double length = -1;
      for (int i = 0; i < 3; ++i) {
        const double l = (current.row(tri[i]) - current.row(tri[(i + 1) % 3])).squaredNorm();
        if (l > length) length = l, longest = i;
      }
      edges.insert(std::minmax(tri[longest], tri[(longest + 1) % 3]));
    }
    split_edges(current, current_faces, origin, edges);
  }

  ConformingDelaunay result;
  result.points = surface.points;
  result.simplices = dt.simplices;
  result.constraints = surface.subfaces;
  result.constraint_parent.resize(surface.subfaces.rows());
  for (Index r = 0; r < surface.subfaces.rows(); ++r) {
    const Index parent = origin[surface.subface_parent(r)];
    result.constraint_parent(r) = parent;
    // Orient each piece like the input triangle it lies in.
    const Eigen::Vector3d a = points.row(faces(parent, 0)), b = points.row(faces(parent, 1)),
                          c = points.row(faces(parent, 2));
    const Eigen::Vector3d p = result.points.row(result.constraints(r, 0)), q = result.points.row(result.constraints(r, 1)),
                          s = result.points.row(result.constraints(r, 2));
    if ((b - a).cross(c - a).dot((q - p).cross(s - p)) < 0) std::swap(result.constraints(r, 0), result.constraints(r, 1));
  }
  result.non_delaunay_faces = static_cast<Index>(missing.size());
  result.is_delaunay = missing.size() == 0;
  return result;
}

}  // namespace animanifold
