// The oriented simplicial complex: points, simplices, attributes, and the
// combinatorial queries every algorithm needs (chapter 2.1, 2.4, 8.2).
//
// Orientation follows §2.4: facet i (0-based here, i+1 in the text) of a
// simplex drops vertex i and swaps the first two remaining vertices when i+1
// is even. For [A,B,C,D] this gives [B,C,D], [C,A,D], [A,B,D], [B,A,C]: all
// facets outward. Two simplices sharing a facet are consistently oriented
// when they list that facet with opposite orientations.
#pragma once

#include "animanifold/types.hpp"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace animanifold {

// An animation manifold (n-simplices in R^(n+1)) or any other simplicial
// complex: `V` is #V by D, `S` is #S by (k+1), attribute tables are indexed
// like V (vertex attributes) or S (simplex attributes).
struct Complex {
  PointMatrix V;
  SimplexMatrix S;
  VertexAttributes vertex_attributes;
  SimplexAttributes simplex_attributes;

  // Outputs: D (V's columns) and k+1 (S's columns)
  // Throws: nothing
  int ambient_dimension() const { return static_cast<int>(V.cols()); }
  int vertices_per_simplex() const { return static_cast<int>(S.cols()); }

  // Outputs: nothing: returns when the complex is well formed
  // Throws: InputError naming the offending simplex, vertex or attribute when
  //   indices are out of range, coordinates are not finite or span more than a
  //   double holds along an axis (slicing divides by their differences), or
  //   attribute tables have the wrong number of rows
  void validate() const;
};

// Inputs:
//   simplex  k vertex indices
//   k        vertices per simplex
//   i        0..k-1: the facet, the one without simplex[i]
// Outputs:
//   out  k-1 vertex indices: facet i, oriented by §2.4's rule
// Throws: nothing (nothing is checked: i must lie in 0..k-1)
// Inline: slicing calls it for every simplex it cuts.
inline void facet(const Index* simplex, int k, int i, Index* out) {
  int j = 0;
  for (int c = 0; c < k; ++c)
    if (c != i) out[j++] = simplex[c];
  // §2.4 counts facets from 1: facet i+1 swaps its first two vertices when even.
  if ((i + 1) % 2 == 0 && k - 1 >= 2) std::swap(out[0], out[1]);
}

// Inputs:
//   S  #S by k simplices (vertex indices)
// Outputs:
//   (#S*k) by (k-1) facets, oriented by §2.4's rule
// Throws: nothing (indices are not checked: see Complex::validate)
//
// All facets, simplex-major: row s*k + i is facet i of simplex s.
// (#S*k) by (k-1).
SimplexMatrix facets(const SimplexMatrix& S);

// Inputs:
//   S  #S by k simplices
// Outputs:
//   neighbour, opposite  #S by k (FacetAdjacency), -1 on the boundary
// Throws: InputError when a facet is shared by more than two simplices
//
// Simplex-to-simplex adjacency across facets.
struct FacetAdjacency {
  SimplexMatrix neighbour;  // #S by k: simplex across facet i, or -1 on the boundary
  SimplexMatrix opposite;   // #S by k: which facet of that neighbour it is, or -1
};
// Throws InputError when a facet is shared by more than two simplices
// (naming the facet's vertices) since adjacency is then not a function.
FacetAdjacency facet_adjacency(const SimplexMatrix& S);

// Inputs:
//   S  #S by k simplices
// Outputs:
//   #B by (k-1) boundary facets, oriented outward
// Throws: nothing
//
// The facets that belong to exactly one simplex, oriented outward (as facets
// of their simplex). #B by (k-1).
SimplexMatrix boundary_facets(const SimplexMatrix& S);

// check_manifold:
// Inputs:
//   S         #S by k simplices
//   boundary  optional: receives boundary_facets(S), from the same pass
// Outputs:
//   ManifoldReport: facet counts by kind, misoriented and degenerate simplices
// Throws: nothing (what is wrong is counted, not thrown)
//
// What a manifold check found. A valid oriented pseudo-manifold has
// nonmanifold == 0 and misoriented == 0.
struct ManifoldReport {
  std::int64_t interior_facets = 0;  // shared by exactly two simplices
  std::int64_t boundary_facets = 0;  // in exactly one simplex
  std::int64_t nonmanifold_facets = 0;   // in three or more simplices
  std::int64_t misoriented_facets = 0;   // shared by two with the same orientation
  std::int64_t degenerate_simplices = 0; // repeating a vertex index
  // Outputs: no non-manifold or misoriented facet and no degenerate simplex.
  // Throws: nothing
  bool is_oriented_manifold() const {
    return nonmanifold_facets == 0 && misoriented_facets == 0 && degenerate_simplices == 0;
  }
};
ManifoldReport check_manifold(const SimplexMatrix& S, SimplexMatrix* boundary = nullptr);

// Inputs:
//   V  #V by D points
//   S  #S by D+1 simplices
// Outputs:
//   #S signed volumes
// Throws: InputError when S does not have D+1 columns or an index is outside V
//
// Signed volume of full-dimensional simplices (k = D+1 vertices in R^D):
// det[v1-v0, ..., vD-v0] / D!. #S vector.
Eigen::VectorXd signed_volumes(const PointMatrix& V, const SimplexMatrix& S);

// Inputs:
//   V  #V by D points
//   S  #S by k+1 simplices, any k <= D
// Outputs:
//   #S unsigned k-volumes
// Throws: InputError when an index is outside V
//
// Unsigned k-volume of k-simplices in any ambient dimension (length, area,
// volume, ...), from the Gram determinant. #S vector.
Eigen::VectorXd simplex_volumes(const PointMatrix& V, const SimplexMatrix& S);

// Inputs:
//   V        #V by D points, D <= 4
//   corners  D+1 indices into V
// Outputs:
//   the relative volume, 0 (flat) to about 1
// Throws: nothing
//
// How far from flat the full-dimensional simplex `corners` (D+1 rows of V,
// #V by D, D <= 4) is: |det[v1 - v0, ...]| over its longest edge to the
// power D — 1 for a cube's corner, 0 for a flat simplex, whatever its size.
double relative_volume(const PointMatrix& V, const Index* corners);

// vertex_star:
// Inputs:
//   S             #S by k simplices
//   vertex_count  #V
// Outputs:
//   VertexStar: offsets (#V+1) and incident simplices
// Throws: InputError when an index is outside 0..vertex_count-1
//
// Vertex-to-simplex incidence in compressed form: the simplices incident to
// vertex v are `simplices[offsets[v] .. offsets[v+1])`.
struct VertexStar {
  std::vector<Index> offsets;
  std::vector<Index> simplices;
};
VertexStar vertex_star(const SimplexMatrix& S, Index vertex_count);

// Inputs:
//   ids  k distinct entries (k <= 8; any k works, in O(k^2))
//   k    how many
// Outputs: the parity of the permutation that sorts `ids`: +1 even, -1 odd
// Throws: nothing
// Inline: slicing calls it for every simplex it cuts in a quad.
inline int permutation_parity(const Index* ids, int k) {
  int inversions = 0;
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      if (ids[a] > ids[b]) ++inversions;
  return inversions % 2 == 0 ? 1 : -1;
}

}  // namespace animanifold
