// The Voronoi skeleton (chapter 7): Voronoi separability of closed oriented
// polygons in R^2 and closed oriented triangle meshes in R^3, and the
// internal/external skeletons extracted from the Voronoi diagram of their
// vertices.
//
// Inputs are `V` (#V by D, D = 2 or 3) and `F` (#F by D: segments in R^2,
// triangles in R^3), closed, manifold and oriented outward (counter-clockwise
// polygons; right-handed triangles whose normals point out of the solid).
// Anything else is refused with an InputError naming the culprit.
//
// Pipeline (§7.6.6): dihedral_test -> make_voronoi_separable (Qhull Voronoi
// diagram, edge/face encroachment, closest-point splits, iteration cap) ->
// wrap (extra Voronoi sites so every mesh vertex has a bounded cell) ->
// extraction of the bisectors b_ij that do not intersect the mesh (CGAL exact
// predicates), classified internal/external and clipped to the convex hull.
#pragma once

#include "animanifold/enum_names.hpp"
#include "animanifold/progress.hpp"
#include "animanifold/types.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace animanifold {

// ---------------------------------------------------------------- wrap (§7.6.4)

enum class WrapShape { None, Box, Sphere };

// The names users choose from, the default first (enum_names.hpp).
inline constexpr NameTable<WrapShape, 3> kWrapShapeNames{
    {{WrapShape::Box, "box"}, {WrapShape::Sphere, "sphere"}, {WrapShape::None, "none"}}};

// Inputs:
//   name  a name of kWrapShapeNames, or "" for None
// Outputs: the shape it names
// Throws: InputError naming `name` and the choices when the table has no such name
WrapShape parse_wrap_shape(const std::string& name);

struct WrapResult {
  PointMatrix vertices;   // the input vertices followed by the wrap's
  SimplexMatrix faces;    // the input faces followed by the wrap's (oriented inward)
  Index input_vertices = 0;
  Index input_faces = 0;
};

// Inputs:
//   V, F     the shape: #V by D points, #F by D faces
//   shape    Box, Sphere or None
//   density  subdivisions of each box edge
//   margin   distance from the bounding box, in bounding-box diagonals
// Outputs:
//   WrapResult: the input followed by the wrap (oriented inward)
// Throws: InputError for density < 1, margin <= 0, or a shape that is not closed and outward
//
// Encloses the input in an axis-aligned box or a sphere (circle/rectangle in
// R^2) placed `margin` bounding-box diagonals away from the input's bounding
// box. `density` is the number of subdivisions of each box edge (sphere: about
// as many points as the box, 6·density²+2; circle: 4·density points). With
// margin >= 1 no wrap site is closer to a point of the input's convex hull
// than the nearest input vertex, so the wrap bounds every input cell without
// taking any part of the hull. The wrap is a second component, oriented
// inward (the region between wrap and input is its inside).
WrapResult wrap(const PointMatrix& V, const SimplexMatrix& F, WrapShape shape, int density = 4,
                double margin = 1.0);

// ------------------------------------------------------ dihedral test (§7.6.6)

struct DihedralReport {
  double limit = 0;          // radians
  double sharpest = M_PI;    // smallest surface angle found (radians)
  bool passes = true;        // no surface angle sharper than the limit
  // Where: 3D the shared edge (2 vertices), 2D the corner vertex (1 column).
  SimplexMatrix sharp;
  Eigen::VectorXd angles;    // the surface angle at each row of `sharp`
};

// Inputs:
//   V, F   the shape: #V by D points, #F by D faces
//   limit  radians
// Outputs:
//   DihedralReport: the sharpest angle and every angle sharper than limit
// Throws: nothing
//
// The surface angle across an edge is pi minus the angle between the two
// face normals (the smaller of the two dihedral angles, so a sharp convex
// ridge and a sharp concave crease both count); at a polygon corner it is the
// angle between the two segments.
DihedralReport dihedral_test(const PointMatrix& V, const SimplexMatrix& F, double limit = M_PI / 4);

// ---------------------------------------------- Voronoi separability (§7.5-7.6)

// One encroached simplex and its closest encroaching vertex. Types follow
// Figure 7.14: 2 = edge encroached (diametral sphere), 3 = face encroached
// (minimum equatorial sphere, vertex above or below the face) without edge
// encroachment of that face, 4 = both.
struct Encroachment {
  Index vertex;     // the encroaching vertex
  Index a, b, c;    // the encroached edge (c = -1) or face
  int type;
  double distance;  // from the vertex to the simplex's closest point
};

// Which edge encroachments count in R^3 (weak separability, §7.6.2). In R^2
// every segment is tested (strong separability, Lemma 7.5.1).
struct EncroachmentRule {
  // Edges skipped for a vertex p: 1 = edges of the triangles of p's one-ring
  // (the dissertation's rule); 2 = also every edge touching a one-ring vertex
  // (the "edges intersected by the contour of C_i" of Figure 7.15).
  int neighbourhood = 2;
  // Edge encroachments by a vertex lying within this angle (radians) of the
  // plane of one of the edge's faces are in-plane: the "within a local
  // sub-surface" degree of freedom that §7.6 decouples from the "between
  // sub-surfaces" one; they are ignored. 0 tests them all. Face encroachment
  // (above or below the face) is always tested.
  //
  // {1, 0} is the dissertation's literal rule; on obtuse meshes it runs into
  // the endless in-plane cascade of Figure 7.11 (the bunny: 30k splits in 8
  // rounds), while the default converges (the bunny: 3 rounds).
  double in_plane_angle = 0.3;
};

// Inputs:
//   V, F  the shape: #V by D points, #F by D faces
//   rule  which edge encroachments count
// Outputs:
//   one Encroachment per encroached simplex
// Throws: nothing
//
// Every encroached simplex with its closest encroacher.
std::vector<Encroachment> encroachments(const PointMatrix& V, const SimplexMatrix& F,
                                        const EncroachmentRule& rule = {});

struct SeparabilityResult {
  PointMatrix vertices;   // the refined mesh: input vertices first, then split points
  SimplexMatrix faces;    // conforming and oriented like the input
  bool separable = false; // no encroachment is left
  int iterations = 0;     // splitting rounds applied (0: the input was separable)
  Index splits = 0;       // vertices inserted
  Index remaining = 0;    // encroached simplices left when the cap was hit
};

// Inputs:
//   V, F            the closed, outward shape
//   max_iterations  splitting rounds at most
//   rule            which edge encroachments count
// Outputs:
//   SeparabilityResult: the refined mesh, whether it is separable, rounds and splits
// Throws: InputError unless (V, F) is closed, manifold and oriented outward
//
// The iterative algorithm of Figure 7.9 / §7.6.6: each encroached simplex is
// split at the closest point to its closest encroacher (§7.6.3); edges first,
// faces whose edges are untouched in the same round. Stops when separable or
// after `max_iterations` rounds, and says which.
SeparabilityResult make_voronoi_separable(const PointMatrix& V, const SimplexMatrix& F, int max_iterations = 4,
                                          const EncroachmentRule& rule = {});

// ------------------------------------------------- skeleton (§7.3, §7.4, §8.6.2)

// Which skeletons users ask for: the medial one inside the shape, the one of
// its concavities and holes (inside the convex hull), or both.
enum class SkeletonSide { Internal, External, Both };

inline constexpr NameTable<SkeletonSide, 3> kSkeletonSideNames{
    {{SkeletonSide::Internal, "internal"}, {SkeletonSide::External, "external"}, {SkeletonSide::Both, "both"}}};

struct SkeletonOptions {
  bool internal = true;
  bool external = true;
  int max_iterations = 4;
  EncroachmentRule rule;
  WrapShape wrap = WrapShape::Box;
  int wrap_density = 4;
  double wrap_margin = 1.0;
  double dihedral_limit = M_PI / 4;
  bool attach = false;  // §8.6.2: connect mesh vertices to the skeleton
};

struct VoronoiSkeleton {
  PointMatrix vertices;      // #S by D (Voronoi vertices, and hull cuts for the external side)
  SimplexMatrix faces;       // #T by D: segments (2D) or triangles of the convex bisector polygons (3D)
  IndexVector side;          // per face: 0 internal, 1 external
  SimplexMatrix sites;       // #T by 2: the refined-mesh vertices (i < j) whose bisector b_ij holds the face;
                             // triangles are oriented with their normal from site i towards site j
  IndexVector polygon;       // per face: which bisector polygon it triangulates
  IndexVector on_mesh;       // per skeleton vertex: 1 when it lies on the mesh (Figure 7.10)
  PointMatrix refined_vertices;  // the Voronoi-separable mesh the skeleton belongs to
  SimplexMatrix refined_faces;
  bool separable = false;
  int iterations = 0;
  Index splits = 0;
  DihedralReport dihedral;
  // §8.6.2: simplices (2D segments, 3D triangles) over the concatenation
  // [refined_vertices; vertices]: index < #refined_vertices is a mesh vertex,
  // index - #refined_vertices a skeleton vertex. Empty unless options.attach.
  SimplexMatrix attachment;
  // Diagnostics.
  Index bisectors = 0;           // bounded bisector polygons between mesh vertices
  Index discarded = 0;           // of which intersect the mesh
  Index discarded_nonlocal = 0;  // of which are not between mesh neighbours
  Index discarded_far = 0;       // of which are not even two edges apart: where holes can be
  double seconds_separability = 0;
  double seconds_extraction = 0;
};

// Inputs:
//   V, F     the closed, outward shape: #V by D points, #F by D faces (D = 2 or 3)
//   options      sides, separability rounds and rule, wrap, attachment
//   interrupter  told of the steps "checks", "separability", "voronoi",
//                "sides", "bisectors" (every 1024 bisector polygons) and "assembly"
// Outputs:
//   VoronoiSkeleton: skeleton vertices and faces with their side and sites, the
//   separable mesh they belong to, the attachment, diagnostics
// Throws: InputError naming the culprit when the shape is not closed, manifold
//   and outward; MeshingError when Qhull or CGAL fails; Cancelled when the
//   interrupter says so
VoronoiSkeleton voronoi_skeleton(const PointMatrix& V, const SimplexMatrix& F, const SkeletonOptions& options = {},
                                 const Interrupter& interrupter = {});

// Inputs:
//   faces_V, faces  the faces to test: points and #T by D faces
//   V, F            the mesh
// Outputs:
//   per face, whether it touches or crosses the mesh
// Throws: InputError for indices out of range or faces that are not segments in R^2 or triangles in R^3
//
// Which of `faces` (triangles in R^3, segments in R^2) intersect the mesh
// (V, F), decided with CGAL's exact predicates. Touching counts.
std::vector<bool> faces_intersecting_mesh(const PointMatrix& faces_V, const SimplexMatrix& faces,
                                          const PointMatrix& V, const SimplexMatrix& F);

// Inputs:
//   V, F  the shape: #V by D points, #F by D faces (D = 2 or 3)
// Outputs: nothing: returns when the shape is one voronoi_skeleton takes
// Throws: InputError naming the culprit unless (V, F) is a closed, manifold,
//   outward-oriented polygon (R^2) or triangle mesh (R^3) without unused or
//   coincident vertices
void check_closed_oriented(const PointMatrix& V, const SimplexMatrix& F);

}  // namespace animanifold
