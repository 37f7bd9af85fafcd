// The skeleton method of morphing (§8.6): free points in each input's
// conforming fill (the push of those points into time: morph_layers.hpp).
//
// A fill of the convex hull of S' at t0 contains cells outside S (in its
// concavities and holes). Were they left at t0, the animation manifold would
// start as the convex hull, not as S; stripping them (§8.5) leaves frames
// that can pinch. Instead every outside cell gets a vertex that is neither
// on S nor inside it — a free vertex: the external Voronoi skeleton's
// vertices (§8.6.1, chosen because they lie as far from the surface as the
// concavity allows), plus a point on any outside face still without one
// (the attachment concern of §8.6.2, Figure 8.11: split_faces). After the
// fill in R^(n+1) the free vertices move off the plane (§8.6.3): every
// outside cell then tilts into time and the cap at t0 is exactly S's inside.
#pragma once

#include "animanifold/delaunay.hpp"
#include "animanifold/morph.hpp"

#include <limits>
#include <string>
#include <array>
#include <vector>

namespace animanifold {

// external_skeleton_points (§8.6.1 step 1) is declared in morph.hpp: the
// binding exposes it.

// How far each of `points` (#P by d) lies inside the convex hull of `V`:
// the distance to the nearest hull facet's plane (line in 2D), negative
// outside. CGAL's convex hull.
Eigen::VectorXd depth_in_hull(const PointMatrix& points, const PointMatrix& V);

// The convex hull of the 3D points `V` (CGAL's) as outward triangles over
// V's rows (the first of duplicate points), in CGAL's order: a flat side's
// triangulation, and that order, can change from one call to the next.
std::vector<std::array<Index, 3>> convex_hull_triangles(const PointMatrix& V);

// Per row of `points` (#P by 3): whether it lies in the plane of a facet of
// the convex hull of `V` (#V by 3), within 1e-12 of V's size — on the hull's
// boundary, for points of V or on its surface. All false outside 3D.
std::vector<bool> on_convex_hull(const PointMatrix& points, const PointMatrix& V);

// Free points for the flat sides of the convex hull of the closed outward
// shape (V, F) (#V by 3) that bridge what lies outside it — a torus's top
// and bottom discs over its hole — just outside the hull: one over each
// hole in the part of a side the shape's own faces cover (a voxel plate's
// top: three), and one over the side's centre where more is uncovered (a
// torus's disc). Without them such a side is made of the input's vertices
// only, which stay in the plane: the pushed free points inside empty the
// hole from within while the discs stay solid, and the frames before t1 hold
// the hole as a bubble (Blender's cube -> torus: 23 % of the frame's volume
// at 0.9 of the range). With a point over the disc, the disc is a face
// between two outside cells, split and pushed like any other, and the hole
// opens from both ends. Empty in 2D, for shapes whose hull has no such side,
// and for sides whose points all lie on the input (a side of a voxel model
// that is the input's own face).
PointMatrix hull_cap_points(const PointMatrix& V, const SimplexMatrix& F);

// perturbed_by_position, except that points on the convex hull's boundary
// do not move: flat sides of the hull stay flat, segments in them stay
// parallel to each other, and a facet of the fill's hull in R^4 that spans
// both inputs in one hyperplane stays in it. With the plain perturbation,
// points of a flat side (a voxel plate's top, collinear points along its
// hull edges) bump in and out of the hull, and the fill's lateral boundary
// holds slivers there that fold once the exact coordinates are back: frames
// that run through themselves. Moving those points within their sides is
// not enough: it breaks the parallels between a cube's side and a voxel
// plate's side facing it (a 1.2x cube -> the voxel plate runs through itself
// at 5 of 5 checked frames that way). Keeping only the flat sides' points is
// not enough either: where two mirror-image corners of an icosphere and an
// edge of the voxel plate parallel to their chord lie in one hyperplane of
// R^4 (a facet of the fill's hull), perturbing the corners bends it and the
// slivers across it fold at the exact coordinates (an icosphere -> the voxel
// plate sticking out of it, Blender's UV sphere -> its torus). So every hull
// point stays; the exact Delaunay fill resolves the ties of unmoved points
// itself. The default (MorphOptions::perturbation); the Python morph()
// retries with perturbed_by_position when frames still run through
// themselves.
PointMatrix perturbed_along_hull_faces(const PointMatrix& V, double scale, std::uint64_t salt);

struct ConformingInput {
  ConformingDelaunay fill;  // of the shape and its free points K: the shape's vertices first, then K, then Steiner points
  PointMatrix exact_points;  // fill.points with the exact coordinates back (restore_on_input); K as given
};

// Conforming Delaunay of the closed outward shape (V, F) with the points K
// (#K by d, outside the shape) inserted. V is the shape perturbed into
// general position, V_exact the shape itself (see morph.cpp). Throws
// MeshingError naming the shape (`name`: "source", "target") and how
// many faces failed when the mesher's result does not conform.
// `while_meshing`, `mesher_time_limit`: see conforming_delaunay_3d (3D only:
// CGAL's 2D mesher runs in this process and is quick).
ConformingInput conform_with_points(const PointMatrix& V, const PointMatrix& V_exact, const SimplexMatrix& F,
                                    const PointMatrix& K, const std::string& name,
                                    const std::function<void()>& while_meshing = {}, double mesher_time_limit = 0);

// The points of the conforming fill `c` with its Steiner points (rows
// `first` on: the mesher's and the mending's, on the input's edges and faces)
// nudged off those edges and faces by up to `amount` per coordinate (a
// function of position, perturbation.hpp), for the fill in R^(n+1): Qhull
// may put three collinear points in one flat simplex. A point whose nudge
// loses a refined face from the Delaunay triangulation of the points goes
// back to where it was, until none is lost; `unnudged` is increased by how
// many. Midpoint refinement leaves pieces of a facet with cocircular
// corners (a cyclic trapezoid), whose diagonal only the exact predicate on
// the mesher's own coordinates settles the mesher's way: TetGen's first run
// on bunny.off has 10 such faces that the nudge alone would lose.
// Points flagged in `stay` (per point of c; empty: none) are not nudged.
PointMatrix nudged_steiner_points(const ConformingDelaunay& c, Index first, double amount, Index& unnudged,
                                  const std::vector<bool>& stay = {});

// The fill `c` was built on `perturbed` input: input vertices get their exact
// coordinates `V` back, and every point the mesher added on an input face is
// put on that face of `V` at the same barycentric coordinates, so the result
// lies exactly on the input surface. Other points keep their place.
PointMatrix restore_on_input(const ConformingDelaunay& c, const PointMatrix& perturbed, const PointMatrix& V,
                             const SimplexMatrix& F);

// One input's plane in the fill: its cells (the fill's facets whose corners
// all lie in the plane: the triangulation of the plane that Theorem 5.2.1
// speaks of, as the fill made it), which of them lie outside the input, and
// its free vertices (vertices of outside cells on no constraint face: they
// are pushed off the plane).
struct PlaneCells {
  SimplexMatrix cells;        // #C by n+1, fill vertex ids
  std::vector<bool> outside;  // per cell
  // Per cell: flat on the surface — zero volume at the exact coordinates (to
  // rounding) and
  // two constraint faces, such as the second diagonal of a planar quad of
  // the input (or one, for a convex input: classify_plane). Neither in nor out (as in stripping): the perturbation tipped
  // it to a side at random. Other flat cells (in a flat facet of the convex
  // hull across a hole, say) are outside or inside like any cell.
  std::vector<bool> flat;
  std::vector<bool> free;     // per fill vertex
};

// The cells of the plane of the points flagged `in_plane` in the fill `A`
// (#A by n+2 over `P`, #P by n+1, the perturbed coordinates the fill was
// built on), classified against the closed outward `constraint` (refined
// faces, fill vertex ids); flatness is judged on `exact` (#P by n+1 or more
// columns; the first n are read). `convex`: the input has no exterior
// skeleton (nothing of its hull lies outside it), so a cell outside it can
// only be flat at the exact coordinates: such a cell with all corners on the
// surface and a constraint face is flat too, though it has one only (cells
// of cocircular points of a flat side, a Blender cylinder's caps: outside,
// their faces were split and pushed into time for nothing, and the
// frames folded over them).
PlaneCells classify_plane(const PointMatrix& P, const PointMatrix& exact, const SimplexMatrix& A,
                          const std::vector<bool>& in_plane, const SimplexMatrix& constraint, bool convex = false);

// Where the source and the target coincide (identical inputs: the rockerArm
// of Figure 8.9; or a part both share), the fill holds prisms σ × [t0, t1]
// over a cell σ that both planes have, with the same corners at the same
// places: σ is Delaunay in both planes, so the eight (2D: six) corners are
// cospherical in R^(n+1) and the prism is a cell of the Delaunay
// subdivision, which the fill triangulates with those corners only. A prism
// over a cell outside both inputs is outside the shape at every time:
// pushing its free vertex would fill it in every frame in between (a
// concavity of the rockerArm closing and opening again, left for the hole
// space to cut back), so it is removed instead — the unambiguous case of
// stripping (§8.5): Figure 8.8's ambiguity is a simplex joining different
// cells of the two planes, and no such simplex is touched. Returns, per
// simplex of `A` (#A by n+2 over `P`): NotShared, or in a prism over a shared
// cell inside the inputs (SharedInside) or outside both (SharedOutside).
// Vertices of the two planes (`in_source`, `in_target`) coincide when their
// first n coordinates are equal bit for bit (the perturbation is a function
// of position, see perturbation.hpp). Flat cells count as inside.
enum class Prism : std::int8_t { NotShared, SharedInside, SharedOutside };
std::vector<Prism> shared_prisms(const PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& in_source,
                                        const std::vector<bool>& in_target, const PlaneCells& source_plane,
                                        const PlaneCells& target_plane);

// The faces of a plane that lie outside the input (faces of outside cells
// and of no inside or flat cell) and have no free vertex: edges first, then
// triangles, then cells (2D: edges, then triangles), each left out when one
// of its own faces is listed already (that split gives it a free vertex).
std::vector<std::vector<Index>> uncovered_outside_faces(const PlaneCells& plane);

// Splits each face (a list of 2 to D+1 vertices of the positively oriented
// simplices `A`, #A by D+1 over `P`, #P by D: a plane's cells, or the 4D
// layer replaying their splits) at a point near its centroid (random weights
// in [1, 2], see the .cpp), one after the other: every simplex holding the
// face becomes one simplex per face vertex, that vertex replaced by the new
// one — all positive again, checked by the exact predicate. Used on faces
// outside an input that have no free vertex (chords across a hole,
// triangles spanning it, cells) and on long edges outside it
// (morph_layers.hpp): the new vertex is free, and once pushed nothing
// outside stays in the plane (a chord left in it would show as a thread
// through the hole in the frames before t1). A stellar split keeps the
// triangulation without another run of the mesher (whose conforming result
// can fail once points are added near the surface). Returns the new
// vertices, appended to `P`.
struct SplitOptions {
  // #faces by P's columns: where each split point goes, instead of a point
  // drawn near the centroid (the caller keeps it on its face).
  const PointMatrix* positions = nullptr;
  // A face none of whose trial points keeps every simplex of its star
  // positive (by the exact predicate) is left unsplit (its entry of the
  // result is -1) instead of split at the best of them.
  bool skip_unsafe = false;
  // With it, a new simplex thinner than this (|det| over its longest edge to
  // the power of the dimension) counts as inverted too.
  double thinnest = 0.0;
  // Filled with the row of `A` each row of the result was split from.
  std::vector<Index>* parents = nullptr;
};
IndexVector split_faces(PointMatrix& P, SimplexMatrix& A, const std::vector<std::vector<Index>>& faces,
                        const SplitOptions& options = {});

}  // namespace animanifold
