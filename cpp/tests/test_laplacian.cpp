#include "animanifold/errors.hpp"
#include "animanifold/laplacian.hpp"
#include "animanifold/stitch.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <utility>
#include <vector>

using namespace animanifold;

namespace {

// An octahedron (closed, outward), the keyframe of the small manifolds below.
void octahedron(PointMatrix& V, SimplexMatrix& F) {
  V.resize(6, 3);
  V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  F.resize(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
}

Complex moving_octahedron(int keyframes) {
  PointMatrix V;
  SimplexMatrix F;
  octahedron(V, F);
  StitchInput in;
  in.frames.resize(6 * keyframes, 3);
  in.times.resize(keyframes);
  for (int i = 0; i < keyframes; ++i) {
    in.frames.middleRows(6 * i, 6) = V * (1.0 + 0.25 * i);
    in.frames.middleRows(6 * i, 6).col(0).array() += 0.3 * i;
    in.times(i) = i;
  }
  in.faces = F;
  return stitch(in);
}

// Anchors on the first keyframe's vertices and handles on the last one's, of
// moving_octahedron(keyframes) (six vertices a keyframe).
std::pair<IndexVector, IndexVector> first_and_last_keyframe(int keyframes) {
  IndexVector anchors(6), handles(6);
  for (int i = 0; i < 6; ++i) {
    anchors(i) = i;
    handles(i) = 6 * (keyframes - 1) + i;
  }
  return {anchors, handles};
}

}  // namespace

TEST(DualOperator, GhostRowsAreAffineAndKeepTheBoundaryFacet) {
  const Complex m = moving_octahedron(2);
  const DualOperator dual = dual_operator(m.S, static_cast<Index>(m.V.rows()));
  EXPECT_EQ(dual.ghost_count(), 16);  // the first and last keyframe's triangles
  for (Index g = 0; g < dual.ghost_count(); ++g) {
    const Index row = dual.simplex_count() + g;
    EXPECT_NEAR(dual.D.row(row).sum(), 1.0, 1e-14);
    const Index s = dual.ghost_facets(g, 0), i = dual.ghost_facets(g, 1);
    EXPECT_NEAR(dual.D.coeff(row, m.S(s, i)), -0.25, 1e-14);
  }
}

TEST(Deformer, ZeroMotionReproducesTetManifoldsForEveryMethod) {
  const Complex m = moving_octahedron(3);
  IndexVector anchors(6), handles(6);
  for (int i = 0; i < 6; ++i) anchors(i) = i, handles(i) = 12 + i;
  for (const char* method : {"uniform", "graph", "dual"}) {
    DeformerOptions o;
    o.laplacian.method = parse_laplacian_method(method);
    Deformer d(m.V, m.S, anchors, handles, o);
    const PointMatrix out = d.deform(Eigen::MatrixXd::Identity(5, 5));
    EXPECT_LT((out - m.V).cwiseAbs().maxCoeff(), 1e-10) << method;
  }
}

TEST(Deformer, TranslationOfTheHandlesAloneTranslatesEverything) {
  const Complex m = moving_octahedron(3);
  IndexVector none(0), handles(3);
  handles << 0, 7, 14;
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(5, 5);
  T.topRightCorner(4, 1) << 0.5, -1, 2, 0.25;
  for (const char* method : {"uniform", "graph", "dual"}) {
    DeformerOptions o;
    o.laplacian.method = parse_laplacian_method(method);
    Deformer d(m.V, m.S, none, handles, o);
    const PointMatrix out = d.deform(T);
    const Eigen::RowVectorXd shift = T.topRightCorner(4, 1).transpose();
    const PointMatrix expected = m.V.rowwise() + shift;
    EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 1e-10) << method;
  }
}

TEST(Deformer, RefusesCotangentOnTetsAndOverlappingConstraints) {
  const Complex m = moving_octahedron(2);
  IndexVector a(1), h(1);
  a << 0;
  h << 0;
  EXPECT_THROW(Deformer(m.V, m.S, a, h), InputError);
  h << 1;
  DeformerOptions o;
  o.laplacian.method = LaplacianMethod::Cotangent;
  EXPECT_THROW(Deformer(m.V, m.S, a, h, o), InputError);
}

// deform(T) combines the responses (deformer_response.hpp); deform_to solves afresh.
TEST(Deformer, DeformByATransformEqualsAFreshSolveToTheSamePositions) {
  const Complex m = moving_octahedron(4);
  const auto [anchors, handles] = first_and_last_keyframe(4);
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(5, 5);
  T.topLeftCorner(4, 4) << 0.9, -0.3, 0, 0.1, 0.3, 0.9, 0, 0, 0, 0.2, 1.1, 0, 0, 0, 0, 1;
  T.topRightCorner(4, 1) << 0.5, -1, 2, -0.25;
  for (const char* method : {"uniform", "graph", "dual"}) {
    DeformerOptions o;
    o.laplacian.method = parse_laplacian_method(method);
    Deformer combined(m.V, m.S, anchors, handles, o), fresh(m.V, m.S, anchors, handles, o);
    ASSERT_EQ(combined.info().grown, 0) << method;
    PointMatrix positions(6, 4);
    for (int h = 0; h < 6; ++h)
      positions.row(h) = m.V.row(handles(h)) * T.topLeftCorner(4, 4).transpose() + T.topRightCorner(4, 1).transpose();
    for (int round = 0; round < 2; ++round) {  // the second reuses the response
      const PointMatrix a = combined.deform(T), b = fresh.deform_to(positions);
      EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-10) << method;
      for (int i = 0; i < 6; ++i) EXPECT_EQ(a.row(i), m.V.row(i)) << method;
    }
  }
}

// laplacian.hpp: one Deformer may be shared; calls from several threads run one
// after the other and each gives what it gives alone. ThreadSanitizer runs this
// (ctest's "tsan." cases) to see what the threads share.
TEST(Deformer, ThreadsSharingOneDeformerGetTheSerialResults) {
  const Complex m = moving_octahedron(4);
  const auto [anchors, handles] = first_and_last_keyframe(4);
  std::vector<Eigen::MatrixXd> transforms;
  for (int k = 0; k < 4; ++k) {
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(5, 5);
    T(0, 3) = 0.25 * k;
    T(1, 1) = 1.0 + 0.1 * k;
    transforms.push_back(T);
  }
  DeformerOptions o;
  o.laplacian.method = LaplacianMethod::Dual;
  Deformer serial(m.V, m.S, anchors, handles, o);
  std::vector<PointMatrix> expected;
  for (const auto& T : transforms) expected.push_back(serial.deform(T));
  for (int round = 0; round < 5; ++round) {
    Deformer shared(m.V, m.S, anchors, handles, o);
    std::vector<PointMatrix> got(transforms.size());
    std::vector<std::thread> threads;
    for (size_t k = 0; k < transforms.size(); ++k)
      threads.emplace_back([&, k] {
        got[k] = shared.deform(transforms[k]);
        shared.points();  // a read beside the other threads' solves
      });
    for (auto& t : threads) t.join();
    for (size_t k = 0; k < transforms.size(); ++k)
      ASSERT_EQ(got[k], expected[k]) << "round " << round << ", transform " << k;
  }
}
