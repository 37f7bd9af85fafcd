// Simplex stripping (§8.5): which simplices of a fill lie outside a
// constraint once projected onto its plane, and which cells of a plane's
// triangulation lie outside the shape.
#include "animanifold/errors.hpp"
#include "animanifold/morph.hpp"
#include "simplex_key.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <unordered_map>

namespace animanifold {

namespace {

using Key = SimplexKey<5>;
using KeyHash = SimplexKeyHash;
constexpr auto make_key = simplex_key<5>;

// Is `apex` strictly on the outer side of the outward constraint face `face`
// (n vertices), within the constraint plane (the first n coordinates)?
// Decided with CGAL's exact predicate.
bool on_outer_side(const PointMatrix& P, const Index* face, int n, Index apex) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  if (n == 3) {
    auto at = [&](Index v) { return K::Point_3(P(v, 0), P(v, 1), P(v, 2)); };
    // orientation(a, b, c, s) is the sign of (s - a) . ((b - a) x (c - a)): positive on the outward side.
    return CGAL::orientation(at(face[0]), at(face[1]), at(face[2]), at(apex)) == CGAL::POSITIVE;
  }
  auto at = [&](Index v) { return K::Point_2(P(v, 0), P(v, 1)); };
  return CGAL::orientation(at(face[0]), at(face[1]), at(apex)) == CGAL::RIGHT_TURN;  // right of a counter-clockwise edge
}

}  // namespace

std::vector<bool> outside_cells(const PointMatrix& P, const SimplexMatrix& cells, const SimplexMatrix& constraint,
                                const std::vector<bool>& flat) {
  const int n = static_cast<int>(cells.cols()) - 1;
  const Index count = static_cast<Index>(cells.rows());
  auto is_flat = [&](Index c) { return !flat.empty() && flat[c]; };

  // Cell adjacency across their facets, and which facets are constraints.
  std::unordered_map<Key, std::array<Index, 2>, KeyHash> cells_of_facet;
  auto facet_key = [&](Index c, int drop) {
    Index ids[4];
    for (int i = 0, j = 0; i < n + 1; ++i)
      if (i != drop) ids[j++] = cells(c, i);
    return make_key(ids, n);
  };
  for (Index c = 0; c < count; ++c)
    for (int drop = 0; drop < n + 1; ++drop) {
      auto [it, inserted] = cells_of_facet.try_emplace(facet_key(c, drop), std::array<Index, 2>{c, -1});
      if (!inserted) it->second[1] = c;
    }
  std::unordered_map<Key, Index, KeyHash> constraint_face;
  for (Index f = 0; f < constraint.rows(); ++f) constraint_face.emplace(make_key(constraint.row(f).data(), n), f);

  // Grow the outside from the outer side of every constraint face (§8.5.2):
  // the front never crosses a constraint face, so it fills exactly the part
  // of the triangulation outside the shape.
  std::vector<bool> outside(count, false);
  std::deque<Index> front;
  for (Index f = 0; f < constraint.rows(); ++f) {
    const auto it = cells_of_facet.find(make_key(constraint.row(f).data(), n));
    if (it == cells_of_facet.end())
      fail<MeshingError>("constraint face ", f, " is not a face of the fill (Theorem 5.2.1 does not hold)");
    for (const Index c : it->second) {
      if (c < 0 || outside[c]) continue;
      Index apex = -1;
      for (int i = 0; i < n + 1; ++i)
        if (std::find(constraint.row(f).data(), constraint.row(f).data() + n, cells(c, i)) ==
            constraint.row(f).data() + n)
          apex = cells(c, i);
      if (!is_flat(c) && on_outer_side(P, constraint.row(f).data(), n, apex)) outside[c] = true, front.push_back(c);
    }
  }
  while (!front.empty()) {
    const Index c = front.front();
    front.pop_front();
    for (int drop = 0; drop < n + 1; ++drop) {
      const Key facet = facet_key(c, drop);
      if (constraint_face.count(facet)) continue;
      for (const Index other : cells_of_facet.at(facet))
        if (other >= 0 && !outside[other] && !is_flat(other)) outside[other] = true, front.push_back(other);
    }
  }
  return outside;
}

std::vector<bool> outside_of_constraint(const PointMatrix& P, const SimplexMatrix& A, Index first, Index last,
                                        const SimplexMatrix& constraint, const PointMatrix* exact) {
  std::vector<bool> plane(P.rows(), false);
  for (Index v = first; v < last; ++v) plane[v] = true;
  return outside_of_constraint(P, A, plane, constraint, exact);
}

std::vector<bool> outside_of_constraint(const PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& plane,
                                        const SimplexMatrix& constraint, const PointMatrix* exact) {
  const int D = static_cast<int>(P.cols());  // fill dimension, n + 1
  const int n = D - 1;
  if (static_cast<Index>(plane.size()) != P.rows())
    fail<InputError>("the plane mask has ", plane.size(), " entries for ", P.rows(), " points");

  // Projections (Figure 8.5): the face of each simplex spanned by its vertices in the plane.
  std::vector<Key> projection(A.rows());
  std::vector<int> projection_size(A.rows());
  std::unordered_map<Key, Index, KeyHash> cell_of;  // in-plane full simplices (n-simplices of the plane)
  std::vector<Key> cell_keys;
  for (Index s = 0; s < A.rows(); ++s) {
    Index ids[5];
    int count = 0;
    for (int c = 0; c < D + 1; ++c)
      if (plane[A(s, c)]) ids[count++] = A(s, c);
    projection[s] = make_key(ids, count);
    projection_size[s] = count;
    if (count == n + 1 && !cell_of.count(projection[s])) {
      cell_of.emplace(projection[s], static_cast<Index>(cell_keys.size()));
      cell_keys.push_back(projection[s]);
    }
  }
  SimplexMatrix cells(static_cast<Index>(cell_keys.size()), n + 1);
  for (Index c = 0; c < cells.rows(); ++c)
    for (int i = 0; i < n + 1; ++i) cells(c, i) = cell_keys[c][i];

  // Flat cells (coplanar corners, such as the two diagonals of a planar quad
  // of the input) lie on the surface, neither inside nor outside; which side
  // the perturbation tipped them to is noise. They are never stripped:
  // stripping one would leave a crack of zero width in every frame.
  std::vector<bool> flat;
  if (exact) {
    flat.assign(cells.rows(), false);
    for (Index c = 0; c < cells.rows(); ++c) {
      Eigen::MatrixXd edges(n, n);
      double longest = 0;
      for (int i = 0; i < n; ++i) {
        edges.row(i) = exact->row(cells(c, i + 1)).head(n) - exact->row(cells(c, 0)).head(n);
        longest = std::max(longest, edges.row(i).norm());
      }
      flat[c] = std::abs(edges.determinant()) <= 1e-6 * std::pow(longest, n);
    }
  }
  const std::vector<bool> cell_outside = outside_cells(P, cells, constraint, flat);

  // Lower-dimensional projections are outside when every cell around them is.
  std::unordered_map<Index, std::vector<Index>> cells_at_vertex;
  for (Index c = 0; c < cells.rows(); ++c)
    for (int i = 0; i < n + 1; ++i) cells_at_vertex[cells(c, i)].push_back(c);
  std::vector<bool> outside(A.rows(), false);
  for (Index s = 0; s < A.rows(); ++s) {
    const int count = projection_size[s];
    if (count == 0) continue;  // the simplex does not touch this plane
    if (count == n + 2) {      // flat in the plane: adds nothing (§8.5.1)
      outside[s] = true;
      continue;
    }
    if (count == n + 1) {
      outside[s] = cell_outside[cell_of.at(projection[s])];
      continue;
    }
    bool any = false, all_outside = true;
    for (const Index c : cells_at_vertex[projection[s][0]]) {
      bool contains = true;
      for (int i = 1; i < count && contains; ++i) {
        const auto row = cells.row(c);
        contains = std::find(row.data(), row.data() + n + 1, projection[s][i]) != row.data() + n + 1;
      }
      if (!contains) continue;
      any = true;
      all_outside = all_outside && cell_outside[c];
    }
    outside[s] = any && all_outside;
  }
  return outside;
}

}  // namespace animanifold
