// The steps of the field method (morph_field.hpp), shared by its files:
// free points and the conforming ends (morph_field_points.cpp), the slabs of
// the space-time triangulation (morph_field_slabs.cpp), the blend's
// schedule in time (morph_field_timing.cpp).
#pragma once

#include "animanifold/morph.hpp"
#include "signed_distance.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace animanifold::morph_field {

using Simplex4 = std::array<Index, 5>;

// A deterministic value in [-0.5, 0.5) of four integers: jitter that makes
// point sets and field values general without randomness.
double jitter(std::int64_t i, std::int64_t j, std::int64_t k, int axis);

// Per vertex, the largest circumradius of the triangles around it.
Eigen::VectorXd vertex_circumradius(const PointMatrix& V, const SimplexMatrix& F);

// ---------------------------------------------------------------- free points

struct Lattice {
  PointMatrix source, target;  // the free points each end keeps
  PointMatrix corners;         // the box's, in both
  double spacing = 0;
};

// A jittered body-centred cubic lattice at `spacing` over a box around both
// inputs: dense where the zero set passes at some time (inside one input
// and outside the other, or near either: the convex blend is of one sign
// elsewhere) and sparse elsewhere; each end keeps the points clear of its
// input (outside the diametral spheres of its faces, which the conforming
// mesher would otherwise split).
Lattice lattice_points(const PointMatrix& VS, const SimplexMatrix& FS, const SignedDistance& dS, const PointMatrix& VT,
                       const SimplexMatrix& FT, const SignedDistance& dT, double spacing, double size);

// Points on both sides of the surface (V, F), one per vertex and side, just
// clear of its faces' diametral spheres: the field near the input is
// resolved at the input's own scale (the frames just after t0 are offsets
// of it). Points whose side test disagrees or that come too close to the
// surface elsewhere (a thin part) are left out.
PointMatrix surface_shell(const PointMatrix& V, const SimplexMatrix& F, const SignedDistance& d);

struct EndMesh {
  PointMatrix points;             // the input's vertices, its free points, the box corners, Steiner points
  SimplexMatrix constraints;      // the input's faces refined (S'), oriented as the input's
  IndexVector constraint_parent;  // the input face each lies in
  std::vector<bool> on_surface;   // vertices of S': where the field is exactly zero at the end
  Index free_points = 0, steiner_points = 0;
};

// The conforming Delaunay tetrahedralization of one input with its free
// points and the box corners (TetGen -D, in a child process). Throws
// std::runtime_error naming the input (`name`) when it fails.
EndMesh conform_end(const PointMatrix& V, const SimplexMatrix& F, const PointMatrix& free, const PointMatrix& corners,
                    const char* name, const std::function<void()>& while_meshing);

// ---------------------------------------------------------------- slabs

// The 4 positive 4-simplices of the prism over the positive tet `c`: point
// v's copies are bottom + v and top + v; split by ascending v (staircase).
void prism_simplices(const Index* c, Index bottom, Index top, Simplex4* out);

struct Fill {
  SimplexMatrix simplices;                   // over [P_S; P_T]
  SimplexMatrix source_cells, target_cells;  // its end facets: K_S over P_S, K_T over P_T, positive in R^3
};

// The Delaunay triangulation in R^4 of P_S at time 0 and P_T at `thickness`.
Fill fill_slab(const PointMatrix& PS, const PointMatrix& PT, double thickness);

// A half's tetrahedralization refined by stellar splits (chapter 6), for the
// stacks of prisms of that half (morph_field.hpp).
struct RefinedCells {
  SimplexMatrix cells;                      // over the points, then the new ones
  PointMatrix new_points;                   // #new by 3: ids n, n+1, ...
  std::vector<std::vector<Index>> splits;   // per new point, the face it split (ids then)
  Index chords = 0, bridges = 0, coarse = 0;  // splits of each kind
  Index outside_chords = 0, flat_chords = 0;  // chords left as they are
};

// Refines the half's cells (`cells` over `points`, the conforming end with
// its input's refined faces `constraints`): the inside chords of the end
// facet (edges, triangles, tets whose corners are all on the input and that
// are not its own: the field would be zero along them at the end), then, in
// `rounds` rounds, edges that at some of the half's `weights` of the blend
// bridge the zero set (its ends of one sign, its middle of the other) or are
// crossed by it and longer than `spacing`. `own` is the end's input's
// signed distance; dS and dT the blend's.
RefinedCells refine_cells(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                          const SimplexMatrix& constraints, const SignedDistance& own, const SignedDistance& dS,
                          const SignedDistance& dT, const std::vector<double>& weights, double spacing, int rounds);

// The slab from a half's refined layer to the fill's (unrefined) one: prisms
// over `cells` (the fill's end facet over its n points) with `splits`
// replayed on the refined layer's copies. Local ids: the refined layer's
// points 0..refined_count-1 (its first n the unrefined points, then the new
// ones), the unrefined layer's refined_count + v.
std::vector<Simplex4> transition_slab(const SimplexMatrix& cells, const std::vector<std::vector<Index>>& splits,
                                      Index n, Index refined_count, bool refined_at_bottom);

// ---------------------------------------------------------------- timing

// The target's weight w in the blend at each share u of the range: the
// inverse of the zero set's accumulated motion, so that it moves at an even
// pace from the first frame to the last.
struct BlendSchedule {
  std::vector<double> u, w;  // increasing, from (0, 0) to (1, 1)
  double operator()(double at) const;
};

// The zero set of the blend at `samples` + 1 weights (the inputs at the
// ends, level sets on K_S and K_T between), the two-sided distance between
// consecutive ones, and their inverse.
BlendSchedule motion_schedule(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                              const SimplexMatrix& FT, const Fill& fill, const PointMatrix& PS,
                              const PointMatrix& PT, const Eigen::VectorXd& sS, const Eigen::VectorXd& tS,
                              const Eigen::VectorXd& sT, const Eigen::VectorXd& tT, int samples);

}  // namespace animanifold::morph_field
