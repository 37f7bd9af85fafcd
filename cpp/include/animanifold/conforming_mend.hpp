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

// The flat cells of a tetrahedralization: tets whose corners all lie on the
// constraint surface and whose volume is zero but for rounding (at most
// 1e-9 of the cube of their longest edge). A planar quad's four corners are
// cocircular whenever it is an isosceles trapezoid (every quad of a
// torus of revolution), and a Delaunay tetrahedralization may then join the
// quad's two diagonals by such a tet: the surface's diagonal on one side,
// the other diagonal on the other. Its prisms in space-time are flat too,
// and a field that changes sign across its corners puts a fold of zero
// thickness into its zero set.
struct FlatCells {
  Index cells = 0;
  // Per flat cell, its diagonal that is an edge of the surface (both edges of
  // the pair of opposite edges that cross, the longest pair, and the one of
  // them the surface's faces hold), smaller index first; each edge once.
  // Where neither diagonal is (four cocircular points in one plane across a
  // step or a hole of an input on a grid), its longest side that is.
  std::vector<std::array<Index, 2>> diagonals;
  Index without_surface_diagonal = 0;  // flat cells neither of whose diagonals is an edge of the surface
};

// Inputs:
//   tets    #T by 4 tetrahedra over points
//   points  #P by 3
//   faces   #F by 3 constraint triangles over points
// Outputs: FlatCells. Throws: nothing
FlatCells flat_surface_cells(const SimplexMatrix& tets, const PointMatrix& points, const SimplexMatrix& faces);

// Inputs:
//   surface  the constraint surface (updated in place)
//   edges    edges of its faces, as pairs of point rows
// Outputs:
//   surface with each edge split at its midpoint (both faces beside it split
//   too); MendReport: the points added (edge_points). Throws: nothing
//
// Mends flat cells (flat_surface_cells' diagonals): the midpoint of a
// quad's diagonal lies strictly inside the circle of its four corners, so
// inside every sphere through them, and no Delaunay tetrahedralization
// holding the midpoint joins the four corners by a tet again; the faces
// stay on the input.
MendReport split_surface_edges(ConstraintSurface& surface, const std::vector<std::array<Index, 2>>& edges);

}  // namespace animanifold
