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
// (1 - w) d_S + w d_T, with w linear in time: a point outside both inputs is
// outside every frame, one inside both inside every frame. Its zero set
// (zero_set.hpp) is a closed 3-manifold whose boundary is S at t0 and T at
// t1: every frame is a level set, so none runs through itself.
#pragma once

#include "animanifold/morph.hpp"
#include "morph_stages.hpp"

namespace animanifold {

Morph field_morph(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT, const SimplexMatrix& FT,
                  const MorphOptions& options, StageClock& clock);

}  // namespace animanifold
