// The peak memory of the core calls whose output size follows from their input, estimated
// before they allocate (memory_limit.hpp checks it against the limit). Each is the output's
// arrays plus what the call holds beside them at its peak, per output vertex and simplex,
// measured by bench/bench_memory_estimates.py (which prints estimate and measured peak side
// by side): an estimate within a small factor of the truth, not a bound.
//
// Inputs the call refuses anyway (too few keyframes, levels out of range, ids out of range)
// are estimated as what their valid part would take, so that the call's own, more precise
// error reaches the caller.
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/memory_limit.hpp"
#include "animanifold/stitch.hpp"
#include "animanifold/subdivide.hpp"

namespace animanifold {

// Inputs:
//   input  as stitch() takes it
// Outputs: stitch()'s estimate: (m*k) points and n*l*(m-1) simplices with their attributes
// Throws: nothing (an input stitch() refuses is estimated, not refused: see above)
MemoryEstimate stitch_memory(const StitchInput& input);

// Inputs:
//   manifold  as subdivide_manifold() takes it
//   levels    its options.levels
// Outputs: subdivide_manifold()'s estimate: 8^levels tets (4^levels triangles) per simplex
// Throws: nothing (levels below 0 count as 0)
MemoryEstimate manifold_subdivision_memory(const Complex& manifold, int levels);

// Inputs:
//   vertices, faces    the frame's sizes (#V, #F) and corners per face (3, 4; 2 for polylines)
//   attribute_columns  columns of all vertex attribute tables together
//   levels             the options' levels
// Outputs: subdivide_frame()'s, subdivide_polyline()'s or smooth_slice()'s estimate: every
//   level's faces (4 per face; 2 per segment), kept by OpenSubdiv's refiner
// Throws: nothing (levels below 0 count as 0)
MemoryEstimate frame_subdivision_memory(Eigen::Index vertices, Eigen::Index faces, int corners,
                                        Eigen::Index attribute_columns, int levels);

// Inputs:
//   vertices, faces    the frame and its faces (or segments), as subdivide_frame() takes them
//   vertex_attributes  its vertex attribute tables
//   levels             the options' levels
// Outputs: the estimate above for that frame
MemoryEstimate frame_subdivision_memory(const PointMatrix& vertices, const SimplexMatrix& faces,
                                        const VertexAttributes& vertex_attributes, int levels);

// Inputs:
//   input           as refine() takes it
//   split_vertices  T by m split faces, -1 padded
// Outputs: refine()'s estimate: each split adds a vertex and splits the simplices around its
//   face into as many as the face has vertices; a face's star is taken as the smallest
//   star of its vertices in the input
// Throws: nothing (ids outside the input's vertices are skipped, not refused)
MemoryEstimate refinement_memory(const Complex& input, const SimplexMatrix& split_vertices);

}  // namespace animanifold
