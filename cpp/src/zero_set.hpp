// The zero set of a piecewise-linear field over full-dimensional simplices:
// marching simplices (the field morph's extraction, morph_field.hpp).
//
// Inputs: simplices of k = 4 or 5 vertices (tets in R^3, 4-simplices in
// R^4), each positively oriented and given with global vertex ids and the
// field's value at each vertex. Outputs: the zero set as (k-1)-vertex
// simplices (triangles, tets) over cut points, welded: a cut point on the
// edge (a, b) is shared by every simplex around that edge.
//
// Rationale:
//  - The zero level splits a simplex's vertices into N (field < 0) and P
//    (field >= 0). The piece of the zero set inside it is the product of two
//    simplices N x P (a cut point for each pair): one simplex for a 1|k-1
//    split, a triangular prism for a 2|3 split. It is cut by its staircase
//    triangulation over the global vertex order (monotone paths from
//    (min N, min P) to (max N, max P)), which restricts to the staircase
//    triangulation of every face: two simplices sharing a facet cut it
//    alike, as stitching splits its prisms (stitch.hpp).
//  - A value exactly 0 counts as positive (a symbolic perturbation), and
//    the cut on an edge from such a vertex is the vertex itself: the zero
//    set passes through it. Pieces whose corners collapse onto fewer points
//    are dropped. This is how an input surface lying exactly in the end
//    facet of a morph (field 0 on its vertices) becomes the boundary of the
//    zero set.
//  - Orientation is combinatorial: each piece is oriented so that it
//    followed by a vertex of P (the side where the field grows) is a
//    positive simplex. The sign is read from barycentric coordinates with
//    every cut at the middle of its edge, which is exact and the same for
//    any cut positions (the pieces never flatten as cuts move along their
//    edges).
#pragma once

#include "animanifold/types.hpp"

#include <cstdint>
#include <vector>

namespace animanifold {

// A point of the zero set: on the edge (a, b), a < b, at `s` from a; a == b
// (s = 0) where the field is exactly zero at vertex a.
struct ZeroCut {
  Index a, b;
  double s;
};

class ZeroSetBuilder {
 public:
  // `corners`: 4 (tets in R^3 -> triangles) or 5 (4-simplices in R^4 -> tets).
  explicit ZeroSetBuilder(int corners, size_t expected_cuts = 1024);

  // Adds the zero set of one positively oriented simplex: `ids` its global
  // vertex ids (distinct), `value` the field at each; `source` is kept with
  // every piece (which simplex it came from). Non-finite values are the
  // caller's to refuse.
  void add(const Index* ids, const double* value, Index source);

  // Appends the cuts and pieces of `other`, a builder over the same vertex
  // ids and values (one part of a complex, extracted beside this one): a cut
  // on an edge both hold is this one's, so the pieces on either side of the
  // parts' seam share it. Throws InputError for another corners().
  void append(const ZeroSetBuilder& other);

  int corners() const { return corners_; }
  const std::vector<ZeroCut>& cuts() const { return cuts_; }
  // corners()-1 cut indices per piece, piece after piece.
  const std::vector<Index>& pieces() const { return pieces_; }
  const std::vector<Index>& sources() const { return sources_; }
  size_t piece_count() const { return sources_.size(); }

 private:
  Index cut(Index a, Index b, double va, double vb);
  // The index of `point` (a cut on an edge), added unless its edge has one.
  Index intern(const ZeroCut& point);
  void grow();

  int corners_;
  std::vector<std::uint64_t> keys_;
  std::vector<Index> slots_;
  size_t mask_ = 0;
  std::vector<ZeroCut> cuts_;
  std::vector<Index> pieces_;
  std::vector<Index> sources_;
};

}  // namespace animanifold
