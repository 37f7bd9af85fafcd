// Conforming Delaunay tetrahedralization through TetGen (-p -D), checked
// against the exact Delaunay triangulation of its points and mended until it
// conforms (conforming_mend.hpp).
#include "animanifold/conforming_mend.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/isolated.hpp"

#include <tetgen.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace animanifold {

namespace {

// Runs of TetGen after the first, each after mending the faces that were not
// Delaunay. Most inputs conform at once or after one; the decimated knight's
// sharp creases (dihedral angles of 9° and 17°), where a point added on one
// side encroaches on the other, take up to 13. A run costs about as much as
// the first while the surface grows little (kMaxMendingGrowth), so the cap
// bounds the stage at a fixed multiple of one run.
constexpr Index kMaxMendingRounds = 24;

// How far the mending may grow the refined surface: to kMaxMendingGrowth
// times the faces of TetGen's first refinement, plus kMendingSlack faces.
// Mending that converges adds little: the knight 37 %, the bunny 2 %, every
// morph in the tests at most 115 % (a small input's first refinement,
// 152 -> 326 faces). Past the bound the mending cascades: the points it
// adds on one side of a thin fold (two faces at a dihedral angle of
// hundredths of a degree) encroach on the other side, so each round leaves
// about twice the non-Delaunay faces of the last and twice the surface, and
// the cost of a run grows with it, which the cap on rounds does not bound.
// Unbounded, the mending of a fuzzed octahedron folded to 0.007°
// (tests/test_morph.py) takes 24 rounds to 33,000 faces, 46 s over the
// morph's perturbations, and does not conform. The slack keeps small inputs
// from being judged by a ratio: runs on a few thousand faces take
// milliseconds.
constexpr double kMaxMendingGrowth = 4.0;
constexpr Index kMendingSlack = 2000;

// Rounds that may also mend flat cells (mend_flat_cells). With the free
// points of a field morph around the surface, one round mends them all: 45
// on the torus of tests/helpers/shapes.py, 39 on bunny.off, 14-16 on
// spot.obj, 2 on 3holes.off. On a bare surface they cascade instead: with no
// point inside a torus's tube, the pieces of a split quad make flat cells
// with their neighbours' corners, 240 -> 218 -> 496 -> 1385 over the
// rounds. After these rounds, further ones (up to kMoreFlatCellRounds in
// all) only while each leaves fewer flat cells than the one before: on
// Blender's cube, cylinder and cone turned by arbitrary angles
// (bench_morph_primitives.py), three rounds left 5 and 1 flat cells on the
// cylinder's and the cone's sides and the further rounds leave none. Flat
// cells left then are reported, not chased.
constexpr Index kFlatCellRounds = 3;
constexpr Index kMoreFlatCellRounds = 8;

struct TetgenSurface {
  PointMatrix points;            // the points given, in order, then TetGen's Steiner points
  SimplexMatrix subfaces;        // refined constraint triangles
  IndexVector subface_parent;    // the input triangle each lies in
};

// One run of TetGen (-p -D) on a constraint surface. Each triangle is a facet
// marked with its input triangle (marker = parent + 1), its inner points
// isolated vertices of that facet. TetGen merges coplanar facets with the
// same marker, so the pieces of one input triangle are one facet again and
// the edges between them constrain nothing. The refined constraints come
// back as its subfaces with their markers.
TetgenSurface run_tetgen(const ConstraintSurface& surface, const std::function<void()>& while_meshing,
                          double time_limit) {
  const PointMatrix& points = surface.points;
  const auto& faces = surface.faces;
  const Index n = static_cast<Index>(points.rows());
  tetgenio in;
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
    static const std::vector<Index> none;
    const std::vector<Index>& inner = f < surface.inner.size() ? surface.inner[f] : none;
    facet.numberofpolygons = 1 + static_cast<int>(inner.size());
    facet.polygonlist = new tetgenio::polygon[facet.numberofpolygons];
    for (int k = 0; k < facet.numberofpolygons; ++k) tetgenio::init(&facet.polygonlist[k]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3]{faces[f][0], faces[f][1], faces[f][2]};
    for (size_t k = 0; k < inner.size(); ++k) {
      facet.polygonlist[k + 1].numberofvertices = 1;
      facet.polygonlist[k + 1].vertexlist = new int[1]{inner[k]};
    }
    in.facetmarkerlist[f] = static_cast<int>(surface.parent[f]) + 1;  // 0 is left for hull faces that constrain nothing
  }
  // p: mesh the PLC; D: conforming Delaunay; c: keep the convex hull (points
  // off the surface, such as a skeleton, lie outside it); z: number from
  // zero; Q: quiet. In a child process (isolated.hpp): Debian's TetGen keeps
  // its assert()s, and an assertion that fails must fail the morph, not end
  // Blender. What comes back: the points, then the triangle faces with their
  // markers.
  // TetGen 1.5 can loop for ever recovering facets (a fan of 64 cocircular
  // points as a cylinder's cap): stopped after far longer than meshing such
  // an input takes: the whole conforming stage of a morph (both inputs, every
  // mending round, CGAL's checks) takes under a second for the shared models
  // with their skeletons (bench/bench_morph.py), and this allows 5 s + 0.5 ms a
  // face per run, several times that.
  // A longer allowance keeps Blender frozen that much longer on an input that
  // loops. Hitting the limit fails the call with TimeLimitError, which no
  // caller retries another way: another perturbation would give another,
  // valid-looking result, chosen by the machine's speed (a loaded machine or
  // a sanitized build can reach the limit on an input that meshes at once).
  const double timeout_seconds = time_limit > 0 ? time_limit : 5.0 + 5e-4 * static_cast<double>(faces.size());
  const std::vector<char> bytes = [&] {
    try {
      return run_isolated([&] {
        char switches[] = "pDczQ";
        tetgenio out;
        try {
          tetrahedralize(switches, &in, &out);
        } catch (int code) {
          fail<MeshingError>("error ", code,
                                   code == 3 ? ": the constraints intersect each other" : code == 1 ? ": out of memory" : "");
        }
        std::vector<char> packed;
        auto put = [&packed](const void* data, size_t size) {
          const size_t at = packed.size();
          packed.resize(at + size);
          if (size > 0) std::memcpy(packed.data() + at, data, size);
        };
        const int faces_with_markers = out.trifacemarkerlist ? out.numberoftrifaces : 0;
        put(&out.numberofpoints, sizeof(int));
        put(&out.numberoftrifaces, sizeof(int));
        put(&faces_with_markers, sizeof(int));
        put(out.pointlist, sizeof(REAL) * 3 * static_cast<size_t>(out.numberofpoints));
        put(out.trifacelist, sizeof(int) * 3 * static_cast<size_t>(out.numberoftrifaces));
        put(out.trifacemarkerlist, sizeof(int) * static_cast<size_t>(faces_with_markers));
        return packed;
      }, timeout_seconds, while_meshing);
    } catch (const IsolatedTimeout& e) {
      fail<TimeLimitError>("TetGen could not build a conforming Delaunay tetrahedralization (", e.what(),
                           "): stopped by its time limit, a safety net against TetGen looping, which a slow or "
                           "loaded machine can also reach; nothing is retried, as the result would then depend on "
                           "the machine's speed");
    } catch (const IsolatedFailure& e) {
      fail<MeshingError>("TetGen could not build a conforming Delaunay tetrahedralization (", e.what(), ")");
    }
  }();
  size_t at = 0;
  auto take = [&bytes, &at](void* data, size_t size) {
    if (at + size > bytes.size()) fail<MeshingError>("TetGen's result came back truncated");
    std::copy(bytes.data() + at, bytes.data() + at + size, static_cast<char*>(data));
    at += size;
  };
  int point_count = 0, face_count = 0, marker_count = 0;
  take(&point_count, sizeof(int));
  take(&face_count, sizeof(int));
  take(&marker_count, sizeof(int));
  TetgenSurface result;
  result.points.resize(point_count, 3);
  take(result.points.data(), sizeof(double) * 3 * static_cast<size_t>(point_count));  // row-major, as TetGen's list
  std::vector<int> trifaces(3 * static_cast<size_t>(face_count)), markers(static_cast<size_t>(marker_count));
  take(trifaces.data(), sizeof(int) * trifaces.size());
  take(markers.data(), sizeof(int) * markers.size());
  // TetGen keeps input points first, in order; check rather than assume.
  for (Index v = 0; v < n; ++v)
    if ((result.points.row(v) - points.row(v)).squaredNorm() != 0)
      fail<MeshingError>("TetGen moved input point ", v, " (duplicate points in the input?)");
  std::vector<int> rows;
  for (int f = 0; f < marker_count; ++f)
    if (markers[f] > 0) rows.push_back(f);
  result.subfaces.resize(static_cast<Index>(rows.size()), 3);
  result.subface_parent.resize(static_cast<Index>(rows.size()));
  for (size_t r = 0; r < rows.size(); ++r) {
    const int f = rows[r];
    for (int c = 0; c < 3; ++c) result.subfaces(static_cast<Index>(r), c) = trifaces[3 * static_cast<size_t>(f) + c];
    result.subface_parent(static_cast<Index>(r)) = markers[f] - 1;
  }
  return result;
}

// The vertices the input faces `f` and `g` share.
std::vector<Index> shared_corners(const SimplexMatrix& faces, Index f, Index g) {
  std::vector<Index> shared;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (faces(f, i) == faces(g, j)) shared.push_back(faces(f, i));
  return shared;
}

// The angle in degrees between the half-planes of faces f and g about
// their shared edge (a, b): near 0 where they fold onto each other.
double fold_angle(const PointMatrix& points, const SimplexMatrix& faces, Index f, Index g, Index a, Index b) {
  const Eigen::Vector3d p = points.row(a), axis = (Eigen::Vector3d(points.row(b)) - p).normalized();
  auto away = [&](Index face) {
    Index apex = -1;
    for (int c = 0; c < 3; ++c)
      if (faces(face, c) != a && faces(face, c) != b) apex = faces(face, c);
    const Eigen::Vector3d u = Eigen::Vector3d(points.row(apex)) - p;
    return Eigen::Vector3d(u - u.dot(axis) * axis).normalized();
  };
  return std::acos(std::clamp(away(f).dot(away(g)), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

// Where a cascading mending works, for its message: the input face that
// holds the most refined faces still not Delaunay and, when the runner-up
// shares an edge with it, the angle the two meet at there.
std::string cascade_site(const PointMatrix& points, const SimplexMatrix& faces, const IndexVector& missing,
                         const IndexVector& parent) {
  std::map<Index, Index> count;
  for (const Index r : missing) ++count[parent(r)];
  std::vector<std::pair<Index, Index>> ranked;  // (pieces, input face), most first
  for (const auto& [face, pieces] : count) ranked.emplace_back(pieces, face);
  std::sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  if (ranked.empty()) return "";
  const Index f = ranked[0].second;
  std::ostringstream out;
  if (ranked.size() > 1) {
    const Index g = ranked[1].second;
    const std::vector<Index> edge = shared_corners(faces, f, g);
    if (edge.size() == 2 && edge[0] != edge[1]) {
      out << ", most on the two faces at the edge between vertices " << std::min(edge[0], edge[1]) << " and "
          << std::max(edge[0], edge[1]) << ", which meet there at " << std::setprecision(2)
          << fold_angle(points, faces, f, g, edge[0], edge[1]) << " degrees";
      return out.str();
    }
  }
  out << ", most on the face with vertices " << faces(f, 0) << ", " << faces(f, 1) << " and " << faces(f, 2);
  return out.str();
}

}  // namespace

ConformingDelaunay conforming_delaunay_3d(const PointMatrix& points, const SimplexMatrix& faces,
                                          const std::function<void()>& while_meshing, double time_limit,
                                          bool mend_flat_cells) {
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
  // dissertation met this too, §8.7.1; see conforming_mend.hpp for what is
  // left and why). Each refined constraint is checked against the Delaunay
  // triangulation of TetGen's points — CGAL's, with exact predicates: Qhull's
  // (inexact, merging nearly cospherical facets) left out faces that have an
  // empty circumsphere with a clear margin (24 of the 25 it reported on the
  // bunny) — and the faces that are missing are mended: points on the input
  // surface at their circumcentres or on the segments those encroach upon,
  // and TetGen runs again on its own refined surface, so that what it split
  // before stays split.
  ConstraintSurface surface;
  surface.points = points;
  surface.faces.resize(faces.rows());
  surface.parent.resize(faces.rows());
  for (Index f = 0; f < faces.rows(); ++f) {
    surface.faces[f] = {faces(f, 0), faces(f, 1), faces(f, 2)};
    surface.parent[f] = f;
  }
  TetgenSurface tetgen;
  DelaunayTriangulation dt;
  IndexVector missing;
  FlatCells flat;
  Index rounds = 0, mended = 0, first_faces = 0, flat_points = 0;
  for (;; ++rounds) {
    tetgen = run_tetgen(surface, while_meshing, time_limit);
    dt = delaunay_exact(tetgen.points);
    missing = missing_facets(dt.simplices, tetgen.subfaces);
    const Index flat_before = flat.cells;
    if (mend_flat_cells) flat = flat_surface_cells(dt.simplices, tetgen.points, tetgen.subfaces);
    const bool flat_falling = rounds > 0 && flat.cells < flat_before;
    if (rounds >= kMoreFlatCellRounds || (rounds >= kFlatCellRounds && !flat_falling)) flat.diagonals.clear();
    if ((missing.size() == 0 && flat.diagonals.empty()) || rounds == kMaxMendingRounds) break;
    if (rounds == 0) first_faces = tetgen.subfaces.rows();
    if (tetgen.subfaces.rows() > kMaxMendingGrowth * static_cast<double>(first_faces) + kMendingSlack)
      fail<MeshingError>("TetGen's fill cannot be made to conform: the mending cascades (", rounds,
                         " rounds grew the refined surface from ", first_faces, " to ", tetgen.subfaces.rows(),
                         " faces, past ", kMaxMendingGrowth, " times the first plus ", kMendingSlack, ", with ",
                         missing.size(), " still not Delaunay)",
                         cascade_site(points, faces, missing, tetgen.subface_parent));
    surface.points = tetgen.points;
    surface.faces.resize(tetgen.subfaces.rows());
    surface.parent.resize(tetgen.subfaces.rows());
    for (Index r = 0; r < tetgen.subfaces.rows(); ++r) {
      surface.faces[r] = {tetgen.subfaces(r, 0), tetgen.subfaces(r, 1), tetgen.subfaces(r, 2)};
      surface.parent[r] = tetgen.subface_parent(r);
    }
    surface.inner.assign(surface.faces.size(), {});
    const MendReport added = mend_non_delaunay_faces(surface, std::vector<Index>(missing.begin(), missing.end()));
    const MendReport split = split_surface_edges(surface, flat.diagonals);
    if (added.added() + split.added() == 0) break;
    mended += added.added() + split.added();
    flat_points += split.added();
  }

  ConformingDelaunay result;
  result.points = tetgen.points;
  result.simplices = dt.simplices;
  result.constraints = tetgen.subfaces;
  result.constraint_parent.resize(tetgen.subfaces.rows());
  for (Index r = 0; r < tetgen.subfaces.rows(); ++r) {
    const Index parent = tetgen.subface_parent(r);
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
  result.mending_rounds = rounds;
  result.mended_points = mended;
  result.flat_cells = flat.cells;
  result.flat_cell_points = flat_points;
  return result;
}

}  // namespace animanifold
