// Conforming Delaunay tetrahedralization through TetGen (-p -D), checked
// with CGAL's exact in-sphere predicate.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tetgen.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace animanifold {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 point_at(const tetgenio& io, int i) {
  return {io.pointlist[3 * i], io.pointlist[3 * i + 1], io.pointlist[3 * i + 2]};
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

  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = n;
  in.pointlist = new REAL[static_cast<size_t>(n) * 3];
  std::copy(points.data(), points.data() + static_cast<size_t>(n) * 3, in.pointlist);
  in.numberoffacets = static_cast<int>(faces.rows());
  in.facetlist = new tetgenio::facet[faces.rows()];
  in.facetmarkerlist = new int[faces.rows()];
  for (Index f = 0; f < faces.rows(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3]{faces(f, 0), faces(f, 1), faces(f, 2)};
    in.facetmarkerlist[f] = static_cast<int>(f) + 1;  // 0 is left for hull faces that constrain nothing
  }

  // p: mesh the PLC; D: conforming Delaunay (split constraints until they are
  // Delaunay faces); c: keep the convex hull (skeleton points lie outside the
  // surface); n: neighbours for the check; z: number from zero; Q: quiet.
  char switches[] = "pDcnzQ";
  try {
    tetrahedralize(switches, &in, &out);
  } catch (int code) {
    fail<std::runtime_error>("TetGen could not build a conforming Delaunay tetrahedralization (error ", code,
                             code == 3 ? ": self-intersecting constraints" : code == 1 ? ": out of memory" : "",
                             ")");
  }

  ConformingDelaunay result;
  result.points.resize(out.numberofpoints, 3);
  std::copy(out.pointlist, out.pointlist + 3 * static_cast<size_t>(out.numberofpoints), result.points.data());
  // TetGen keeps input points first, in order; check rather than assume.
  for (Index v = 0; v < n; ++v)
    if ((result.points.row(v) - points.row(v)).squaredNorm() != 0)
      fail<std::runtime_error>("TetGen reordered input point ", v, " (duplicate points in the input?)");

  result.simplices.resize(out.numberoftetrahedra, 4);
  for (int t = 0; t < out.numberoftetrahedra; ++t)
    for (int c = 0; c < 4; ++c) result.simplices(t, c) = out.tetrahedronlist[t * out.numberofcorners + c];
  const Eigen::VectorXd volumes = signed_volumes(result.points, result.simplices);
  for (Index t = 0; t < result.simplices.rows(); ++t)
    if (volumes(t) < 0) std::swap(result.simplices(t, 0), result.simplices(t, 1));

  // Refined constraints: subfaces whose marker names an input triangle,
  // oriented like that triangle.
  std::vector<Index> rows;
  for (int f = 0; f < out.numberoftrifaces; ++f)
    if (out.trifacemarkerlist && out.trifacemarkerlist[f] > 0) rows.push_back(f);
  result.constraints.resize(static_cast<Index>(rows.size()), 3);
  result.constraint_parent.resize(static_cast<Index>(rows.size()));
  for (size_t r = 0; r < rows.size(); ++r) {
    const int f = static_cast<int>(rows[r]);
    const Index parent = out.trifacemarkerlist[f] - 1;
    Index tri[3] = {out.trifacelist[3 * f], out.trifacelist[3 * f + 1], out.trifacelist[3 * f + 2]};
    const Eigen::Vector3d a = points.row(faces(parent, 0)), b = points.row(faces(parent, 1)),
                          c = points.row(faces(parent, 2));
    const Eigen::Vector3d p = result.points.row(tri[0]), q = result.points.row(tri[1]), s = result.points.row(tri[2]);
    if ((b - a).cross(c - a).dot((q - p).cross(s - p)) < 0) std::swap(tri[0], tri[1]);
    const Index row = static_cast<Index>(r);
    result.constraints.row(row) << tri[0], tri[1], tri[2];
    result.constraint_parent(row) = parent;
  }

  // Delaunay check: across every interior face, the opposite vertex of the
  // neighbour must not lie strictly inside the tet's circumsphere. Locally
  // Delaunay everywhere implies globally Delaunay.
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    const int* tet = out.tetrahedronlist + t * out.numberofcorners;
    const auto p0 = point_at(out, tet[0]), p1 = point_at(out, tet[1]), p2 = point_at(out, tet[2]),
               p3 = point_at(out, tet[3]);
    for (int i = 0; i < 4; ++i) {
      const int neighbour = out.neighborlist[4 * t + i];
      if (neighbour < 0 || neighbour < t) continue;  // hull face, or already checked from the other side
      const int* other = out.tetrahedronlist + neighbour * out.numberofcorners;
      int apex = -1;
      for (int c = 0; c < 4; ++c)
        if (other[c] != tet[0] && other[c] != tet[1] && other[c] != tet[2] && other[c] != tet[3]) apex = other[c];
      if (apex < 0) continue;
      if (CGAL::side_of_bounded_sphere(p0, p1, p2, p3, point_at(out, apex)) == CGAL::ON_BOUNDED_SIDE)
        ++result.non_delaunay_faces;
    }
  }
  result.is_delaunay = result.non_delaunay_faces == 0;
  return result;
}

}  // namespace animanifold
