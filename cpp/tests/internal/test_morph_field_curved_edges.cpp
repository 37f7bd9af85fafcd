// The halves' curved edges split at their middles (split_curved_edges,
// morph_field_internal.hpp): which edges, where the points go, what the
// cells and distances become, and that the blend is left linear enough
// along every edge it looks at.
#include "../fixtures.hpp"
#include "animanifold/delaunay.hpp"
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

constexpr double kSpacing = 0.25;
const std::vector<double> kWeights{0.3, 0.6};
const std::vector<double> kSlaved{0.8};

// An octahedron with its faces subdivided (S; its edges crease the
// distance inside it along the medial planes) and T, S at half its size and
// moved, with S's vertices and a jittered grid over [-2, 2]^3 (the grid's
// points within a tenth of the spacing of S left out) as the points, and
// their Delaunay tetrahedra as the cells.
struct Octahedra {
  PointMatrix VS, VT, points;
  SimplexMatrix F, cells;
  std::vector<bool> on_surface;
  Octahedra() {
    fixtures::octahedron(VS, F);
    fixtures::subdivide(VS, F, 2);
    VT = 0.5 * VS;
    VT.col(0).array() += 0.3;
    const SignedDistance dS(VS, F);
    std::vector<Eigen::RowVector3d> grid;
    const int n = 17;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          Eigen::RowVector3d p;
          for (int a = 0; a < 3; ++a)
            p(a) = -2.0 + kSpacing * std::array<int, 3>{i, j, k}[a] + 0.2 * kSpacing * jitter(i, j, k, a);
          grid.push_back(p);
        }
    PointMatrix all(static_cast<Index>(grid.size()), 3);
    for (size_t r = 0; r < grid.size(); ++r) all.row(static_cast<Index>(r)) = grid[r];
    const Eigen::VectorXd d = dS.distances(all);
    std::vector<Index> keep;
    for (Index r = 0; r < all.rows(); ++r)
      if (std::abs(d(r)) > 0.1 * kSpacing) keep.push_back(r);
    points.resize(VS.rows() + static_cast<Index>(keep.size()), 3);
    points << VS, all(keep, Eigen::all);
    on_surface.assign(points.rows(), false);
    for (Index v = 0; v < VS.rows(); ++v) on_surface[v] = true;
    cells = delaunay_tetrahedra(points);
  }
  SignedDistance dS() const { return SignedDistance(VS, F); }
  SignedDistance dT() const { return SignedDistance(VT, F); }
};

struct Split {
  RefinedCells refined;
  EndDistances distances;
  Index added = 0;
};

Split split(const Octahedra& o, double tolerance, double shortest, int rounds) {
  Split out;
  out.refined.cells = o.cells;
  out.refined.new_points.resize(0, 3);
  const SignedDistance dS = o.dS(), dT = o.dT();
  out.distances.extend(o.points, dS, dT);
  out.added = split_curved_edges(out.refined, o.points, o.on_surface, kWeights, kSlaved, dS, dT, out.distances,
                                 tolerance, shortest, rounds);
  return out;
}

Eigen::RowVector3d position(const Octahedra& o, const RefinedCells& refined, Index v) {
  const Index n = o.points.rows();
  return v < n ? Eigen::RowVector3d(o.points.row(v)) : Eigen::RowVector3d(refined.new_points.row(v - n));
}

double signed_volume(const Octahedra& o, const RefinedCells& refined, const Index* tet) {
  const Eigen::RowVector3d a = position(o, refined, tet[0]);
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.row(k) = position(o, refined, tet[k + 1]) - a;
  return edges.determinant() / 6.0;
}

double blend(const EndDistances& d, Index v, double w) { return (1 - w) * d.s(v) + w * d.t(v); }

}  // namespace

TEST(CurvedEdges, EveryNewPointIsTheMiddleOfAnEdgeFromTheInputWithItsOwnDistances) {
  const Octahedra o;
  const Split s = split(o, 0.02 * kSpacing, 0.1 * kSpacing, 5);
  ASSERT_GT(s.added, 0);
  ASSERT_EQ(s.refined.new_points.rows(), s.added);
  ASSERT_EQ(s.refined.splits.size(), static_cast<size_t>(s.added));
  ASSERT_EQ(s.refined.shares.size(), static_cast<size_t>(s.added));
  const Index n = o.points.rows();
  const Eigen::VectorXd ds = o.dS().distances(s.refined.new_points), dt = o.dT().distances(s.refined.new_points);
  for (Index j = 0; j < s.added; ++j) {
    const std::vector<Index>& edge = s.refined.splits[static_cast<size_t>(j)];
    ASSERT_EQ(edge.size(), 2u);
    auto on_input = [&](Index v) { return v < n && o.on_surface[v]; };
    EXPECT_NE(on_input(edge[0]), on_input(edge[1])) << "split " << j;
    EXPECT_EQ(s.refined.shares[static_cast<size_t>(j)], (std::vector<double>{0.5, 0.5}));
    const Eigen::RowVector3d middle = 0.5 * (position(o, s.refined, edge[0]) + position(o, s.refined, edge[1]));
    EXPECT_EQ(Eigen::RowVector3d(s.refined.new_points.row(j)), middle);
    EXPECT_EQ(s.distances.s(n + j), ds(j));
    EXPECT_EQ(s.distances.t(n + j), dt(j));
  }
}

TEST(CurvedEdges, TheRefinedCellsArePositiveAndTileTheSameRegion) {
  const Octahedra o;
  const Split s = split(o, 0.02 * kSpacing, 0.1 * kSpacing, 5);
  ASSERT_GT(s.added, 0);
  double before = 0, after = 0;
  for (Index c = 0; c < o.cells.rows(); ++c) {
    const double volume = signed_volume(o, s.refined, o.cells.row(c).data());
    ASSERT_GT(volume, 0);
    before += volume;
  }
  for (Index c = 0; c < s.refined.cells.rows(); ++c) {
    const double volume = signed_volume(o, s.refined, s.refined.cells.row(c).data());
    EXPECT_GT(volume, 0) << "cell " << c;
    after += volume;
  }
  EXPECT_NEAR(after, before, 1e-12 * before);
  // Each split of an edge turns each tet around it into two.
  EXPECT_GT(s.refined.cells.rows(), o.cells.rows() + s.added);
  // The input's points are all still corners.
  std::set<Index> corners(s.refined.cells.data(), s.refined.cells.data() + s.refined.cells.size());
  for (Index v = 0; v < o.VS.rows(); ++v) EXPECT_TRUE(corners.count(v));
}

namespace {

struct Bends {
  Index looked_at = 0;  // edges from the input, no shorter than `shortest`, near the zero set
  Index bent = 0;       // of those, the blend more than `tolerance` off linear along them
  Index could_split = 0;  // of those, ones split_curved_edges would split
};

// The edges split_curved_edges() looks at in `s`'s cells, and how bent the blend is along them.
Bends bends(const Octahedra& o, const Split& s, double tolerance, double shortest) {
  const SignedDistance dS = o.dS(), dT = o.dT();
  const Index n = o.points.rows();
  auto on_input = [&](Index v) { return v < n && o.on_surface[v]; };
  const double extent = o.points.cwiseAbs().maxCoeff();
  std::set<std::array<Index, 2>> edges;
  for (Index c = 0; c < s.refined.cells.rows(); ++c)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Index u = s.refined.cells(c, a), v = s.refined.cells(c, b);
        if (on_input(u) != on_input(v)) edges.insert({std::min(u, v), std::max(u, v)});
      }
  Bends out;
  for (const auto& [u, v] : edges) {
    const Eigen::RowVector3d pu = position(o, s.refined, u), pv = position(o, s.refined, v);
    const double length = (pu - pv).norm();
    if (length < shortest) continue;
    bool near = false;
    for (const double w : kWeights) {
      const double a = blend(s.distances, u, w), b = blend(s.distances, v, w);
      near = near || (a < 0) != (b < 0) || (std::abs(a) < 0.5 * length && std::abs(b) < 0.5 * length);
    }
    if (!near) continue;
    ++out.looked_at;
    const Eigen::RowVector3d middle = 0.5 * (pu + pv);
    const double ms = dS.distances(middle).value(), mt = dT.distances(middle).value();
    auto mean = [&](double w) { return 0.5 * (blend(s.distances, u, w) + blend(s.distances, v, w)); };
    bool over = false, keeps_sign = true;
    for (const double w : kWeights) over = over || std::abs((1 - w) * ms + w * mt - mean(w)) > tolerance;
    for (const auto* weights : {&kWeights, &kSlaved})
      for (const double w : *weights) keeps_sign = keeps_sign && (((1 - w) * ms + w * mt < 0) == (mean(w) < 0));
    if (!over) continue;
    ++out.bent;
    // A middle that is a point already there but for rounding is not added
    // (on the subdivided faces, points line up).
    double nearest = 1e300;
    for (Index r = 0; r < n + s.refined.new_points.rows(); ++r)
      nearest = std::min(nearest, (position(o, s.refined, r) - middle).norm());
    if (keeps_sign && nearest > 1e-9 * extent) ++out.could_split;
  }
  return out;
}

}  // namespace

TEST(CurvedEdges, AfterEnoughRoundsTheBlendIsLinearEnoughAlongEveryEdgeItLooksAt) {
  const Octahedra o;
  const double tolerance = 0.02 * kSpacing, shortest = 0.1 * kSpacing;
  const Bends before = bends(o, split(o, tolerance, shortest, 0), tolerance, shortest);
  EXPECT_GT(before.could_split, 50);
  const Bends after = bends(o, split(o, tolerance, shortest, 40), tolerance, shortest);
  EXPECT_GT(after.looked_at, before.looked_at);
  EXPECT_EQ(after.could_split, 0);
  EXPECT_LT(after.bent, after.looked_at / 10);
}

TEST(CurvedEdges, NoSplitPutsAPointOnTheOtherSideOfZeroFromTheUnsplitCells) {
  const Octahedra o;
  const Split s = split(o, 0.02 * kSpacing, 0.1 * kSpacing, 5);
  ASSERT_GT(s.added, 0);
  const Index n = o.points.rows();
  for (Index j = 0; j < s.added; ++j) {
    const std::vector<Index>& edge = s.refined.splits[static_cast<size_t>(j)];
    for (const auto* weights : {&kWeights, &kSlaved})
      for (const double w : *weights) {
        const double unsplit = 0.5 * (blend(s.distances, edge[0], w) + blend(s.distances, edge[1], w));
        EXPECT_EQ(blend(s.distances, n + j, w) < 0, unsplit < 0) << "split " << j << " at " << w;
      }
  }
}

TEST(CurvedEdges, OneRoundSplitsOnlyTheGivenEdgesAndShortEdgesAreLeft) {
  const Octahedra o;
  const Split one = split(o, 0.02 * kSpacing, 0.1 * kSpacing, 1);
  ASSERT_GT(one.added, 0);
  for (const auto& edge : one.refined.splits)
    for (const Index v : edge) EXPECT_LT(v, o.points.rows());
  const Split none = split(o, 0.02 * kSpacing, 100.0, 5);
  EXPECT_EQ(none.added, 0);
  EXPECT_EQ(none.refined.cells, o.cells);
  const Split flat = split(o, 1e3, 0.1 * kSpacing, 5);
  EXPECT_EQ(flat.added, 0);
}

TEST(CurvedEdges, DistancesThatDoNotCoverThePointsAreRefused) {
  const Octahedra o;
  RefinedCells refined;
  refined.cells = o.cells;
  refined.new_points.resize(0, 3);
  EndDistances partial;
  const SignedDistance dS = o.dS(), dT = o.dT();
  partial.extend(o.points.topRows(10), dS, dT);
  EXPECT_THROW(split_curved_edges(refined, o.points, o.on_surface, kWeights, kSlaved, dS, dT, partial, 0.01, 0.01, 1),
               InputError);
}
