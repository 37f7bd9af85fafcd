// Barycentric refinement of a simplicial complex in any dimension (chapter 6).
//
// A split tuple [b, f] names a simplex f of the complex — a face of any
// dimension up to the top one, given by its vertex indices — and barycentric
// coordinates b over f's vertices. Applying it inserts one vertex
// q = sum_i b_i p_i and splits every top simplex T that contains f into |f|
// children: child j is T with its j-th vertex of f replaced, in place, by q.
// Replacing a vertex in place keeps the orientation (the child's signed
// volume is b_j times T's), and splitting every simplex around f keeps the
// complex conforming, so the result is a valid, consistently oriented complex
// after every single split (§6.1, §6.2).
//
// Pending tuples whose simplex g contains f (exactly those the split
// destroys) are re-homed by eq. 6.1: with gamma the coordinates of the
// applied split over g (gamma_i = 0 for the vertices of g not in f, the rule
// for simplices of another dimension), the ratio test picks
// j = argmin_{i in f} beta_i / gamma_i; the tuple moves to g with g_j
// replaced by q and coordinates beta_i - gamma_i * beta_j / gamma_j, and
// beta_j / gamma_j on q. Only vertices with gamma_i > 0 enter a ratio, so
// there is no division by zero; a tie (the point on a new face) leaves zero
// coordinates, which the sliver control below drops.
//
// Sliver control (§6.3), applied to every tuple on input and after every
// update: coordinates below `epsilon` are dropped and the rest renormalised,
// downgrading the tuple to the lower face; a tuple left with one coordinate
// (its point within epsilon, in barycentric terms, of an existing vertex) is
// removed and reported as snapped to that vertex.
//
// Ordering (§6.3): `Given` applies tuples in input order (Figure 6.1);
// `Degeneracy` applies them greedily from a priority queue keyed by the worst
// degeneracy (edge_length_degeneracy below) among the top simplices the
// split would create, recomputed whenever a split changes the star of a
// tuple's simplex; ties go to the earlier tuple. Pending tuples are found through a hash
// keyed by their simplex (sorted vertex ids), and the simplices around a
// face through a vertex-to-simplex incidence map, so a split costs what its
// neighbourhood holds, not a scan of the complex.
//
// Works for any simplices up to kMaxRefineVertices vertices in any ambient
// dimension: triangles in R^3, tets in R^4 (animation manifolds), tets in
// R^3 (full-space complexes), and so on.
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/enum_names.hpp"

namespace animanifold {

// Largest number of vertices per simplex refine() accepts (7-simplices).
inline constexpr int kMaxRefineVertices = 8;

enum class RefineOrder {
  Given,       // input order, re-homed tuples keeping their place
  Degeneracy,  // least degenerate split first (priority queue)
};

// The names users choose from (enum_names.hpp).
inline constexpr NameTable<RefineOrder, 2> kRefineOrderNames{
    {{RefineOrder::Given, "given"}, {RefineOrder::Degeneracy, "degeneracy"}}};

struct RefineOptions {
  // Barycentric sliver tolerance, in [0, 0.5): a coordinate below it is
  // dropped. With 0 only exact zeros are dropped.
  double epsilon = 1e-3;
  RefineOrder order = RefineOrder::Degeneracy;
};

// The refined complex and how it relates to the input. T is the number of
// split tuples, k the number of vertices per simplex.
struct Refinement {
  Complex complex;  // points #V' by D (input vertices first, then one per applied
                    // split in the order applied), simplices #S' by k,
                    // vertex attributes interpolated with each split's final
                    // coordinates, simplex attributes copied from the parent
  // T: the vertex split t created, or -1 when t was removed by the sliver
  // control (its point was within epsilon of an existing vertex).
  IndexVector new_vertex_of_split;
  // T: for a removed split, the existing vertex (input or created by an
  // earlier split) it coincided with; -1 for an applied split.
  IndexVector snapped_vertex_of_split;
  // #V': the split that created each vertex, -1 for input vertices.
  IndexVector split_of_vertex;
  // #S': the input simplex each output simplex descends from.
  IndexVector parent_simplex;
  // T by k: the simplex each split was finally applied to (after updates and
  // downgrades), sorted vertex ids, padded with -1; all -1 for removed splits.
  SimplexMatrix applied_simplex;
  // T by k: the coordinates it was applied with, matching applied_simplex
  // column for column, padded with 0.
  PointMatrix applied_barycentric;
};

// Inputs:
//   input              the complex (#V by D points, #S by k simplices, attributes)
//   split_vertices     T by m split faces, -1 padded
//   split_barycentric  T by m coordinates
//   options            sliver tolerance and order
// Outputs:
//   Refinement: the refined complex and how each split, vertex and simplex maps to the input
// Throws: InputError (see below); MemoryLimitError when its estimate (memory_estimates.hpp) exceeds memory_limit()
//
// Applies the split tuples to `input` (validated: see Complex::validate).
//
// split_vertices  T by m (1 <= m <= k): row t holds the vertex ids of the
//                 simplex of tuple t followed by -1 padding; the ids must be
//                 distinct and span a face of some simplex of the complex.
// split_barycentric  T by m: the coordinates matching those ids, each >= 0,
//                 summing to 1 (within 1e-6; they are renormalised); entries
//                 under the padding are ignored.
//
// Throws InputError naming the split (and vertex) at fault, the simplex that
// repeats a vertex, or when the simplices have more than kMaxRefineVertices
// vertices or epsilon is out of range.
Refinement refine(const Complex& input, const SimplexMatrix& split_vertices, const PointMatrix& split_barycentric,
                  const RefineOptions& options = {});

// Inputs:
//   V  #V by D points
//   S  #S by k simplices
// Outputs:
//   #S degeneracies (0 for a regular simplex)
// Throws: InputError for indices out of range or more than kMaxRefineVertices vertices
//
// The degeneracy measure of §6.3 for each simplex: the variance of its edge
// lengths divided by their squared mean (0 for a regular simplex, growing as
// it turns into a sliver). Normalising by the squared mean makes the measure
// independent of scale, so splits in small and large simplices compare fairly
// in the priority queue (the raw variance would rank a tiny sliver before a
// large well-shaped simplex). #S vector; 0 for simplices with fewer than
// two edges or whose edges all have zero length.
Eigen::VectorXd edge_length_degeneracy(const PointMatrix& V, const SimplexMatrix& S);

}  // namespace animanifold
