// Keyframes with vertex correspondence → animation manifold (§2.2).
//
// m keyframes of k vertices share one connectivity of l faces (triangles in
// R^3, or edges of closed polygons in R^2). Keyframe i is embedded at time
// times[i]; vertex j of keyframe i becomes manifold vertex i*k + j. Each
// face sweeps a prism between consecutive keyframes, split into n simplices
// (3 tets, or 2 triangles) by the global order of the face's vertex indices:
// a side quad shared by two prisms is split along the same diagonal in both,
// so the result is conforming (any global order works; `vertex_order`
// chooses one). The manifold has exactly n·l·(m−1) simplices,
// its boundary is the first keyframe (in its own orientation) and the last
// keyframe (reversed), and slicing at times[i] gives keyframe i back.
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/progress.hpp"

#include <cstdint>

namespace animanifold {

struct StitchInput {
  // (m*k) by d keyframe positions, keyframe-major: row i*k + j is vertex j of
  // keyframe i (d = 3 for triangle meshes, d = 2 for polygons).
  PointMatrix frames;
  // l by d faces (triangles when d = 3, edges when d = 2), shared by all keyframes.
  SimplexMatrix faces;
  // m strictly increasing, finite times.
  Eigen::VectorXd times;
  // Per-vertex float attributes: k by c (constant over time) or (m*k) by c.
  VertexAttributes vertex_attributes;
  // Per-face integer attributes: l by c, carried onto every simplex of the face's prisms.
  SimplexAttributes face_attributes;
  // Optional: the keyframe vertices (k of them) in the order that splits the
  // prisms (default: by index). Copies of one point (a vertex split at a UV
  // seam) placed next to each other in it get matching splits on both sides
  // of the seam, so welding the copies later closes the seam.
  IndexVector vertex_order;
};

// Inputs:
//   input        StitchInput: frames (m*k) by d, faces l by d, times m, attributes, vertex_order
//   interrupter  told of the steps "checks", "prisms" (once per keyframe gap) and "attributes"
// Outputs:
//   the manifold: (m*k) by d+1 points (time last), n*l*(m-1) by d+1 simplices,
//   vertex attributes per point, face attributes per simplex
// Throws: see below; MemoryLimitError when its estimate (memory_estimates.hpp) exceeds memory_limit()
//
// Throws InputError naming the keyframe, vertex or face at fault: fewer than
// two keyframes, frames not a multiple of the keyframe count, non-finite
// coordinates, non-increasing times (or times whose span overflows), face
// indices out of range or repeated, a face together with its exact reverse
// (both would vanish from every slice), attribute tables of the wrong size,
// or a manifold too large for 32-bit indices. Cancelled when the interrupter
// says so.
Complex stitch(const StitchInput& input, const Interrupter& interrupter = {});

// Inputs:
//   keyframes, vertices, faces  m, k (per keyframe) and l, in 64 bits
//   corners                     vertices per face (n)
// Throws: InputError when the manifold's m*k points or n*l*(m-1) simplices
//   would not fit a 32-bit index. stitch() calls it before allocating.
void check_stitch_size(std::int64_t keyframes, std::int64_t vertices, std::int64_t faces, int corners);

// Inputs:
//   segment              the keyframe gap: the prism between keyframes segment and segment+1
//   face                 the keyframe face
//   face_count           l
//   simplices_per_prism  n
// Outputs: the first manifold simplex that face's prism became, (segment * l + face) * n,
//   in 64 bits (a row index); the prism's n simplices are consecutive from there
// Throws: nothing (nothing is checked)
inline Eigen::Index stitched_simplex(Index segment, Index face, Index face_count, int simplices_per_prism) {
  return (Eigen::Index{segment} * face_count + face) * simplices_per_prism;
}

}  // namespace animanifold
