// The push's layer (morph_layers.hpp) on a small plane whose cells are known:
// a U-shaped polygon in its convex hull, the notch outside it.
#include "animanifold/complex.hpp"
#include "morph_layers.hpp"
#include "animanifold/slice.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace animanifold {
namespace {

// The U: (0,0) (4,0) (4,2) (3,2) (3,1) (1,1) (1,2) (0,2), counter-clockwise,
// and a free point in its notch [1,3] x [1,2]; the plane's cells (CCW
// triangles), the notch's four outside. Points carry a time column set to
// `time` (where the fill's copies are).
struct UPlane {
  PointMatrix P;            // #P by 3 (x, y, t)
  PlaneCells plane;
  PointMatrix input;        // the U's 8 corners, #8 by 2
  SimplexMatrix input_edges;
};

UPlane u_plane(double time, bool with_sliver) {
  UPlane u;
  const int count = with_sliver ? 10 : 9;
  const double xy[10][2] = {{0, 0}, {4, 0}, {4, 2}, {3, 2}, {3, 1}, {1, 1}, {1, 2}, {0, 2}, {2, 1.6}, {2, -1e-15}};
  u.P.resize(count, 3);
  for (int v = 0; v < count; ++v) u.P.row(v) << xy[v][0], xy[v][1], time;
  std::vector<std::array<Index, 3>> cells = {{0, 1, 4}, {0, 4, 5}, {1, 2, 3}, {1, 3, 4}, {0, 5, 6},
                                             {0, 6, 7}, {5, 4, 8}, {4, 3, 8}, {3, 6, 8}, {6, 5, 8}};
  if (with_sliver) {
    // A point a rounding below the hull's bottom edge: the cell (0, 9, 1) is
    // outside the U and flat to rounding, on the hull.
    cells.push_back({0, 9, 1});
  }
  u.plane.cells.resize(static_cast<Index>(cells.size()), 3);
  for (size_t c = 0; c < cells.size(); ++c)
    for (int i = 0; i < 3; ++i) u.plane.cells(static_cast<Index>(c), i) = cells[c][i];
  u.plane.outside.assign(cells.size(), false);
  for (size_t c = 6; c < cells.size(); ++c) u.plane.outside[c] = true;
  u.plane.flat.assign(cells.size(), false);
  u.plane.free.assign(count, false);
  for (Index v = 8; v < count; ++v) u.plane.free[v] = true;
  u.input = u.P.topLeftCorner(8, 2);
  u.input_edges.resize(8, 2);
  for (Index e = 0; e < 8; ++e) u.input_edges.row(e) << e, (e + 1) % 8;
  return u;
}

// The layer's boundary: closed (the fill's cap at its top included), its slices the frames.
Complex closed_layer(const PointMatrix& P, const PlaneLayer& layer) {
  Complex c;
  c.V = P;
  c.S = boundary_facets(layer.simplices);
  return c;
}

TEST(MorphLayers, PrismsArePositiveAndFillTheirColumns) {
  // A positive tet lifted from heights (0, 0.2, 0.5, 0.1) to 1: 4 simplices,
  // all positive, of total volume = its volume x (1 - the mean height).
  PointMatrix P(8, 4);
  P << 0, 0, 0, 0, 1, 0, 0, 0.2, 0, 1, 0, 0.5, 0, 0, 1, 0.1,  //
      0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1;
  const Index cell[4] = {0, 1, 2, 3}, lower[4] = {0, 1, 2, 3}, upper[4] = {4, 5, 6, 7};
  std::vector<Index> rows;
  append_prism(cell, 4, lower, upper, rows);
  const SimplexMatrix S = Eigen::Map<SimplexMatrix>(rows.data(), 4, 5);
  const Eigen::VectorXd volumes = signed_volumes(P, S);
  EXPECT_GT(volumes.minCoeff(), 0.0);
  EXPECT_NEAR(volumes.sum(), (1.0 / 6) * (1.0 - 0.8 / 4), 1e-15);
  // The same tet listed in another (still positive) order splits the same way.
  const Index turned[4] = {1, 2, 0, 3}, turned_lower[4] = {1, 2, 0, 3}, turned_upper[4] = {5, 6, 4, 7};
  std::vector<Index> again;
  append_prism(turned, 4, turned_lower, turned_upper, again);
  const SimplexMatrix T = Eigen::Map<SimplexMatrix>(again.data(), 4, 5);
  EXPECT_GT(signed_volumes(P, T).minCoeff(), 0.0);
  auto sorted_rows = [](SimplexMatrix M) {
    std::vector<std::array<Index, 5>> out;
    for (Index r = 0; r < M.rows(); ++r) {
      std::array<Index, 5> row;
      std::copy(M.row(r).data(), M.row(r).data() + 5, row.begin());
      std::sort(row.begin(), row.end());
      out.push_back(row);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(sorted_rows(S), sorted_rows(T));
}

TEST(MorphLayers, TheLayerIsPositiveEndsInTheInputAndOpensTheNotchFromTheHull) {
  UPlane u = u_plane(1.0, false);
  const PointMatrix fill_points = u.P;
  const Index plane_points = static_cast<Index>(u.P.rows());
  const PlaneLayer layer = plane_layer(u.P, fill_points, u.plane, u.input, u.input_edges, 0.0, 1.0);
  // The notch's top (3, 6) is an edge of the hull outside the U without a free vertex: split.
  EXPECT_EQ(layer.split_faces, 1);
  EXPECT_EQ(layer.peeled_slivers, 0);
  EXPECT_GT(signed_volumes(u.P, layer.simplices).minCoeff(), 0.0);
  // At the end: the U's corners, exactly; the free vertices between the end and the fill.
  ASSERT_EQ(layer.end_copies.size(), 8u);
  for (const Index v : layer.end_copies) {
    EXPECT_EQ(u.P(v, 2), 0.0);
    EXPECT_EQ((u.input.rowwise() - u.P.row(v).head(2)).rowwise().norm().minCoeff(), 0.0);
  }
  EXPECT_EQ(layer.free_vertices, static_cast<Index>(layer.free_copies.size()));
  for (const Index v : layer.free_copies) EXPECT_TRUE(u.P(v, 2) > 0.0 && u.P(v, 2) < 0.9) << v;
  EXPECT_GT(layer.largest, layer.smallest);
  // The layer fills the hull (area 8) over the thickness 1, less what lies
  // under the notch's heights; at least the U (area 6).
  const double volume = signed_volumes(u.P, layer.simplices).sum();
  EXPECT_GT(volume, 6.0);
  EXPECT_LT(volume, 8.0);
  // Its boundary at the end is the U's six cells: the frame at t0 is the input.
  const SimplexMatrix B = boundary_facets(layer.simplices);
  int at_end = 0;
  double area_at_end = 0;
  for (Index f = 0; f < B.rows(); ++f) {
    bool all = true;
    for (int i = 0; i < 3; ++i) all = all && u.P(B(f, i), 2) == 0.0;
    if (!all) continue;
    ++at_end;
    const Eigen::Vector2d a = u.P.row(B(f, 0)).head(2), b = u.P.row(B(f, 1)).head(2), c = u.P.row(B(f, 2)).head(2);
    area_at_end += 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  }
  EXPECT_EQ(at_end, 6);
  EXPECT_NEAR(area_at_end, 6.0, 1e-12);
  // The boundary is closed (with the fill's cap at t = 1, which it leaves open), and every frame
  // in between is one loop: the notch empties from the hull's edge, no hole of its own (bubble).
  EXPECT_EQ(check_manifold(B).nonmanifold_facets, 0);
  const Complex closed = closed_layer(u.P, layer);
  for (const double t : {0.05, 0.3, 0.6, 0.85}) {
    const Slice s = slice(closed, 2, t);
    // Loops: vertices each start one segment; count them by following the segments.
    std::vector<Index> next(s.vertices.rows(), -1);
    for (Index e = 0; e < s.faces.rows(); ++e) next[s.faces(e, 0)] = s.faces(e, 1);
    std::vector<bool> seen(s.vertices.rows(), false);
    int loops = 0;
    for (Index v = 0; v < s.vertices.rows(); ++v) {
      if (seen[v] || next[v] < 0) continue;
      ++loops;
      for (Index w = v; !seen[w]; w = next[w]) seen[w] = true;
    }
    EXPECT_EQ(loops, 1) << "t = " << t;
  }
  EXPECT_GE(u.P.rows(), plane_points + 2 * 8);
}

TEST(MorphLayers, ACellFlatToRoundingOnTheHullIsLeftOutOfTheLayer) {
  UPlane u = u_plane(1.0, true);
  const PointMatrix fill_points = u.P;
  const PlaneLayer layer = plane_layer(u.P, fill_points, u.plane, u.input, u.input_edges, 0.0, 1.0);
  EXPECT_EQ(layer.peeled_slivers, 1);
  EXPECT_GT(signed_volumes(u.P, layer.simplices).minCoeff(), 0.0);
  // The sliver's free corner (2, -1e-15) is in no cell of the layer: no copy of it is used.
  for (Index s = 0; s < layer.simplices.rows(); ++s)
    for (int i = 0; i < 4; ++i) {
      const Index v = layer.simplices(s, i);
      EXPECT_FALSE(u.P(v, 0) == 2 && u.P(v, 1) == -1e-15) << v;
    }
}

}  // namespace
}  // namespace animanifold
