#include "animanifold/errors.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/stitch.hpp"
#include "animanifold/subdivide.hpp"

#include <gtest/gtest.h>

#include "fixtures.hpp"

using namespace animanifold;

namespace {

// A closed octahedron with outward faces, moving through three keyframes.
Complex octahedron_manifold() {
  Eigen::Matrix3d offset;
  offset << 0, 0, 0, 0.5, 0.5, 0, 1, 0, 0;
  return stitch(fixtures::octahedron_keyframes({0.0, 1.0, 2.0}, {1, 1, 1}, offset));
}

}  // namespace

TEST(Subdivide, LinearSplitKeepsOrientationAndVolumeInR3) {
  Complex c;
  c.V.resize(5, 3);
  c.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1.2;
  c.S.resize(2, 4);
  c.S << 0, 1, 2, 3, 1, 4, 2, 3;
  const double before = signed_volumes(c.V, c.S).sum();
  for (int levels : {1, 2, 3}) {
    ManifoldSubdivisionOptions options;
    options.levels = levels;
    options.scheme = ManifoldScheme::Linear;
    const auto r = subdivide_manifold(c, options);
    const Eigen::VectorXd volumes = signed_volumes(r.manifold.V, r.manifold.S);
    EXPECT_EQ(volumes.size(), 2 << (3 * levels));
    EXPECT_GT(volumes.minCoeff(), 0.0) << "level " << levels;
    EXPECT_NEAR(volumes.sum(), before, 1e-12);
    EXPECT_TRUE(check_manifold(r.manifold.S).is_oriented_manifold());
  }
}

TEST(Subdivide, SchaeferOnStitchedManifold) {
  const Complex m = octahedron_manifold();
  const auto r = subdivide_manifold(m);
  EXPECT_EQ(r.manifold.S.rows(), 8 * m.S.rows());
  const auto report = check_manifold(r.manifold.S);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 4 * check_manifold(m.S).boundary_facets);
  const SimplexMatrix boundary = boundary_facets(r.manifold.S);
  for (Eigen::Index b = 0; b < boundary.rows(); ++b) {
    const double t = r.manifold.V(boundary(b, 0), 3);
    EXPECT_TRUE(t == 0.0 || t == 2.0);
    for (int i = 1; i < 3; ++i) EXPECT_EQ(r.manifold.V(boundary(b, i), 3), t);
  }
  ASSERT_EQ(r.keyframe_times.size(), 3);
  EXPECT_EQ(r.keyframe_times(1), 1.0);
  // Old vertices keep their ids; midpoints name their edge.
  for (Index v = 0; v < m.V.rows(); ++v) EXPECT_EQ(r.vertex_parents(v, 0), v);
  // The end slices are the keyframes refined 1 -> 4, closed.
  const Slice s = slice(r.manifold, 3, 0.0);
  EXPECT_EQ(s.faces.rows(), 32);
  EXPECT_EQ(check_manifold(s.faces).boundary_facets, 0);
}

TEST(Subdivide, KeepKeyframeTimes) {
  const Complex m = octahedron_manifold();
  ManifoldSubdivisionOptions options;
  options.keep_keyframe_times = true;
  const auto r = subdivide_manifold(m, options);
  Eigen::Index on_middle = 0;
  for (Eigen::Index v = 0; v < r.manifold.V.rows(); ++v) on_middle += r.manifold.V(v, 3) == 1.0;
  EXPECT_EQ(on_middle, 6 + 12);  // the octahedron's vertices and edge midpoints
  const Slice s = slice(r.manifold, 3, 1.0);
  EXPECT_EQ(s.faces.rows(), 32);
  EXPECT_TRUE(check_manifold(s.faces).is_oriented_manifold());
}

TEST(Subdivide, Errors) {
  Complex m = octahedron_manifold();
  ManifoldSubdivisionOptions options;
  options.levels = -1;
  EXPECT_THROW(subdivide_manifold(m, options), InputError);
  m.S(0, 1) = m.S(0, 0);
  EXPECT_THROW(subdivide_manifold(m), InputError);
  EXPECT_THROW(parse_manifold_scheme("loop"), InputError);
}

// One name per frame scheme, as the Python API spells them; the B-spline
// scheme is the polylines', not the surfaces'.
TEST(FrameSubdivision, SchemesAreNamedOnceAndBSplineIsForPolylines) {
  EXPECT_EQ(parse_frame_scheme("catmull_clark"), FrameScheme::CatmullClark);
  EXPECT_EQ(parse_frame_scheme("bspline"), FrameScheme::BSpline);
  EXPECT_THROW(parse_frame_scheme("catmull-clark"), InputError);
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  FrameSubdivisionOptions options;
  options.scheme = FrameScheme::BSpline;
  EXPECT_THROW(subdivide_frame(V, F, options), InputError);
}

TEST(FrameSubdivision, CatmullClarkCubeAndCreases) {
  PointMatrix V(8, 3);
  for (int i = 0; i < 8; ++i) V.row(i) << (i & 4 ? 1 : -1), (i & 2 ? 1 : -1), (i & 1 ? 1 : -1);
  SimplexMatrix Q(6, 4);
  Q << 0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6, 0, 2, 6, 4, 1, 5, 7, 3;
  FrameSubdivisionOptions options;
  options.scheme = FrameScheme::CatmullClark;
  options.crease_angle_degrees = 0;
  const auto smooth = subdivide_frame(V, Q, options);
  EXPECT_EQ(smooth.vertices.rows(), 26);
  EXPECT_EQ(smooth.faces.rows(), 24);
  EXPECT_EQ(smooth.faces.cols(), 4);
  options.crease_angle_degrees = 45;
  options.levels = 2;
  const auto sharp = subdivide_frame(V, Q, options);
  EXPECT_EQ(sharp.crease_count, 12);
  for (Eigen::Index v = 0; v < sharp.vertices.rows(); ++v)
    EXPECT_NEAR(sharp.vertices.row(v).cwiseAbs().maxCoeff(), 1.0, 1e-12);
  options.scheme = FrameScheme::Loop;
  EXPECT_THROW(subdivide_frame(V, Q, options), InputError);
}
