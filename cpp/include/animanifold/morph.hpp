// Morphing between closed shapes of any topology (chapters 5 and 8).
//
// The source S is embedded at t0 and the target T at t1; the space between
// them is filled with a Delaunay triangulation A in R^(n+1), which conforms
// with both thanks to Theorem 5.2.1 once S and T have been made conforming
// Delaunay (S', T'). Simplices of A whose projection onto the plane of S or T
// lies outside the shape are stripped (§8.5); the boundary of what remains,
// less the flat caps at t0 and t1, is the animation manifold: its slice at t0
// is S and at t1 is T.
//
// Shapes are closed, outward-oriented triangle meshes in R^3 (manifold: tets
// in R^4) or closed polygons in R^2 given as oriented edges (manifold:
// triangles in R^3).
#pragma once

#include "animanifold/complex.hpp"

#include <functional>
#include <string>
#include <vector>

namespace animanifold {

struct MorphOptions {
  double t0 = 0.0, t1 = 1.0;
  // "strip": fill and strip (§8.5). Convex inputs need no stripping (§8.4):
  // the same call then strips nothing.
  std::string method = "strip";
  // Called with (stage, fraction done) between stages; returning false cancels
  // (the call then throws Cancelled).
  std::function<bool(const std::string&, double)> progress;
};

// What the checks of §8.3 found, and what each stage cost.
struct MorphReport {
  // Theorem 5.2.1: refined constraint faces of S' and T' not found in the fill.
  Index missing_source_faces = 0, missing_target_faces = 0;
  bool source_conforming = false, target_conforming = false;  // the mesher's result was Delaunay
  Index flat_fill_simplices = 0;  // zero-volume simplices across the two planes (the fill is refused then)
  double perturbation = 0.0;      // of the size, used for the combinatorics only (see morph.cpp)
  Index fill_simplices = 0, stripped_simplices = 0;
  // Validity 1: the smallest signed hypervolume of the kept simplices, how
  // many are inverted (below -tolerance) and how many are degenerate slivers
  // (within tolerance of zero: four coplanar corners of a planar quad, say).
  // The tolerance is 1e-8 of the bounding-box diagonal to the power n+1.
  double min_volume = 0.0;
  Index inverted_simplices = 0, degenerate_simplices = 0;
  // Validity 2: one-sided distances between the slices at t0/t1 and the
  // inputs, relative to the bounding-box diagonal (every slice vertex on the
  // input, every input vertex in the slice).
  double source_distance = 0.0, target_distance = 0.0;
  bool ends_reproduced = false;
  std::vector<std::pair<std::string, double>> stage_seconds;
};

struct Morph {
  Complex manifold;  // n-simplices in R^(n+1), oriented like stitched manifolds
  MorphReport report;
};

struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

// Throws InputError naming the shape and face when an input is not a closed,
// consistently oriented manifold (open inputs are refused), and
// std::runtime_error when a mesher fails.
Morph morph(const PointMatrix& source_points, const SimplexMatrix& source_faces, const PointMatrix& target_points,
            const SimplexMatrix& target_faces, const MorphOptions& options = {});

// Marks, for each simplex of the fill `A` (#A by n+2 over `points`), whether
// its projection onto the constraint plane of the points in [first, last)
// lies outside the closed constraint `constraint` (refined faces, outward,
// indexing `points`) — the stripping test of §8.5 for one constraint.
// With `exact` (the same points unperturbed), cells that are flat there are
// kept whatever side the perturbation tipped them to.
std::vector<bool> outside_of_constraint(const PointMatrix& points, const SimplexMatrix& A, Index first, Index last,
                                        const SimplexMatrix& constraint, const PointMatrix* exact = nullptr);

}  // namespace animanifold
