// The field method of morphing (DESIGN.md, "Morph methods"): the animation
// manifold is the zero set of a space-time field phi(x, t) on a conforming
// triangulation of the slab [t0, t1] x a box around both inputs.
//
// Inputs: closed, outward-oriented triangle meshes S and T in R^3 (checked
// by morph()), the morph's options and its stage clock. Output: the
// manifold (tets in R^4) and the report's field entries. Throws
// MeshingError naming the input when the mesher or the fill fails.
//
// The triangulation, layer by layer in time:
//  - At each end, a conforming Delaunay tetrahedralization of the input and
//    free points (a jittered body-centred lattice in the band the surface
//    sweeps, kept clear of the input so it does not encroach on its faces;
//    TetGen -D): its Steiner points go only where conforming needs them.
//  - The source's end stacks prisms over its tetrahedralization K_S for the
//    first half of the range, the target's over K_T for the second (each
//    prism cut into 4-simplices by global vertex order, as stitching does),
//    and one slab in the middle joins them: the Delaunay triangulation in
//    R^4 of K_S's points at its bottom and K_T's at its top, which by
//    Theorem 5.2.1 has K_S and K_T as its end facets.
//  - In the two end slabs, edges, triangles and tets of the end facet whose
//    corners all lie on the input but that are not the input's own (chords)
//    are split at their middle (stellar splits of the 4-simplices around
//    them): otherwise the field, zero at all their corners, would be zero
//    along them and the end frame would gain faces, fins or tunnels.
// The field: signed distance to S at t0 and to T at t1 (exactly zero on
// their vertices and Steiner points), and in between the convex blend
// (1 - w) d_S + w d_T, with w following the zero set's measured motion
// (motion_schedule). Where the inputs barely meet or touch nowhere but lie
// close, that blend is (all but) empty around the middle; it is then
// lowered there by up to a widening (morph_field_internal.hpp's blend and
// middle_widening), so that the shape passes through the space between
// them. Inside T but outside S, d_S is the longer of the straight distance
// and the path inside T from where the two overlap, and d_T likewise
// inside S only (distances_through_inputs): a limb grows from its root and
// retracts from its tip. A point inside both inputs is inside every frame;
// one outside both is outside every frame unless the blend is widened, and
// then only if it lies within the widening of one of them. Its zero set
// (zero_set.hpp) is a closed 3-manifold whose boundary is S at t0 and T at
// t1: every frame is a level set, so none runs through itself.
#pragma once

#include "animanifold/morph.hpp"
#include "morph_stages.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace animanifold {

// The space-time triangulation the zero set is extracted from, in the parts
// its certificate reads: per end, the points and cells the stacks of prisms
// stand on (the conforming end, refined by the chords' splits), the slab
// from them to the fill's end facet, and the times of the layers.
// What the certificate (certify_space_time) finds of one side's cells and
// transition slab: "" for each that tiles its region once, else what fails.
struct SideCover {
  std::string cells, transition;
};

struct SpaceTimeTriangulation {
  struct Side {
    PointMatrix points;                      // the conforming end's, then the chords' middles
    Index plain = 0;                         // the conforming end's points (the fill's)
    SimplexMatrix cells;       // the stacks' cells over `points`
    SimplexMatrix transition;  // the slab from `cells` to the fill's end facet (transition_slab's ids)
    std::vector<double> times; // the layers' times, end first, the fill's last
  };
  Side source, target;
  // The 4-simplices the zero set passes through that are flat but for
  // rounding (the extraction counts them).
  Index flat_crossed_simplices = 0;
};

// Where S and T are the same surface (the same points, and the same faces
// in any order and from any corner: an object and its unmoved duplicate,
// Figure 8.9's case), the blended field is the same at every time and its
// zero set is S swept from t0 to t1. That sweep, S x [t0, t1] stitched as two
// equal keyframes (stitch.hpp), is returned instead of an extraction of it:
// every frame is S exactly, and no simplex is flat (the lattice's zero set
// there runs along S's faces, and on flat parts of S its tets are flat).
// nullopt where the surfaces differ.
std::optional<Complex> swept_when_same(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                                       const SimplexMatrix& FT, double t0, double t1);

struct FieldMorph {
  Morph morph;
  SpaceTimeTriangulation space_time;
  // check_side_cover of the source's side and the target's, made as soon as
  // each side was extracted, beside the fill (certify_space_time reads them).
  std::array<SideCover, 2> covers;
};

FieldMorph field_morph(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT, const SimplexMatrix& FT,
                       const MorphOptions& options, StageClock& clock);

// Whether the space-time triangulation is embedded, so that the zero set of
// any field on it is, and with it every frame at every time: no frame can
// run through itself. Each end's cells and each transition slab must tile
// their convex regions once (convex_cover.hpp), and the layers' times must
// increase from t0 to t1. The stacks of prisms between layers are products
// of an end's cells with an interval of time, split by one vertex order per
// slab (prism_simplices), so they are embedded when the cells are and the
// times increase. The fill is CGAL's Delaunay triangulation of its two
// layers (delaunay_exact, exact predicates), which tiles their convex hull
// by the library's contract; what is checked is what is built on it.
// The zero set is computed, not exact: its corners are rounded where the
// zero set cuts the edges. That moves a piece by a rounding, unless its
// simplex is itself flat but for rounding: there the zero set is a sheet in
// the simplex's hyperplane that the roundings place, and neighbouring
// sheets can fold onto each other with zero thickness (the flat cells of a
// torus's planar quads did: frames crossed themselves by far more than
// rounding while the triangulation was embedded). So the certificate also
// asks that no simplex the zero set passes through be flat.
// `failure` names the first part that is not embedded ("" when all are).
struct SpaceTimeCertificate {
  bool embedded = false;
  std::string failure;
};
// `covers`: the sides' check_side_cover when already made (field_morph's),
// else they are made here.
SpaceTimeCertificate certify_space_time(const SpaceTimeTriangulation& space_time,
                                        const std::array<SideCover, 2>* covers = nullptr);

// The costly part of the certificate, one side's: whether its cells (over
// `points`) and its transition slab tile their regions once. `times` are the
// side's layers' times (at least two; the certificate refuses fewer before it
// reads the covers).
SideCover check_side_cover(const PointMatrix& points, Index plain, const SimplexMatrix& cells,
                           const SimplexMatrix& transition, const std::vector<double>& times);
// Its two checks apart ("" where the part tiles its region once): the
// cells' (ready once the half is built) and the transition slab's (once the
// slab is extracted), which field_morph makes on whichever thread is free.
std::string check_cells_cover(const PointMatrix& points, const SimplexMatrix& cells);
std::string check_transition_cover(const PointMatrix& points, Index plain, const SimplexMatrix& transition,
                                   const std::vector<double>& times);

}  // namespace animanifold
