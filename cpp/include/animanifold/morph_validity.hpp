// The morph's checks on its frames (§8.3 validity 1 beyond positive
// simplices, and the frames' topology).
//
// Inputs: the manifold (tets in R^4), its range, the inputs (for their
// topology and size). Outputs, into the report: which checked frames run
// through themselves (beyond 1e-9 of the size), hold more cavities than
// either input, or leave the inputs' topology (Euler characteristic outside
// the ends', more pieces than the ends'); how many frames were checked and
// whether the bisections below stopped at their limit.
//
// Frames: 24 evenly spread inside the range, each given every check (the
// crossings on the first `crossing_frames` of them in coarse-to-fine order:
// the middle, the quarters, the eighths, ...; all 24 by default, and the
// rest too when `check_the_rest()` says so once `alongside` is done). Then
// the `closer` frames the caller asks for, checked like the bisections. Then,
// between two checked frames whose topology differs, frames bisecting
// towards the change, so that the frames where the topology changes are
// looked at too: up to 5 levels and 24 frames in all, shared evenly between
// the changes (`frames_capped` when changes were left), each checked for
// topology, cavities included, but not for crossings, which cost several
// times a frame's slicing and topology. Each change is bisected on its own,
// so that no core waits for another change's level.
// The frames checked depend only on the manifold, never on the machine's
// speed or thread count. Frames are checked on all cores (the slicer's index
// is built first, then only read). morph() runs it on every 3D morph; the
// binding exposes it for any manifold.
#pragma once

#include "animanifold/morph.hpp"

#include <functional>
#include <vector>

namespace animanifold {

// Inputs:
//   manifold        tets in R^4
//   t0, t1          its range
//   VS, FS, VT, FT  the morph's inputs
//   alongside       work items run by the threads that check the 24
//                   spread frames, before their frames (the morph's checks
//                   of its simplices, its ends and its space-time
//                   triangulation: a core would otherwise idle while they
//                   run); they must not write the report's frame checks
//   crossing_frames how many spread frames are checked for crossings
//                   (0..24; the field method checks the middle one, and the rest
//                   only when its space-time triangulation is not
//                   certified embedded)
//   check_the_rest  optional; asked once the spread frames and `alongside`
//                   are done: true checks the other spread frames for
//                   crossings too
//   closer          optional; more frames checked like the bisections'
//                   (topology, cavities), before them: where the
//                   construction can change between two spread frames
//                   (the field method's fill slab, shorter than their
//                   spacing)
// Outputs:
//   report's frame checks (frames_checked, crossing_frames, bubble_frames, ...)
// Throws: what an `alongside` item or the slicing of a frame throws (the
// first item's first), once the spread frames are checked; nothing else of
// its own
void check_frames(const Complex& manifold, double t0, double t1, const PointMatrix& VS, const SimplexMatrix& FS,
                  const PointMatrix& VT, const SimplexMatrix& FT, MorphReport& report,
                  const std::vector<std::function<void()>>& alongside = {}, int crossing_frames = 24,
                  const std::function<bool()>& check_the_rest = {}, const std::vector<double>& closer = {});

}  // namespace animanifold
