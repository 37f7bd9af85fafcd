// Smoothing subdivision of animation manifolds (§4.3, Figure 4.6, §10.2.2)
// and OpenSubdiv refinement of sliced frames (§10.3.1).
//
// Manifold subdivision follows Schaefer, Hakenberg and Warren, "Smooth
// subdivision of tetrahedral meshes" (SGP 2004). One level:
//
//  1. Split. Every tetrahedron becomes 4 corner tetrahedra and an octahedron
//     (vertices: its six edge midpoints); every octahedron becomes 6 corner
//     octahedra and 8 tetrahedra around a new centre vertex. Cells are kept as
//     a hybrid tet/oct mesh between levels, as in the paper.
//  2. Average. Each vertex moves to the mean, over its incident cells, of the
//     cell's local mask: tetrahedron  -1/16 at the vertex, 17/48 at each other
//     vertex; octahedron 3/8 at the vertex, 1/12 at each of its four
//     neighbours, 7/24 at the opposite vertex. (Regular tet/oct lattices give
//     the C^2 trivariate box spline; the paper shows C^1 along edges of the
//     base mesh.) The triangle analogue (2D animations: triangles in R^3) splits
//     1→4 and uses the mask 1/4 at the vertex, 3/8 at the others, which is
//     Loop's box spline on regular meshes; polylines use 1/2, 1/2 (cubic
//     B-splines).
//
// After the last level every octahedron is cut into 4 tetrahedra along its
// shortest diagonal (ties broken by vertex ids, so the result is
// deterministic). An octahedron's faces are its own triangles whichever
// diagonal is chosen, so the cut is conforming whatever the neighbours do.
// The output therefore has exactly 8^levels times the input's tetrahedra
// (4^levels triangles for 2D animations), and every child keeps its parent's
// orientation sense (check_manifold stays clean; in a full-dimensional
// embedding all child volumes have the parent's sign).
//
// Boundary rule. Boundary facets (for a stitched manifold: the first and last
// keyframe) are grouped into patches: a facet whose vertices share one time
// value lies on that keyframe hyperplane; any other boundary facet (the sweep
// of an open keyframe's border) belongs to the "side" patch. Boundary vertices
// are averaged only with boundary facets (the triangle or segment mask above),
// so a keyframe patch stays inside its hyperplane (its time coordinate is
// restored exactly); where patches meet (creases) vertices are averaged only
// along the crease (segment mask); crease corners stay fixed. The ends of the
// manifold therefore remain its boundary, at the first and last time.
//
// Vertex attributes are carried with the same stencils as positions (split,
// then averaged); simplex attributes are inherited from the input simplex.
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/enum_names.hpp"
#include "animanifold/progress.hpp"
#include "animanifold/slice.hpp"

#include <string>
#include <vector>

namespace animanifold {

enum class ManifoldScheme {
  Schaefer,  // split + averaging (smooth)
  Linear,    // split only: the same refinement without moving any point
};

// The names users choose from, the default first (enum_names.hpp).
inline constexpr NameTable<ManifoldScheme, 2> kManifoldSchemeNames{
    {{ManifoldScheme::Schaefer, "schaefer"}, {ManifoldScheme::Linear, "linear"}}};

struct ManifoldSubdivisionOptions {
  int levels = 1;
  ManifoldScheme scheme = ManifoldScheme::Schaefer;
  // Points that lie on a keyframe hyperplane stay on it, so slices at
  // keyframe times stay attached to those times (the first and last keyframe
  // stay on their hyperplanes in any case: boundary rule). An interior point
  // that the averaging moved off its hyperplane by dt is slid back along the
  // manifold — along the time axis projected onto the tangent space, from the
  // manifold's normal when D == columns (tets in R^4, triangles in R^3) —
  // and not just reset in time, which would shift moving shapes by
  // velocity * dt. Otherwise (and for boundary points) only the time
  // coordinate is reset. Vertex attributes are not slid.
  bool keep_keyframe_times = false;
  // The keyframe times. Empty: inferred as every time value t at which some
  // facet of a simplex lies entirely on the hyperplane {time = t} (for a
  // stitched manifold, exactly its keyframe times).
  std::vector<double> keyframe_times;
};

struct ManifoldSubdivision {
  Complex manifold;  // 8^levels tets (4^levels triangles) per input simplex
  // #V' by 2, relative to the vertices of the previous level (the input when
  // levels == 1): (v, v) for a vertex that existed (same id: vertex v of the
  // input is vertex v of the output), (a, b) with a < b for the midpoint of
  // edge (a, b), (-1, -1) for the centre of an octahedron.
  SimplexMatrix vertex_parents;
  // #S': the input simplex each output simplex descends from.
  IndexVector simplex_parent;
  // The keyframe times used (given or inferred), sorted.
  Eigen::VectorXd keyframe_times;
};

// Inputs:
//   manifold  #V by D points, #S by 4 tets (or by 3 triangles)
//   options      levels, scheme, keyframe times to keep
//   interrupter  told of the steps "checks", "refining" and "averaging" (once
//                per level) and "octahedra"
// Outputs:
//   ManifoldSubdivision: the refined manifold, each vertex's parents, each
//   simplex's input simplex, the keyframe times used
// Throws: InputError (see below); Cancelled when the interrupter says so;
//   MemoryLimitError when its estimate (memory_estimates.hpp) exceeds memory_limit()
//
// Subdivides a manifold of tetrahedra (4 columns) or triangles (3 columns)
// embedded in R^D (D >= columns - 1; the last coordinate is time).
// Throws InputError when the complex is invalid (see Complex::validate), when
// a simplex repeats a vertex, when a facet is shared by more than two
// simplices, when levels < 0, or when the result would not fit 32-bit indices.
ManifoldSubdivision subdivide_manifold(const Complex& manifold, const ManifoldSubdivisionOptions& options = {},
                                       const Interrupter& interrupter = {});

// --- Frames: OpenSubdiv ----------------------------------------------------

// Loop (triangles) and Catmull-Clark (triangles or quads) refine surfaces
// (subdivide_frame); B-splines refine the polylines of 2D animations
// (subdivide_polyline), which take no other scheme.
enum class FrameScheme { Loop, CatmullClark, BSpline };

// The names users choose from, the default for triangles first (enum_names.hpp).
inline constexpr NameTable<FrameScheme, 3> kFrameSchemeNames{
    {{FrameScheme::Loop, "loop"}, {FrameScheme::CatmullClark, "catmull_clark"}, {FrameScheme::BSpline, "bspline"}}};

struct FrameSubdivisionOptions {
  int levels = 1;
  FrameScheme scheme = FrameScheme::Loop;
  // Edges whose dihedral angle (between the normals of their two faces)
  // exceeds this many degrees become infinitely sharp creases. A value <= 0
  // or >= 180 disables the test.
  double crease_angle_degrees = 30.0;
  // Extra crease edges (#C by 2 vertex pairs of the input), infinitely sharp.
  SimplexMatrix crease_edges;
  // Project the refined points (and attributes) onto the limit surface.
  bool limit = true;
};

struct FrameSubdivision {
  PointMatrix vertices;  // #V' by 3
  SimplexMatrix faces;   // #F' by 3 (Loop) or 4 (Catmull-Clark), oriented like the input
  PointMatrix normals;   // #V' by 3 unit area-weighted normals of the refined mesh
  VertexAttributes vertex_attributes;  // refined with the same stencils as the points
  SimplexAttributes face_attributes;   // inherited from the input face
  IndexVector face_parent;             // #F': the input face each face descends from
  Index crease_count = 0;              // number of input edges made sharp
};

// Inputs:
//   vertices, faces    #V by 3 points, #F by 3 triangles or #F by 4 quads
//   options            levels, scheme, creases, limit projection
//   vertex_attributes  refined with the points; face_attributes inherited
//   interrupter        told each step (creases, topology, points, attributes,
//                      faces, normals) as it starts
// Outputs:
//   FrameSubdivision: refined vertices, faces, normals, attributes, face parents
// Throws: InputError (see below); Cancelled when the interrupter says so;
//   MemoryLimitError when its estimate (memory_estimates.hpp) exceeds memory_limit()
//
// Refines a polygon mesh (#V by 3 points; #F by 3 triangles or #F by 4 quads)
// with OpenSubdiv (Far::TopologyRefiner + PrimvarRefiner): Loop needs
// triangles, Catmull-Clark takes either. Throws InputError naming the
// offending face or edge (index out of range, repeated vertex, Loop on
// quads, the B-spline scheme, an edge shared by faces that OpenSubdiv rejects).
FrameSubdivision subdivide_frame(const PointMatrix& vertices, const SimplexMatrix& faces,
                                 const FrameSubdivisionOptions& options = {},
                                 const VertexAttributes& vertex_attributes = {},
                                 const SimplexAttributes& face_attributes = {},
                                 const Interrupter& interrupter = {});

// Inputs:
//   vertices, segments  #V by d points, #E by 2 directed segments
//   options             levels, crease angle
//   attributes          refined (vertex) or inherited (segment)
//   interrupter         told each level (and the limit step) as it starts
// Outputs:
//   FrameSubdivision with segments as faces
// Throws: InputError for segments out of range; Cancelled when the interrupter says so;
//   MemoryLimitError when its estimate (memory_estimates.hpp) exceeds memory_limit()
//
// Frames of 2D animations are polylines, which OpenSubdiv does not refine:
// cubic B-spline subdivision (midpoints, then 1/8, 3/4, 1/8 at old points;
// limit 1/6, 2/3, 1/6) with corners kept where the curve turns by more than
// the crease angle, ends or branches. `vertices` is #V by d (any d >= 2),
// `segments` #E by 2 directed a -> b. `faces` of the result are segments;
// normals (d == 2 only, else zero) are (dy, -dx), outward for
// counter-clockwise loops; `crease_count` is the number of corners.
FrameSubdivision subdivide_polyline(const PointMatrix& vertices, const SimplexMatrix& segments,
                                    const FrameSubdivisionOptions& options = {},
                                    const VertexAttributes& vertex_attributes = {},
                                    const SimplexAttributes& segment_attributes = {},
                                    const Interrupter& interrupter = {});

// Inputs:
//   frame    a Slice
//   options  as subdivide_frame
// Outputs:
//   the refined Slice (no vertex_edges: refined points are on no manifold edge)
// Throws: InputError and MemoryLimitError as subdivide_frame / subdivide_polyline
//
// A sliced frame refined by subdivide_frame (Loop on the triangles of a 3D
// frame) or subdivide_polyline (the segments of a 2D animation's frame): the
// vertices, faces, normals and vertex attributes are those of the refined
// frame, face attributes and face_simplex are inherited from the parent face,
// and vertex_edges / edge_parameter are empty (refined points do not lie on
// manifold edges).
Slice smooth_slice(const Slice& frame, const FrameSubdivisionOptions& options);

// Inputs:
//   name  a name of kManifoldSchemeNames
// Outputs: the scheme it names
// Throws: InputError naming `name` and the choices when the table has no such name
ManifoldScheme parse_manifold_scheme(const std::string& name);

// Inputs:
//   name  a name of kFrameSchemeNames
// Outputs: the scheme it names
// Throws: InputError naming `name` and the choices when the table has no such name
FrameScheme parse_frame_scheme(const std::string& name);

}  // namespace animanifold
