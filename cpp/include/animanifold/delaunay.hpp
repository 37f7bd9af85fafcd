// Delaunay triangulations (chapter 5).
//
//  - delaunay(): the d-dimensional Delaunay triangulation of a point set
//    through Qhull (reentrant libqhull_r, triangulated output), every simplex
//    positively oriented; delaunay_exact() the same in R^3 and R^4 through
//    CGAL, much faster on a morph's fill. Points on two parallel hyperplanes (two embedded
//    cross-sections) are degenerate for Delaunay: Qhull's triangulated output
//    may contain flat simplices, which are reported and left out.
//  - conforming_delaunay_3d(): a conforming Delaunay tetrahedralization of
//    constraint triangles in R^3 through TetGen (`-p -D`), with the refined
//    constraint surface S' read directly from TetGen's subfaces (each with
//    the input triangle it lies in), checked against the exact Delaunay
//    triangulation of its points (delaunay_exact); where TetGen returned a
//    constrained but not conforming result, points are added on the input
//    surface there and TetGen runs again (conforming_mend.hpp), until it
//    conforms, a cap on the rounds, or a refinement that cascades.
//  - conforming_delaunay_2d(): the same for constraint segments in R^2
//    through CGAL (make_conforming_Delaunay_2).
//  - missing_facets(): Theorem 5.2.1's check, which constraint faces are not
//    faces of a triangulation.
#pragma once

#include "animanifold/types.hpp"

#include <functional>
#include <string>
#include <vector>

namespace animanifold {

struct DelaunayTriangulation {
  SimplexMatrix simplices;       // #S by d+1, positive signed volume
  Index flat_simplices = 0;      // zero-volume simplices Qhull returned, left out
  SimplexMatrix flat;            // ... and those simplices
  // delaunay_exact(): rows of `simplices` that are nearly flat (Hadamard's
  // ratio below 1e-12): proper for CGAL's exact predicates, so kept, but a
  // volume that small is roundoff in later computations in doubles.
  std::vector<Index> slivers;
};

// delaunay:
// Inputs:
//   points  #P by d, d >= 2
//   joggle  let Qhull perturb the input ('QJ')
// Outputs:
//   DelaunayTriangulation: #S by d+1 positive simplices, flat ones left out
// Throws: InputError, MeshingError (see below)
//
// `points` is #P by d (d >= 2). With `joggle`, Qhull perturbs the input by a
// tiny random amount ('QJ') so that every simplex it returns is proper: the
// result is a Delaunay triangulation of points within roundoff of the input,
// with no flat simplices; orientation is decided on the joggled points.
// Without it, degenerate input gives merged facets that 'Qt' triangulates,
// possibly into flat simplices (counted, left out). Throws InputError for too
// few or non-finite points, and MeshingError with Qhull's message when
// Qhull fails.
DelaunayTriangulation delaunay(const PointMatrix& points, bool joggle = false);

// Inputs:
//   points  #P by d, d = 3 or 4
// Outputs:
//   DelaunayTriangulation: every cell proper, slivers listed
// Throws: InputError (see below)
//
// The same in R^3 and R^4 through CGAL's dD Delaunay triangulation (exact
// predicates, symbolic perturbation of cospherical points, incremental along
// a space-filling curve). On points on two parallel hyperplanes — a morph's
// fill — Qhull spends its time merging the huge vertical facets each plane
// makes in the lifted hull, quadratic in the points; CGAL never builds them. Every cell is
// proper (exact orientation) and kept; those flat within roundoff (Hadamard's
// ratio below 1e-12) are listed in `slivers`. Throws InputError for
// coinciding or too few points.
DelaunayTriangulation delaunay_exact(const PointMatrix& points);

// Inputs:
//   points  #P by 3
// Outputs:
//   #T by 4 positive tets
// Throws: InputError (see below)
//
// The Delaunay tetrahedralization of points in R^3 (#P by 3) through CGAL's
// Delaunay_triangulation_3: positively oriented tets (#T by 4). Much faster
// than delaunay_exact() in R^3; ties among cospherical points are broken its
// own way, which may differ from delaunay_exact()'s. Throws InputError for
// coinciding, non-finite or coplanar points.
SimplexMatrix delaunay_tetrahedra(const PointMatrix& points);

struct ConformingDelaunay {
  // Input points first (same indices), then the Steiner points the mesher added.
  PointMatrix points;
  // The Delaunay triangulation of `points` (the convex hull), positively
  // oriented (tets in 3D, triangles in 2D).
  SimplexMatrix simplices;
  // The refined constraints S': triangles (3D) or segments (2D), each
  // oriented like the input constraint it lies in.
  SimplexMatrix constraints;
  IndexVector constraint_parent;  // the input constraint each refined one lies in
  // Every refined constraint is a face of the Delaunay triangulation. False
  // when the mesher gave a constrained but not a conforming result (and, in
  // 3D, the mending rounds did not mend it); `non_delaunay_faces` counts
  // the offending faces.
  bool is_delaunay = false;
  Index non_delaunay_faces = 0;
  // 3D: how many times TetGen ran again after mending (0: it conformed at
  // once), and the points those rounds added on the input surface (TetGen's
  // own Steiner points not counted). 0 in 2D.
  Index mending_rounds = 0;
  Index mended_points = 0;
  // With mend_flat_cells: the flat cells left (flat_surface_cells,
  // conforming_mend.hpp), and the points that mended the others (counted in
  // mended_points too).
  Index flat_cells = 0;
  Index flat_cell_points = 0;
};

// conforming_delaunay_3d:
// Inputs:
//   points         #P by 3
//   faces          #F by 3 constraint triangles
//   while_meshing  optional poll while TetGen runs
//   time_limit     seconds a TetGen run may take; <= 0: the default allowance
//                  (5 s + 0.5 ms a face, see run_tetgen)
//   mend_flat_cells  also mend the flat cells between points of the surface
//                  (flat_surface_cells): the surface diagonal of each is
//                  split at its midpoint, in the same rounds
// Outputs:
//   ConformingDelaunay: points (input first), tets, refined constraints and their parents
// Throws: InputError, MeshingError (see below); whatever while_meshing throws
//
// Constraint triangles `faces` (#F by 3) over `points` (#P by 3); points that
// belong to no face (skeleton vertices, say) are inserted too. `simplices`
// are CGAL's exact Delaunay triangulation of the result's points. Throws
// InputError for bad indices or coinciding points and MeshingError
// naming TetGen's failure. The mending rounds (conforming_mend.hpp) stop at
// a cap, returning a result that is not Delaunay, or sooner with a
// MeshingError once they cascade — the refined surface grown past a few
// times TetGen's first refinement (a fold of hundredths of a degree, where
// points added on one face encroach on the other) — naming the edge or face
// where most non-Delaunay faces lie. TetGen runs in a child process (isolated.hpp);
// `while_meshing` is called about every 0.1 s meanwhile, and what it throws
// stops TetGen and leaves this call (a cancel, an interrupt). A TetGen run
// past its time limit (a safety net: TetGen 1.5 can loop for ever) throws
// TimeLimitError, which callers let pass rather than retry another way:
// whether the limit is hit depends on the machine, and a result must not.
ConformingDelaunay conforming_delaunay_3d(const PointMatrix& points, const SimplexMatrix& faces,
                                          const std::function<void()>& while_meshing = {}, double time_limit = 0,
                                          bool mend_flat_cells = false);

// Inputs:
//   points  #P by 2
//   edges   #E by 2 constraint segments
// Outputs:
//   ConformingDelaunay: points (input first), triangles, refined segments
// Throws: InputError for points not in R^2, fewer than 3, non-finite or coinciding,
//   or segments that are not pairs of indices into points; MeshingError when CGAL's
//   mesher fails or loses a constraint segment
//
// Constraint segments `edges` (#E by 2) over `points` (#P by 2).
ConformingDelaunay conforming_delaunay_2d(const PointMatrix& points, const SimplexMatrix& edges);

// Inputs:
//   simplices  #S by k+1
//   faces      #F by k
// Outputs:
//   the rows of faces missing from simplices
// Throws: InputError when faces have more columns than simplices
//
// Rows of `faces` (#F by k) that are not faces of any simplex of `simplices`
// (compared as vertex sets). Empty when the triangulation conforms.
IndexVector missing_facets(const SimplexMatrix& simplices, const SimplexMatrix& faces);

}  // namespace animanifold
