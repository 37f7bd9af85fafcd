#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/skeleton.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <map>

using namespace animanifold;

namespace {

// A box [0,w]x[0,h]x[0,t] whose top is sheared by (sx, sy), each face a
// single quad split in two (so a thin slab has long faces close to each
// other: its top corners encroach on the bottom faces).
void box(double w, double h, double t, PointMatrix& V, SimplexMatrix& F, double sx = 0, double sy = 0) {
  V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    V.row(i) << (i & 1 ? w : 0) + (i & 4 ? sx : 0), (i & 2 ? h : 0) + (i & 4 ? sy : 0), (i & 4 ? t : 0);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  F.resize(12, 3);
  for (int q = 0; q < 6; ++q) {
    F.row(2 * q) << quads[q][0], quads[q][1], quads[q][2];
    F.row(2 * q + 1) << quads[q][0], quads[q][2], quads[q][3];
  }
}

// A 2x2x0.2 slab whose top has a centre vertex (a fan of four triangles) while
// the bottom is two triangles: the top centre lies in the diametral sphere of
// the bottom diagonal, far from it on the mesh (Figure 7.14, type 2).
void slab(PointMatrix& V, SimplexMatrix& F) {
  V.resize(9, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0, 2, 2, 0, 0, 0, 0.2, 2, 0, 0.2, 0, 2, 0.2, 2, 2, 0.2, 1, 1, 0.2;
  F.resize(14, 3);
  F << 0, 2, 3, 0, 3, 1, 4, 5, 8, 5, 7, 8, 7, 6, 8, 6, 4, 8, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1,
      3, 7, 1, 7, 5;
}

double enclosed_volume(const PointMatrix& V, const SimplexMatrix& F) {
  double v = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}

}  // namespace

TEST(Skeleton, BoxFixtureIsClosedAndOutward) {
  PointMatrix V;
  SimplexMatrix F;
  box(2, 2, 0.1, V, F);
  EXPECT_NO_THROW(check_closed_oriented(V, F));
  EXPECT_NEAR(enclosed_volume(V, F), 0.4, 1e-12);
}

TEST(Skeleton, SlabIsEncroachedAndSeparatedKeepingOrientation) {
  PointMatrix V;
  SimplexMatrix F;
  slab(V, F);
  ASSERT_NO_THROW(check_closed_oriented(V, F));
  const auto found = encroachments(V, F);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].vertex, 8);
  EXPECT_EQ(std::min(found[0].a, found[0].b), 0);
  EXPECT_EQ(std::max(found[0].a, found[0].b), 3);
  EXPECT_EQ(found[0].c, -1);
  EXPECT_EQ(found[0].type, 2);
  EXPECT_NEAR(found[0].distance, 0.2, 1e-12);

  const auto sep = make_voronoi_separable(V, F, 4);
  ASSERT_TRUE(sep.separable);
  EXPECT_EQ(sep.iterations, 1);
  ASSERT_EQ(sep.vertices.rows(), 10);
  EXPECT_NEAR((sep.vertices.row(9) - Eigen::RowVector3d(1, 1, 0)).norm(), 0, 1e-12) << "the foot of vertex 8";
  EXPECT_TRUE(encroachments(sep.vertices, sep.faces).empty());
  const auto report = check_manifold(sep.faces);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 0);
  EXPECT_NEAR(enclosed_volume(sep.vertices, sep.faces), 0.8, 1e-12) << "splits stay on the surface, oriented";
  EXPECT_EQ(sep.faces.rows(), 16) << "both triangles on the split diagonal are halved";

  const auto capped = make_voronoi_separable(V, F, 0);
  EXPECT_FALSE(capped.separable);
  EXPECT_EQ(capped.remaining, 1);
}

TEST(Skeleton, SlabInternalSkeletonIsItsMidPlane) {
  PointMatrix V;
  SimplexMatrix F;
  slab(V, F);
  SkeletonOptions o;
  o.external = false;
  const auto sk = voronoi_skeleton(V, F, o);
  ASSERT_TRUE(sk.separable);
  ASSERT_GT(sk.faces.rows(), 0);
  for (Index f = 0; f < sk.faces.rows(); ++f) {
    EXPECT_EQ(sk.side[f], 0);
    const Eigen::Vector3d p = sk.refined_vertices.row(sk.sites(f, 0)), q = sk.refined_vertices.row(sk.sites(f, 1));
    const Eigen::Vector3d a = sk.vertices.row(sk.faces(f, 0)), b = sk.vertices.row(sk.faces(f, 1)),
                          c = sk.vertices.row(sk.faces(f, 2));
    EXPECT_GT((b - a).cross(c - a).dot(q - p), 0) << "oriented from site 0 towards site 1";
    for (const Eigen::Vector3d& x : {a, b, c}) {
      EXPECT_NEAR((x - p).norm(), (x - q).norm(), 1e-9);
      EXPECT_NEAR(x[2], 0.1, 1e-9);
    }
  }
}

TEST(Skeleton, RefusesOpenNonManifoldAndInwardInput) {
  PointMatrix V;
  SimplexMatrix F;
  box(1, 1, 1, V, F);
  const SimplexMatrix open = F.topRows(11);
  try {
    check_closed_oriented(V, open);
    FAIL() << "an open mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open"), std::string::npos) << e.what();
  }
  SimplexMatrix inward = F;
  inward.col(1).swap(inward.col(2));
  EXPECT_THROW(check_closed_oriented(V, inward), InputError);
  SimplexMatrix fin(13, 3);
  fin << F, F.row(0);
  PointMatrix V2(9, 3);
  V2 << V, Eigen::RowVector3d(5, 5, 5);
  fin(12, 2) = 8;
  try {
    check_closed_oriented(V2, fin);
    FAIL() << "a non-manifold mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold"), std::string::npos) << e.what();
  }
}

TEST(Skeleton, WrapAddsAnInwardBoxAroundTheInput) {
  PointMatrix V;
  SimplexMatrix F;
  box(1, 1, 1, V, F);
  const auto w = wrap(V, F, WrapShape::Box, 3, 1.0);
  EXPECT_EQ(w.input_vertices, 8);
  EXPECT_EQ(w.vertices.rows(), 8 + 6 * 9 + 2);  // a 3x3x3 lattice box surface: 56 points
  const SimplexMatrix shell = w.faces.bottomRows(w.faces.rows() - w.input_faces);
  const auto report = check_manifold(shell);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 0);
  EXPECT_LT(enclosed_volume(w.vertices, shell), 0) << "the wrap faces inward";
  const double diag = std::sqrt(3.0);
  for (Index v = 8; v < w.vertices.rows(); ++v)  // on the box [-diag, 1 + diag]^3
    EXPECT_NEAR((w.vertices.row(v).array() - 0.5).abs().maxCoeff(), 0.5 + diag, 1e-9);
}
