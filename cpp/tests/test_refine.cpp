#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/refine.hpp"
#include "animanifold/stitch.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace animanifold;

namespace {

// The regular icosahedron (0, ±1, ±φ) and its cyclic permutations; its 20
// faces are the vertex triples at mutual distance 2, oriented outward.
Complex icosahedron() {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  Complex c;
  c.V.resize(12, 3);
  int r = 0;
  for (double s1 : {-1.0, 1.0})
    for (double s2 : {-phi, phi}) {
      c.V.row(r++) << 0, s1, s2;
      c.V.row(r++) << s1, s2, 0;
      c.V.row(r++) << s2, 0, s1;
    }
  std::vector<std::array<Index, 3>> faces;
  auto edge = [&](int a, int b) { return std::abs((c.V.row(a) - c.V.row(b)).norm() - 2) < 1e-9; };
  for (int a = 0; a < 12; ++a)
    for (int b = a + 1; b < 12; ++b)
      for (int d = b + 1; d < 12; ++d)
        if (edge(a, b) && edge(b, d) && edge(a, d)) {
          const Eigen::Vector3d ab = (c.V.row(b) - c.V.row(a)).transpose();
          const Eigen::Vector3d ad = (c.V.row(d) - c.V.row(a)).transpose();
          if (ab.cross(ad).dot(c.V.row(a).transpose()) > 0) faces.push_back({a, b, d});
          else faces.push_back({a, d, b});
        }
  c.S.resize(static_cast<Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) c.S(static_cast<Index>(f), k) = faces[f][k];
  return c;
}

// The unit cube as six positively oriented tets around the main diagonal (Kuhn).
Complex cube_tets() {
  Complex c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) c.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  c.S.resize(6, 4);
  for (int t = 0; t < 6; ++t) {
    int v = 0;
    c.S(t, 0) = 0;
    for (int s = 0; s < 3; ++s) {
      v |= 1 << axes[t][s];
      c.S(t, s + 1) = v;
    }
  }
  const Eigen::VectorXd vol = signed_volumes(c.V, c.S);
  for (int t = 0; t < 6; ++t)
    if (vol(t) < 0) std::swap(c.S(t, 1), c.S(t, 2));
  return c;
}

// A tetrahedron's surface moving and growing over three keyframes: tets in R^4
// with the first and last keyframes as boundary.
Complex stitched_tetrahedron() {
  StitchInput in;
  const Eigen::Matrix<double, 4, 3> base =
      (Eigen::Matrix<double, 4, 3>() << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
  in.frames.resize(12, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      in.frames.row(i * 4 + j) = base.row(j) * (1 + 0.3 * i) + Eigen::RowVector3d(0.2 * i, -0.1 * i, 0.05 * i * j);
  in.faces.resize(4, 3);
  in.faces << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  in.times.resize(3);
  in.times << 0, 1, 2.5;
  return stitch(in);
}

struct Splits {
  SimplexMatrix ids;
  PointMatrix coords;
};

Splits make_splits(const std::vector<std::vector<Index>>& ids, const std::vector<std::vector<double>>& coords, int k) {
  Splits s;
  s.ids = SimplexMatrix::Constant(static_cast<Index>(ids.size()), k, -1);
  s.coords = PointMatrix::Zero(static_cast<Index>(ids.size()), k);
  for (size_t t = 0; t < ids.size(); ++t)
    for (size_t c = 0; c < ids[t].size(); ++c) {
      s.ids(static_cast<Index>(t), static_cast<Index>(c)) = ids[t][c];
      s.coords(static_cast<Index>(t), static_cast<Index>(c)) = coords[t][c];
    }
  return s;
}

// Random faces of random simplices with random coordinates; some repeated
// (to exercise removal) and some with a tiny coordinate (downgrading).
Splits random_splits(const Complex& c, int count, unsigned seed) {
  std::mt19937 rng(seed);
  const int k = static_cast<int>(c.S.cols());
  std::uniform_int_distribution<Index> pick_simplex(0, static_cast<Index>(c.S.rows()) - 1);
  std::uniform_int_distribution<int> pick_size(2, k);
  std::uniform_real_distribution<double> unit(0.05, 1.0);
  std::uniform_real_distribution<double> chance(0, 1);
  Splits s;
  s.ids = SimplexMatrix::Constant(count, k, -1);
  s.coords = PointMatrix::Zero(count, k);
  for (int t = 0; t < count; ++t) {
    if (t > 0 && chance(rng) < 0.1) {  // a near-duplicate of an earlier split
      std::uniform_int_distribution<int> earlier(0, t - 1);
      const int e = earlier(rng);
      s.ids.row(t) = s.ids.row(e);
      s.coords.row(t) = s.coords.row(e);
      continue;
    }
    const Index s_id = pick_simplex(rng);
    std::vector<Index> verts(c.S.row(s_id).data(), c.S.row(s_id).data() + k);
    std::shuffle(verts.begin(), verts.end(), rng);
    const int m = pick_size(rng);
    double sum = 0;
    std::vector<double> b(m);
    for (int i = 0; i < m; ++i) sum += b[i] = unit(rng);
    if (m > 2 && chance(rng) < 0.2) {  // a coordinate under epsilon
      sum -= b[0];
      b[0] = 1e-5;
      sum += b[0];
    }
    for (int i = 0; i < m; ++i) {
      s.ids(t, i) = verts[i];
      s.coords(t, i) = b[i] / sum;
    }
  }
  return s;
}

double total_volume(const PointMatrix& V, const SimplexMatrix& S) { return simplex_volumes(V, S).sum(); }

// Orientation of an n-simplex within its own n-plane compared with another's
// in the same plane: sign of det(E_a E_b^T) for their edge matrices.
double orientation_agreement(const PointMatrix& Va, const Index* a, const PointMatrix& Vb, const Index* b, int k) {
  const int D = static_cast<int>(Va.cols());
  Eigen::MatrixXd Ea(k - 1, D), Eb(k - 1, D);
  for (int i = 1; i < k; ++i) {
    Ea.row(i - 1) = Va.row(a[i]) - Va.row(a[0]);
    Eb.row(i - 1) = Vb.row(b[i]) - Vb.row(b[0]);
  }
  return (Ea * Eb.transpose()).determinant();
}

// Everything issue 4 asks to hold after any batch of splits.
void expect_valid_refinement(const Complex& in, const Refinement& r, const Splits& splits, double epsilon) {
  const Complex& out = r.complex;
  const int k = static_cast<int>(in.S.cols());
  const auto before = check_manifold(in.S);
  const auto after = check_manifold(out.S);
  ASSERT_TRUE(before.is_oriented_manifold());
  EXPECT_TRUE(after.is_oriented_manifold()) << after.nonmanifold_facets << " non-manifold, "
                                            << after.misoriented_facets << " misoriented facets";
  const double volume = total_volume(in.V, in.S);
  EXPECT_NEAR(total_volume(out.V, out.S), volume, 1e-9 * volume);
  const SimplexMatrix B0 = boundary_facets(in.S), B1 = boundary_facets(out.S);
  EXPECT_NEAR(total_volume(out.V, B1), total_volume(in.V, B0), 1e-9 * (1 + total_volume(in.V, B0)));
  if (B0.rows() == 0) EXPECT_EQ(B1.rows(), 0);

  ASSERT_EQ(r.parent_simplex.size(), out.S.rows());
  for (Index s = 0; s < out.S.rows(); ++s) {
    const Index p = r.parent_simplex(s);
    ASSERT_TRUE(p >= 0 && p < in.S.rows());
    EXPECT_GT(orientation_agreement(out.V, out.S.row(s).data(), in.V, in.S.row(p).data(), k), 0)
        << "simplex " << s << " is flipped against its parent " << p;
  }
  if (k == in.V.cols() + 1) {
    const Eigen::VectorXd vol = signed_volumes(out.V, out.S);
    EXPECT_GT(vol.minCoeff(), 0);
  }

  // Every requested point is a vertex (up to the sliver control's moves), or
  // its split was removed next to an existing vertex.
  double diameter = 0;
  for (Index a = 0; a < in.V.rows(); ++a)
    for (Index b = 0; b < in.V.rows(); ++b) diameter = std::max(diameter, (in.V.row(a) - in.V.row(b)).norm());
  const double tolerance = 2 * k * epsilon * diameter + 1e-12;
  int applied = 0;
  for (Index t = 0; t < splits.ids.rows(); ++t) {
    Eigen::RowVectorXd wanted = Eigen::RowVectorXd::Zero(in.V.cols());
    for (int c = 0; c < k && splits.ids(t, c) >= 0; ++c) wanted += splits.coords(t, c) * in.V.row(splits.ids(t, c));
    const Index v = r.new_vertex_of_split(t), snapped = r.snapped_vertex_of_split(t);
    ASSERT_TRUE((v >= 0) != (snapped >= 0)) << "split " << t;
    const Index at = v >= 0 ? v : snapped;
    EXPECT_LT((out.V.row(at) - wanted).norm(), tolerance) << "split " << t;
    if (v >= 0) {
      ++applied;
      EXPECT_EQ(r.split_of_vertex(v), t);
    }
  }
  EXPECT_EQ(out.V.rows(), in.V.rows() + applied);
}

}  // namespace

TEST(Refine, IcosahedronExampleOfSection6_4) {
  const Complex ico = icosahedron();
  ASSERT_EQ(ico.S.rows(), 20);
  ASSERT_TRUE(check_manifold(ico.S).is_oriented_manifold());
  const Index A = ico.S(0, 0), B = ico.S(0, 1), C = ico.S(0, 2);
  const Splits splits = make_splits({{A, B}, {A, B}, {B, C}, {A, B, C}},
                                    {{0.5, 0.5}, {0.4999999, 0.5000001}, {0.5, 0.5}, {0.3, 0.3, 0.4}}, 3);
  const Refinement r = refine(ico, splits.ids, splits.coords, {1e-3, RefineOrder::Given});
  const Index D = r.new_vertex_of_split(0);
  EXPECT_EQ(D, 12);
  // The near-duplicate is removed: it coincides with D.
  EXPECT_EQ(r.new_vertex_of_split(1), -1);
  EXPECT_EQ(r.snapped_vertex_of_split(1), D);
  // The list becomes [B, C],[0.5, 0.5] then [D, C],[0.6, 0.4].
  EXPECT_EQ(r.new_vertex_of_split(2), 13);
  EXPECT_EQ(r.new_vertex_of_split(3), 14);
  EXPECT_EQ(r.applied_simplex(2, 0), std::min(B, C));
  EXPECT_EQ(r.applied_simplex(2, 1), std::max(B, C));
  EXPECT_EQ(r.applied_simplex(2, 2), -1);
  EXPECT_NEAR(r.applied_barycentric(2, 0), 0.5, 1e-12);
  // Sorted ids: C < D = 12.
  EXPECT_EQ(r.applied_simplex(3, 0), C);
  EXPECT_EQ(r.applied_simplex(3, 1), D);
  EXPECT_EQ(r.applied_simplex(3, 2), -1);
  EXPECT_NEAR(r.applied_barycentric(3, 0), 0.4, 1e-12);
  EXPECT_NEAR(r.applied_barycentric(3, 1), 0.6, 1e-12);
  // Two triangles per edge split.
  EXPECT_EQ(r.complex.V.rows(), 15);
  EXPECT_EQ(r.complex.S.rows(), 26);
  expect_valid_refinement(ico, r, splits, 1e-3);
  // The face split's point is unchanged by its re-homing onto [D, C].
  const Eigen::RowVector3d wanted = 0.3 * ico.V.row(A) + 0.3 * ico.V.row(B) + 0.4 * ico.V.row(C);
  EXPECT_LT((r.complex.V.row(14) - wanted).norm(), 1e-12);
}

TEST(Refine, RatioTestRehomesIntoTheRightChild) {
  Complex tri;
  tri.V.resize(3, 2);
  tri.V << 0, 0, 1, 0, 0, 1;
  tri.S.resize(1, 3);
  tri.S << 0, 1, 2;
  // After the centroid split, (0.5, 0.3, 0.2) has ratios 1.5, 0.9, 0.6: vertex 2
  // is replaced, giving [0, 1, q] with (0.5 - 0.2, 0.3 - 0.2, 0.6).
  // (0.6, 0.2, 0.2) ties vertices 1 and 2: it lies on the new edge [0, q].
  const double third = 1.0 / 3;
  const Splits splits = make_splits({{0, 1, 2}, {0, 1, 2}, {0, 1, 2}},
                                    {{third, third, third}, {0.5, 0.3, 0.2}, {0.6, 0.2, 0.2}}, 3);
  const Refinement r = refine(tri, splits.ids, splits.coords, {1e-3, RefineOrder::Given});
  EXPECT_EQ(r.applied_simplex(1, 0), 0);
  EXPECT_EQ(r.applied_simplex(1, 1), 1);
  EXPECT_EQ(r.applied_simplex(1, 2), 3);
  EXPECT_NEAR(r.applied_barycentric(1, 0), 0.3, 1e-12);
  EXPECT_NEAR(r.applied_barycentric(1, 1), 0.1, 1e-12);
  EXPECT_NEAR(r.applied_barycentric(1, 2), 0.6, 1e-12);
  // The tie: an edge split, not a division by zero. Vertex 4 (split 1) does
  // not touch edge [0, 3], so the tuple stays on it.
  EXPECT_EQ(r.applied_simplex(2, 0), 0);
  EXPECT_EQ(r.applied_simplex(2, 1), 3);
  EXPECT_EQ(r.applied_simplex(2, 2), -1);
  EXPECT_NEAR(r.applied_barycentric(2, 0), 0.4, 1e-12);
  EXPECT_NEAR(r.applied_barycentric(2, 1), 0.6, 1e-12);
  EXPECT_EQ(r.complex.S.rows(), 1 + 2 + 2 + 2);
  expect_valid_refinement(tri, r, splits, 1e-3);
}

TEST(Refine, TuplesOnOtherSimplicesKeepTheirCoordinates) {
  const Complex cube = cube_tets();
  // Split the main diagonal [0, 7] (in all six tets); a tuple on a face that
  // does not contain the diagonal keeps its coordinates exactly, one on a tet
  // containing it is re-homed with gamma = 0 off the diagonal.
  const Index t0 = 0;
  const Index a = cube.S(t0, 0), b = cube.S(t0, 1), c = cube.S(t0, 2), d = cube.S(t0, 3);
  const Splits splits = make_splits({{0, 7}, {a, b, c}, {a, b, c, d}},
                                    {{0.5, 0.5}, {0.2, 0.3, 0.5}, {0.1, 0.2, 0.3, 0.4}}, 4);
  ASSERT_TRUE(a == 0 && d == 7);
  const Refinement r = refine(cube, splits.ids, splits.coords, {1e-3, RefineOrder::Given});
  // Face [a, b, c] contains 0 but not 7: untouched.
  EXPECT_EQ(r.applied_simplex(1, 0), a);
  EXPECT_EQ(r.applied_simplex(1, 1), std::min(b, c));
  EXPECT_NEAR(r.applied_barycentric(1, 0), 0.2, 1e-15);
  // Tet: ratios 0.1/0.5 (vertex 0) < 0.4/0.5 (vertex 7): vertex 0 replaced by
  // q = 8, coordinates b, c unchanged, 7 gets 0.4 - 0.5*0.2, q gets 0.2.
  std::vector<std::pair<Index, double>> got;
  for (int col = 0; col < 4; ++col) got.emplace_back(r.applied_simplex(2, col), r.applied_barycentric(2, col));
  std::sort(got.begin(), got.end());
  const std::vector<Index> expected_ids = [&] {
    std::vector<Index> e = {b, c, 7, 8};
    std::sort(e.begin(), e.end());
    return e;
  }();
  for (int col = 0; col < 4; ++col) EXPECT_EQ(got[col].first, expected_ids[col]);
  auto coord = [&](Index v) {
    for (auto [id, w] : got)
      if (id == v) return w;
    return -1.0;
  };
  EXPECT_NEAR(coord(b), 0.2, 1e-12);
  EXPECT_NEAR(coord(c), 0.3, 1e-12);
  EXPECT_NEAR(coord(7), 0.3, 1e-12);
  EXPECT_NEAR(coord(8), 0.2, 1e-12);
  // The diagonal split makes 12 tets out of 6.
  EXPECT_EQ(r.complex.S.rows(), 12 + 2 + 3);  // the face is on the cube's boundary
  expect_valid_refinement(cube, r, splits, 1e-3);
}

TEST(Refine, SliverControlDowngradesAndRemoves) {
  const Complex cube = cube_tets();
  const Index a = cube.S(0, 0), b = cube.S(0, 1), c = cube.S(0, 2);
  const Splits splits = make_splits({{a, b, c}, {a, b}, {a, b, c}},
                                    {{0.5, 0.4995, 0.0005}, {0.9995, 0.0005}, {0.5, 0.5, 0}}, 4);
  const Refinement r = refine(cube, splits.ids, splits.coords, {1e-3, RefineOrder::Given});
  // Downgraded to the edge, renormalised.
  EXPECT_EQ(r.applied_simplex(0, 0), std::min(a, b));
  EXPECT_EQ(r.applied_simplex(0, 2), -1);
  EXPECT_NEAR(r.applied_barycentric(0, 0) + r.applied_barycentric(0, 1), 1.0, 1e-15);
  // Within epsilon of vertex a: removed, reported as snapped to it.
  EXPECT_EQ(r.new_vertex_of_split(1), -1);
  EXPECT_EQ(r.snapped_vertex_of_split(1), a);
  // The same point as split 0 (after its downgrade): snapped to split 0's vertex.
  EXPECT_EQ(r.new_vertex_of_split(2), -1);
  EXPECT_EQ(r.snapped_vertex_of_split(2), r.new_vertex_of_split(0));
  expect_valid_refinement(cube, r, splits, 1e-3);
}

TEST(Refine, AttributesAreInterpolatedAndInherited) {
  Complex cube = cube_tets();
  cube.vertex_attributes["position"] = cube.V;  // a linear field: must equal the points after
  SimplexMatrix id(cube.S.rows(), 2);
  for (Index s = 0; s < cube.S.rows(); ++s) id.row(s) << s, 100 + s;
  cube.simplex_attributes["id"] = id;
  const Splits splits = random_splits(cube, 60, 7);
  for (RefineOrder order : {RefineOrder::Given, RefineOrder::Degeneracy}) {
    const Refinement r = refine(cube, splits.ids, splits.coords, {1e-3, order});
    const PointMatrix& position = r.complex.vertex_attributes.at("position");
    EXPECT_LT((position - r.complex.V).cwiseAbs().maxCoeff(), 1e-12);
    const SimplexMatrix& inherited = r.complex.simplex_attributes.at("id");
    ASSERT_EQ(inherited.rows(), r.complex.S.rows());
    for (Index s = 0; s < inherited.rows(); ++s) {
      EXPECT_EQ(inherited(s, 0), r.parent_simplex(s));
      EXPECT_EQ(inherited(s, 1), 100 + r.parent_simplex(s));
    }
  }
}

TEST(Refine, RandomBatchesOnSurfaceFullSpaceAndAnimationManifold) {
  const Complex cases[] = {icosahedron(), cube_tets(), stitched_tetrahedron()};
  const char* names[] = {"icosahedron", "cube tets", "stitched tetrahedron"};
  for (int i = 0; i < 3; ++i)
    for (unsigned seed : {1u, 2u, 3u})
      for (RefineOrder order : {RefineOrder::Given, RefineOrder::Degeneracy}) {
        SCOPED_TRACE(std::string(names[i]) + " seed " + std::to_string(seed) +
                     (order == RefineOrder::Given ? " given" : " degeneracy"));
        const Splits splits = random_splits(cases[i], 150, seed);
        const Refinement r = refine(cases[i], splits.ids, splits.coords, {1e-3, order});
        expect_valid_refinement(cases[i], r, splits, 1e-3);
        // The batch exercised removal (near-duplicates).
        EXPECT_GT((r.new_vertex_of_split.array() < 0).count(), 0);
      }
}

TEST(Refine, OrdersGiveTheSameVertexSet) {
  const Complex cube = cube_tets();
  // Distinct well-separated random interior points: no removal, so both orders
  // must insert the same points.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.1, 1.0);
  SimplexMatrix ids = SimplexMatrix::Constant(40, 4, -1);
  PointMatrix coords = PointMatrix::Zero(40, 4);
  for (int t = 0; t < 40; ++t) {
    const Index s = t % 6;
    double w[4], sum = 0;
    for (double& x : w) sum += x = unit(rng);
    for (int c = 0; c < 4; ++c) {
      ids(t, c) = cube.S(s, c);
      coords(t, c) = w[c] / sum;
    }
  }
  const Refinement given = refine(cube, ids, coords, {1e-3, RefineOrder::Given});
  const Refinement greedy = refine(cube, ids, coords, {1e-3, RefineOrder::Degeneracy});
  ASSERT_EQ(given.complex.V.rows(), greedy.complex.V.rows());
  for (int t = 0; t < 40; ++t) {
    ASSERT_GE(given.new_vertex_of_split(t), 0);
    ASSERT_GE(greedy.new_vertex_of_split(t), 0);
    EXPECT_LT((given.complex.V.row(given.new_vertex_of_split(t)) -
               greedy.complex.V.row(greedy.new_vertex_of_split(t))).norm(),
              1e-2);
  }
  // The orders really differ (otherwise this test shows nothing).
  EXPECT_FALSE(given.complex.V == greedy.complex.V);
}

TEST(Refine, EdgeLengthDegeneracy) {
  PointMatrix V(4, 2);
  V << 0, 0, 1, 0, 0.5, std::sqrt(3.0) / 2, 0.5, 0.01;
  SimplexMatrix S(2, 3);
  S << 0, 1, 2, 0, 1, 3;
  const Eigen::VectorXd d = edge_length_degeneracy(V, S);
  EXPECT_NEAR(d(0), 0, 1e-15);
  // Edges 1, ~0.5, ~0.5: variance 1/18 over mean^2 4/9 = 1/8.
  EXPECT_NEAR(d(1), 0.125, 1e-3);
  // Scale invariant.
  EXPECT_NEAR(edge_length_degeneracy(PointMatrix(V * 1000), S)(1), d(1), 1e-12);
}

TEST(Refine, InputErrorsNameTheSplit) {
  const Complex cube = cube_tets();
  auto message = [&](const Splits& s, double epsilon = 1e-3) -> std::string {
    try {
      refine(cube, s.ids, s.coords, {epsilon, RefineOrder::Given});
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const Splits good = make_splits({{0, 7}}, {{0.5, 0.5}}, 4);
  EXPECT_NE(message(make_splits({{0, 7}, {1, 6}}, {{0.5, 0.5}, {0.5, 0.5}}, 4)).find("split 1"), std::string::npos);
  EXPECT_NE(message(make_splits({{0, 7}, {0, 9}}, {{0.5, 0.5}, {0.5, 0.5}}, 4)).find("vertex 9"), std::string::npos);
  EXPECT_NE(message(make_splits({{0, 7}}, {{0.5, 0.6}}, 4)).find("sum to 1.1"), std::string::npos);
  EXPECT_NE(message(make_splits({{0, 7}}, {{1.5, -0.5}}, 4)).find("-0.5"), std::string::npos);
  EXPECT_NE(message(make_splits({{0, 0}}, {{0.5, 0.5}}, 4)).find("named twice"), std::string::npos);
  EXPECT_NE(message(good, 0.5).find("epsilon"), std::string::npos);
  EXPECT_EQ(message(good), "no error");
  Splits padded = make_splits({{0, 7}}, {{0.5, 0.5}}, 4);
  padded.ids(0, 3) = 3;
  EXPECT_NE(message(padded).find("padding"), std::string::npos);
}
