// Mending a constrained Delaunay surface into a conforming one: the
// refinement rounds of conforming_delaunay_3d() (chapter 5; the
// dissertation met TetGen's constrained-only results too, §8.7.1).
//
// TetGen 1.5's -D splits the segments and subfaces that it finds encroached
// upon, but leaves some refined constraint faces that are not faces of the
// Delaunay triangulation of its own points: on bunny.off (with the external
// skeleton points a morph adds) 24 of 9,482, on decimated-knight.off 87 of
// 1,932. Every sphere through such a face holds a point: mostly a skeleton
// point off the surface, or, on the knight, a point on the other side of a
// sharp crease (dihedral angles of 9° and 17°). mend_non_delaunay_faces()
// adds points on the input surface there — Delaunay refinement in the
// manner of Chew's and Ruppert's: a face's circumcentre, or the midpoint of a
// piece of the input triangle's boundary where the circumcentre would lie on
// or beyond it — and TetGen runs again on its own refined surface with those
// points inserted.
#pragma once

#include "animanifold/types.hpp"

#include <array>
#include <vector>

namespace animanifold {

// A constraint surface as the mesher is given it: triangles, each inside one
// input triangle (pieces of the same input triangle are one facet to TetGen,
// which merges them), and points inside the triangles to be inserted there.
struct ConstraintSurface {
  PointMatrix points;                       // #P by 3
  std::vector<std::array<Index, 3>> faces;  // triangles over `points`
  std::vector<Index> parent;                // per face: the input triangle it lies in
  std::vector<std::vector<Index>> inner;    // per face: rows of `points` strictly inside it
};

struct MendReport {
  Index inner_points = 0;  // circumcentres added inside faces
  Index edge_points = 0;   // midpoints (or nearer points) added on edges
  // Circumcentres not added this time because their face has an edge split
  // too (the point could fall on the new edge, which TetGen does not
  // survive); the next round sees that face again if it still needs one.
  Index deferred = 0;
  // Outputs: inner_points + edge_points. Throws: nothing
  Index added() const { return inner_points + edge_points; }
};

// Inputs:
//   surface  the constraint surface (updated in place)
//   bad      rows of surface.faces that are not Delaunay
// Outputs:
//   surface with points added; MendReport: how many, and where
// Throws: nothing
//
// Adds points on `surface` for the faces `bad` (rows of surface.faces: the
// mesher's refined faces that are not faces of the Delaunay triangulation).
// For each, in the input triangle it lies in (its parent):
//  - its circumcentre c, when c lies well inside a piece of the parent
//    (barycentric coordinates of at least 0.05) and in the diametral circle
//    of no piece of the parent's boundary: added to that piece's `inner`;
//  - else the boundary pieces c encroaches upon are split at their
//    midpoints (both triangles beside an edge are split, so the surface stays
//    conforming with itself); where c lies outside the parent and encroaches
//    upon none, the boundary piece nearest it is split;
//  - where c lies near an edge between two pieces of the parent, that edge
//    is split at c's projection (kept within the middle 80%).
// Points already in `inner` of a split triangle go to the half that holds
// them best. Nothing added (MendReport::added() == 0) means no progress.
MendReport mend_non_delaunay_faces(ConstraintSurface& surface, const std::vector<Index>& bad);

}  // namespace animanifold
