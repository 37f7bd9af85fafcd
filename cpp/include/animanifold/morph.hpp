// Morphing between closed shapes of any topology (chapters 5 and 8).
//
// The source S is embedded at t0 and the target T at t1; the space between
// them is filled with a Delaunay triangulation A in R^(n+1), which conforms
// with both thanks to Theorem 5.2.1 once S and T have been made conforming
// Delaunay (S', T'). The boundary of A, less the flat caps at t0 and t1, is
// the animation manifold: its slice at t0 is S and at t1 is T. Concave
// inputs and inputs with holes need one of two methods so that A fills only
// what the shapes enclose at the ends:
//  - "strip" (§8.5): simplices of A whose projection onto the plane of S or
//    T lies outside the shape are removed. Ambiguous (Figure 8.8): frames in
//    between can pinch into non-manifold shapes when the genus changes.
//  - "skeleton" (§8.6, the default): each conforming fill also holds free
//    points outside the shape (its external Voronoi skeleton, plus points on
//    any outside face left without one), and those points are pushed into
//    time (§8.6.3) with every simplex positive: in a layer of prisms between
//    each input's plane and the fill (morph_layers.hpp), where the push is
//    never held back. Nothing is left outside the shapes at t0 and t1, A
//    stays a proper triangulation of a ball, and every frame in between is a
//    closed surface: concavities and holes of S close over the first part of
//    the range, those of T open over the last (holes both share are the
//    hole spaces' business, §8.6.5).
//
// Shapes are closed, outward-oriented triangle meshes in R^3 (manifold: tets
// in R^4) or closed polygons in R^2 given as oriented edges (manifold:
// triangles in R^3).
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/enum_names.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/progress.hpp"

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace animanifold {

// How the space between the inputs is filled (see the top of this file and
// morph_field.hpp): the zero set of a blended distance field (the default for
// surfaces), or the seed's skeleton (§8.6) and strip (§8.5) methods (the
// only ones for 2D polygons).
enum class MorphMethod { Field, Skeleton, Strip };
// The seed's Delaunay fill: CGAL's exact one (delaunay_exact) or Qhull's.
enum class FillTriangulation { Cgal, Qhull };
// How the seed's methods put the inputs in general position (see morph.cpp).
enum class Perturbation { HullFaces, Position };

// Each value with the name the Python API, the CLI and the add-on use for it
// (the binding exposes these, so no other list of them exists).
inline constexpr NameTable<MorphMethod, 3> kMorphMethodNames{
    {{MorphMethod::Field, "field"}, {MorphMethod::Skeleton, "skeleton"}, {MorphMethod::Strip, "strip"}}};
inline constexpr NameTable<FillTriangulation, 2> kFillTriangulationNames{
    {{FillTriangulation::Cgal, "cgal"}, {FillTriangulation::Qhull, "qhull"}}};
inline constexpr NameTable<Perturbation, 2> kPerturbationNames{
    {{Perturbation::HullFaces, "hull_faces"}, {Perturbation::Position, "position"}}};

struct MorphOptions {
  // The times of the source and the target. The morph is solved over a span
  // proportional to the shapes' size and mapped onto t0..t1 (see morph.cpp),
  // so it is the same morph over any range: frames at the same fraction of
  // the range are the same.
  double t0 = 0.0, t1 = 1.0;
  // Field (morph_field.hpp; 3D only), Skeleton (§8.6) or Strip (§8.5).
  // Convex inputs need neither of the seed's: both then reduce to the plain
  // fill (no free points, nothing stripped).
  MorphMethod method = MorphMethod::Field;
  // Skeleton method: the thickness of each layer the free points are pushed
  // in (morph_layers.hpp), as a fraction of t1 - t0: the source's concavities
  // close within it after t0, the target's open within it before t1.
  double max_push = 0.45;
  // The fill's Delaunay triangulation: Cgal (delaunay_exact, the default:
  // Qhull's time grows quadratically on the fill's two planes of points) or Qhull.
  FillTriangulation fill = FillTriangulation::Cgal;
  // How the inputs are put in general position (see morph.cpp):
  // HullFaces (perturbed_along_hull_faces, the default: points on the
  // inputs' hulls stay where they are, so the hulls' flat sides and
  // collinear edges stay exact and the exact fill resolves their ties) or
  // Position (perturbed_by_position: every point; the Python morph()
  // retries with it when frames run through themselves).
  Perturbation perturbation = Perturbation::HullFaces;
  // 3D: flat convex polygons of six corners or more (a cylinder's or a cone's
  // caps) are triangulated again as fans from their centre before meshing
  // (fan_flat_polygons, flat_polygons.hpp): their chords between cocircular
  // rim points are what the conforming mesher cannot settle.
  bool fan_flat_polygons = true;
  // Field method: the number of time slabs (odd: the source's half, the
  // slab joining the two, the target's half) and the free points' lattice,
  // as cells across the shapes' size (morph_field.hpp).
  int field_layers = 17;
  double field_resolution = 24;
  // progress() is called with (stage, fraction done) between stages;
  // returning false cancels (the call then throws Cancelled). interrupted()
  // is polled about every 0.1 s while a mesher runs in its child process
  // (TetGen takes seconds on large inputs, and on unlucky ones runs until its
  // timeout); returning true stops it and cancels the morph. The Python
  // binding checks for a Ctrl-C there.
  Interrupter interrupter;
  // For tests of cancellation: at the start of the stage named `hold_stage`,
  // a stand-in child process sleeps `hold_seconds` under the same polling as
  // TetGen's, so a cancel or a Ctrl-C can be tested while the core waits on
  // a child, whatever the input and the machine.
  std::string hold_stage;
  double hold_seconds = 0;
  // Seconds each TetGen run may take (a safety net: TetGen can loop for
  // ever); <= 0, the default allowance of 5 s + 0.5 ms a face. A run past it
  // fails the morph with TimeLimitError, never a retry at another
  // perturbation: the result must not depend on the machine's speed. Tests
  // give a tiny limit to take that path whatever the machine.
  double mesher_time_limit = 0;
};

// What the checks of §8.3 found, and what each stage cost.
struct MorphReport {
  // Theorem 5.2.1: refined constraint faces of S' and T' not found in the fill.
  Index missing_source_faces = 0, missing_target_faces = 0;
  bool source_conforming = false, target_conforming = false;  // the mesher's result was Delaunay
  Index flat_fill_simplices = 0;  // zero-volume simplices across the two planes inside the fill (refused then)
  // Both inputs convex: the fill was built from the hull's faces at the exact
  // coordinates (morph_convex.hpp), not by a Delaunay fill of perturbed points.
  bool exact_convex_fill = false;
  Index peeled_hull_slivers = 0;  // zero-volume simplices across the planes on the hull's boundary, left out
  double perturbation = 0.0;      // of the size, used for the combinatorics only (see morph.cpp)
  // Steiner points left where the mesher put them, because nudging them off
  // their edges and faces would lose a refined face (nudged_steiner_points).
  Index unnudged_steiner_points = 0;
  Index fill_simplices = 0, stripped_simplices = 0;
  Index simplices = 0;  // of the filled shape A: what is kept of the fill, and the layers
  // Skeleton method: simplices removed from prisms over cells both inputs
  // share and that lie outside both (shared_outside_prisms).
  Index shared_stripped_simplices = 0;
  // Every simplex of the fill lies in such a prism: the inputs coincide (up
  // to their triangulations' Steiner points), every frame is the input, and
  // no frame enters the hole space.
  bool inputs_coincide = false;
  // Field method: no point of its ends' tetrahedralizations lies inside both
  // inputs, so they do not overlap where they are (their transforms place
  // them), and they lie too far apart for the blend to be widened between
  // them (middle_widening below): the blend then shrinks the source away
  // where it stands and grows the target where it stands, nothing travels
  // between them. False for the seed's methods, which do not look.
  bool inputs_apart = false;
  // Skeleton method: skeleton points given per input, free vertices of the
  // conforming fills (skeleton points and the mesher's Steiner points off the
  // surface), and in the layers (PlaneLayer): faces outside an input without
  // a free vertex split, long edges outside it split, cells flat to rounding
  // on a hull left out, how far the free vertices were pushed (fractions of
  // t1 - t0: smallest, mean, largest), how many the levelling moved off the
  // heights of their distance from the input, and how many lie in regions
  // that do not reach a hull. Field method: split_faces counts the stellar
  // splits of the halves' cells (chords inside an input, and edges from an
  // input along which the blend bends), refinement_points the free points
  // added where the zero set needs them.
  Index source_skeleton_points = 0, target_skeleton_points = 0;
  Index source_cap_points = 0, target_cap_points = 0;  // of those, over flat sides of the hulls (hull_cap_points)
  Index source_fanned_polygons = 0, target_fanned_polygons = 0;  // MorphOptions::fan_flat_polygons
  Index source_free_vertices = 0, target_free_vertices = 0;
  Index split_faces = 0, refinement_points = 0, peeled_slivers = 0;
  std::array<double, 3> source_push{0, 0, 0}, target_push{0, 0, 0};
  Index levelled_vertices = 0, sealed_vertices = 0;
  // Validity 1, at the exact coordinates: the smallest signed hypervolume of
  // the kept simplices, the smallest relative to its longest edge L (the
  // determinant over L^(n+1): 1 for a cube's corner, 0 for a flat one), how
  // many are inverted (negative beyond anything restoring the exact
  // coordinates can do) and how many are degenerate (zero or negative within
  // it: flat at the exact coordinates, cells of the inputs' degenerate
  // configurations — four coplanar or cocircular points — whose orientation
  // the perturbation decided; see morph.cpp).
  double min_volume = 0.0, min_relative_volume = 0.0;
  Index inverted_simplices = 0, degenerate_simplices = 0;
  // Validity 2: one-sided distances between the slices at t0/t1 and the
  // inputs, relative to the bounding-box diagonal (every slice vertex on the
  // input, every input vertex in the slice).
  double source_distance = 0.0, target_distance = 0.0;
  bool ends_reproduced = false;
  // Field method: Steiner points the conforming mesher put on each input (the
  // end frames carry them), the time slabs, the free points' lattice
  // spacing (of the size).
  Index source_steiner_points = 0, target_steiner_points = 0;
  // Of those, the midpoints of planar quads' diagonals that mend flat cells
  // (conforming_mend.hpp's flat_surface_cells), and the flat cells left (the
  // field method first adds free points beside them, counted in
  // refinement_points): each a fold of zero thickness wherever the frames
  // pass it.
  Index flat_cell_points = 0, flat_cells = 0;
  // Points of one end moved (by at most 1e-12 of the size) onto the other's
  // where the two coincided but for rounding (share_coincident_points).
  Index shared_points = 0;
  int field_layers = 0;
  double lattice_spacing = 0.0;
  // Field method: how much the blend was lowered at the middle, of the size
  // (0 where the inputs overlap well; morph_field_internal.hpp's
  // middle_widening): inputs that barely meet pass through the space
  // between them instead of shrinking to nothing there.
  double middle_widening = 0.0;
  // The frames' checks (morph_validity.hpp): how many frames were looked at
  // (24 spread over the range, the field method's 7 in its fill slab, then
  // up to 24 towards the changes of topology), whether changes were left
  // unbisected at that limit, and the times of frames that run through
  // themselves (checked on the spread frames), hold a bubble neither input
  // has, or leave the inputs' topology.
  Index frames_checked = 0;
  bool frames_capped = false;
  // Crossings: how many of the spread frames were checked for them (the
  // middle and the quarters first), and, for the field method, whether its
  // space-time triangulation is certified embedded, which rules them out in
  // every frame at every time (morph_field.hpp's certify_space_time); when
  // it is not, what failed, and every spread frame is checked instead.
  Index crossing_frames_checked = 0;
  bool crossings_certified = false;
  std::string certificate_failure;
  // How often the topology (Euler characteristic, pieces, cavities) changes
  // from one checked frame to the next, in time order.
  Index topology_changes = 0;
  std::vector<double> crossing_frames, noise_frames;
  // (time, bubbles beyond the inputs' own) of each frame holding bubbles,
  // and the largest share of a frame's volume they take.
  std::vector<std::pair<double, Index>> bubble_frames;
  double largest_bubble_fraction = 0.0;
  std::vector<std::pair<std::string, double>> stage_seconds;
};

// Inputs:
//   report  a morph's report
//   visit   called as visit(name, value) for every entry, in the order declared
// Outputs: nothing but the calls
// Throws: whatever visit throws
//
// The one list of the report's names (the binding's MorphReport.to_dict(),
// which the cache stores, comes from it).
template <class Visit>
void for_each_entry(const MorphReport& report, Visit&& visit) {
  visit("missing_source_faces", report.missing_source_faces);
  visit("missing_target_faces", report.missing_target_faces);
  visit("source_conforming", report.source_conforming);
  visit("target_conforming", report.target_conforming);
  visit("flat_fill_simplices", report.flat_fill_simplices);
  visit("peeled_hull_slivers", report.peeled_hull_slivers);
  visit("exact_convex_fill", report.exact_convex_fill);
  visit("perturbation", report.perturbation);
  visit("unnudged_steiner_points", report.unnudged_steiner_points);
  visit("fill_simplices", report.fill_simplices);
  visit("stripped_simplices", report.stripped_simplices);
  visit("simplices", report.simplices);
  visit("shared_stripped_simplices", report.shared_stripped_simplices);
  visit("inputs_coincide", report.inputs_coincide);
  visit("inputs_apart", report.inputs_apart);
  visit("source_skeleton_points", report.source_skeleton_points);
  visit("target_skeleton_points", report.target_skeleton_points);
  visit("source_cap_points", report.source_cap_points);
  visit("target_cap_points", report.target_cap_points);
  visit("source_fanned_polygons", report.source_fanned_polygons);
  visit("target_fanned_polygons", report.target_fanned_polygons);
  visit("source_free_vertices", report.source_free_vertices);
  visit("target_free_vertices", report.target_free_vertices);
  visit("split_faces", report.split_faces);
  visit("refinement_points", report.refinement_points);
  visit("peeled_slivers", report.peeled_slivers);
  visit("source_push", report.source_push);
  visit("target_push", report.target_push);
  visit("levelled_vertices", report.levelled_vertices);
  visit("sealed_vertices", report.sealed_vertices);
  visit("min_volume", report.min_volume);
  visit("min_relative_volume", report.min_relative_volume);
  visit("inverted_simplices", report.inverted_simplices);
  visit("degenerate_simplices", report.degenerate_simplices);
  visit("source_distance", report.source_distance);
  visit("target_distance", report.target_distance);
  visit("ends_reproduced", report.ends_reproduced);
  visit("source_steiner_points", report.source_steiner_points);
  visit("target_steiner_points", report.target_steiner_points);
  visit("flat_cell_points", report.flat_cell_points);
  visit("shared_points", report.shared_points);
  visit("flat_cells", report.flat_cells);
  visit("field_layers", report.field_layers);
  visit("lattice_spacing", report.lattice_spacing);
  visit("middle_widening", report.middle_widening);
  visit("frames_checked", report.frames_checked);
  visit("frames_capped", report.frames_capped);
  visit("crossing_frames_checked", report.crossing_frames_checked);
  visit("crossings_certified", report.crossings_certified);
  visit("certificate_failure", report.certificate_failure);
  visit("topology_changes", report.topology_changes);
  visit("crossing_frames", report.crossing_frames);
  visit("bubble_frames", report.bubble_frames);
  visit("largest_bubble_fraction", report.largest_bubble_fraction);
  visit("noise_frames", report.noise_frames);
  visit("stage_seconds", report.stage_seconds);
}

struct Morph {
  Complex manifold;  // n-simplices in R^(n+1), oriented like stitched manifolds
  MorphReport report;
};

// Inputs:
//   V, F  the input: #V by d points, #F by d faces
//   name  "source" or "target", for the message
// Outputs: nothing
// Throws: InputError (see below)
//
// What morph() checks of each input first: throws InputError naming the
// shape (`name`: "source", "target") and the face or vertex when it is not a
// closed, consistently outward-oriented manifold without self-intersections
// (2D: closed counter-clockwise polygons), has non-finite points, points
// beyond kMaxCoordinate (coordinate_bound.hpp) or faces out of range.
void check_morph_input(const PointMatrix& V, const SimplexMatrix& F, const std::string& name);

// Inputs:
//   source_points, source_faces  the source: #V by d points, #F by d faces (d = 3 or 2)
//   target_points, target_faces  the target, in the same dimension
//   options                      times, method, push, fill, perturbation, progress, interrupt
// Outputs:
//   Morph: the manifold (n-simplices in R^(n+1), source at t0, target at t1) and the MorphReport
// Throws: InputError, MeshingError (see below); Cancelled when progress()
//   returns false or interrupted() returns true
//
// Throws InputError naming the shape and face when an input is not a closed,
// consistently oriented manifold (open inputs are refused), and
// MeshingError when a mesher fails.
Morph morph(const PointMatrix& source_points, const SimplexMatrix& source_faces, const PointMatrix& target_points,
            const SimplexMatrix& target_faces, const MorphOptions& options = {});

// Inputs:
//   V, F  the closed outward shape
//   gap   the least distance kept from the surface and between points
// Outputs:
//   #K by d skeleton points off the surface
// Throws: InputError as voronoi_skeleton; MeshingError when Qhull or CGAL fails
//
// §8.6.1 step 1 of the skeleton method: the vertices of the external Voronoi skeleton of the closed outward shape
// (V, F) that lie off the surface, at least `gap` from it and from each
// other (on symmetric shapes many Voronoi vertices lie within roundoff of one
// place and would only make slivers). #K by d; empty for convex shapes.
PointMatrix external_skeleton_points(const PointMatrix& V, const SimplexMatrix& F, double gap);

// Inputs:
//   points       the fill's points, #P by n+1
//   A            #A by n+2 simplices
//   first, last  the constraint plane's points (or a mask, below)
//   constraint   the closed outward refined faces, indexing points
//   exact        optional: the points unperturbed
// Outputs:
//   per simplex of A, whether its projection lies outside the constraint
// Throws: InputError when the plane mask does not match the points
//
// Marks, for each simplex of the fill `A` (#A by n+2 over `points`), whether
// its projection onto the constraint plane of the points in [first, last)
// lies outside the closed constraint `constraint` (refined faces, outward,
// indexing `points`) — the stripping test of §8.5 for one constraint.
// With `exact` (the same points unperturbed), cells that are flat there are
// kept whatever side the perturbation tipped them to.
std::vector<bool> outside_of_constraint(const PointMatrix& points, const SimplexMatrix& A, Index first, Index last,
                                        const SimplexMatrix& constraint, const PointMatrix* exact = nullptr);

// Inputs: as above, with
//   plane  #P flags: the constraint plane's points
// Outputs: as above
// Throws: InputError when plane does not have one flag per point
//
// The skeleton method gives its plane's points by a mask: it leaves the free
// points out, as they are pushed off the plane.
std::vector<bool> outside_of_constraint(const PointMatrix& points, const SimplexMatrix& A, const std::vector<bool>& plane,
                                        const SimplexMatrix& constraint, const PointMatrix* exact = nullptr);

// Inputs:
//   points      #P by n (or more) points
//   cells       #C by n+1 cells of a triangulation holding the constraint's faces
//   constraint  the closed outward faces
//   flat        optional: cells never outside
// Outputs:
//   per cell, whether it lies outside the shape
// Throws: MeshingError when a constraint face is not a face of the triangulation
//
// For each cell (row of n+1 vertices: tets in R^3, triangles in R^2, over
// the first n coordinates of `points`) of a triangulation whose faces include
// the closed outward `constraint`: whether it lies outside the shape, found
// by growing from the outer side of every constraint face without crossing
// one (§8.5.2). Cells flagged in `flat` are never outside. Throws when a
// constraint face is not a face of the triangulation.
std::vector<bool> outside_cells(const PointMatrix& points, const SimplexMatrix& cells, const SimplexMatrix& constraint,
                                const std::vector<bool>& flat = {});

}  // namespace animanifold
