// Laplacian deformation of animation manifolds and meshes (chapter 4).
//
// Inputs are n-manifolds of n-simplices in R^(n+1), n = 2 (triangles in R^3:
// surfaces, or animated contours) or n = 3 (tets in R^4: animated surfaces),
// with or without boundary: `V` is #V by D (D = n+1), `S` is #S by D.
//
// A Laplacian system L V = Δ encodes each vertex (primal) or each simplex
// centroid (dual) relative to its neighbours; constraining anchor and handle
// vertices and solving LᵀL V = LᵀΔ in the least-squares sense deforms the
// rest (§4.2). Four schemes:
//   uniform    w_ij = 1/|N_i| (Taubin 1995)
//   cotangent  w_ij ∝ cot α + cot β, normalised (2-manifolds in R^3 only)
//   graph      w_i from the per-vertex QP of eq. 4.2 (Zhou et al. 2005)
//   dual       Au et al. 2006, generalised: L = L'·D over simplex centroids
// Primal boundary vertices always use the eq. 4.3 weights (§4.4.1); the dual
// scheme completes boundary simplices with ghost dual vertices (§4.4.2).
//
// Use `laplacian_deform` for a one-off deformation, or a `Deformer`, which
// factors the normal matrix once with CHOLMOD (supernodal), answers every
// handle move (a dense combination of response columns for a move by a
// transform, a solve for explicit positions), then optionally restores
// features (dual scheme).
#pragma once

#include "animanifold/affine_maps.hpp"
#include "animanifold/enum_names.hpp"
#include "animanifold/progress.hpp"
#include "animanifold/types.hpp"

#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

namespace animanifold {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

enum class LaplacianMethod { Uniform, Cotangent, Graph, Dual };

// What to do when the dual Laplacian's ghost vertices (or anything else, such
// as a component without constraints) leave the constrained system
// rank-deficient (§4.4.2). The system is never solved while rank-deficient.
enum class BoundaryRule {
  GhostAnchors,  // every ghost dual vertex is kept at its input position (extra rows)
  Grow,          // grow anchors/handles to neighbouring vertices until full rank
  Error,         // refuse, saying how many more constraints are needed
};

// The names users choose from, the default first (enum_names.hpp).
inline constexpr NameTable<LaplacianMethod, 4> kLaplacianMethodNames{{{LaplacianMethod::Dual, "dual"},
                                                                      {LaplacianMethod::Graph, "graph"},
                                                                      {LaplacianMethod::Uniform, "uniform"},
                                                                      {LaplacianMethod::Cotangent, "cotangent"}}};
inline constexpr NameTable<BoundaryRule, 3> kBoundaryRuleNames{
    {{BoundaryRule::Grow, "grow"}, {BoundaryRule::GhostAnchors, "ghost_anchors"}, {BoundaryRule::Error, "error"}}};

// Inputs:
//   name  a name of kLaplacianMethodNames
// Outputs: the method it names
// Throws: InputError naming `name` and the choices when the table has no such name
LaplacianMethod parse_laplacian_method(const std::string& name);

// Inputs:
//   name  a name of kBoundaryRuleNames
// Outputs: the rule it names
// Throws: InputError naming `name` and the choices when the table has no such name
BoundaryRule parse_boundary_rule(const std::string& name);

// Inputs:
//   method  a Laplacian method
// Outputs: its name in kLaplacianMethodNames (what parse_laplacian_method reads back)
// Throws: nothing
std::string to_string(LaplacianMethod method);

// Inputs:
//   rule  a boundary rule
// Outputs: its name in kBoundaryRuleNames (what parse_boundary_rule reads back)
// Throws: nothing
std::string to_string(BoundaryRule rule);

// Parameters of the graph-Laplacian QP, eq. 4.2:
//   min_w ‖Σ_j w_j (v_j − v_i)‖² + λ Σ_j w_j ‖v_j − v_i‖² + ρ·h̄²‖w‖²
//   such that Σ_j w_j = 1 and w_j ≥ ξ,
// where h̄² is the mean squared one-ring edge length. Both data terms scale
// like h̄², so λ is dimensionless. ‖v_i − Σ w_j v_j‖ equals the first term
// because the weights sum to one. The ridge ρ (tiny) makes each QP strictly
// convex, so the weights are unique where the first term alone has a whole
// face of minimisers (flat regions); it moves the objective by at most ρ·h̄².
struct GraphWeightOptions {
  double lambda = 0.1;
  double xi = 1e-3;      // clamped to 0.5/valence for vertices of very high valence
  double ridge = 1e-8;
};

struct LaplacianOptions {
  LaplacianMethod method = LaplacianMethod::Dual;
  GraphWeightOptions graph;
  // Vertices whose detail is discarded, for the offline regularisation of
  // §4.5.1 (new vertices of a refined complex): primal schemes give them
  // uniform weights and δ = 0; the dual scheme sets δ' = 0 on every simplex
  // incident to one of them. Empty by default.
  std::vector<Index> zero_detail_vertices;
};

// vertex_adjacency:
// Inputs:
//   S             #S by k simplices
//   vertex_count  #V
// Outputs:
//   VertexAdjacency: offsets (#V+1) and each vertex's sorted neighbours
// Throws: InputError when an index is outside 0..vertex_count-1 (check_indices)
//
// Vertex adjacency (the 1-ring) in compressed form: neighbours of v are
// `neighbours[offsets[v] .. offsets[v+1])`, sorted.
struct VertexAdjacency {
  std::vector<Index> offsets;
  std::vector<Index> neighbours;
};
VertexAdjacency vertex_adjacency(const SimplexMatrix& S, Index vertex_count);

// Inputs:
//   S             #S by k simplices
//   vertex_count  #V
// Outputs:
//   #V flags: 1 for a vertex on a boundary facet (a facet in exactly one simplex)
// Throws: InputError when an index is outside 0..vertex_count-1 (check_indices)
std::vector<char> boundary_vertices(const SimplexMatrix& S, Index vertex_count);

// Inputs:
//   edges    k by D one-ring edge vectors e_j = v_j − v_i of one vertex
//   options  λ, ξ and the ridge of eq. 4.2
// Outputs:
//   k weights summing to 1 (uniform when every edge has zero length; empty for k = 0)
// Throws: InputError when λ < 0, ξ < 0 or the ridge is not positive, and from
//   solve_simplex_qp when an edge is infinite (a NaN is not caught here:
//   laplacian_system checks the points first)
//
// The eq. 4.2 weights of one vertex; λ = 0 gives eq. 4.3.
Eigen::VectorXd graph_laplacian_weights(const PointMatrix& edges, const GraphWeightOptions& options);

// Inputs:
//   V       #V by D points
//   S       #S by D simplices
//   method  Uniform, Cotangent or Graph
//   graph   the graph Laplacian's QP parameters
// Outputs:
//   #V by #V sparse W, rows summing to one
// Throws: InputError (see below, and for a mesh with indices out of range)
//
// Primal weight matrix W (#V by #V, row i holds w_ij, rows sum to one); the
// Laplacian is I − W. `method` is Uniform, Cotangent or Graph; boundary
// vertices use eq. 4.3 whatever the method (§4.4.1). An isolated vertex has an
// empty row. Cotangent throws InputError unless S is triangles in R^3, or when
// a vertex's cotangent weights sum to ≤ 0 (naming it).
SparseRowMatrix primal_weights(const PointMatrix& V, const SimplexMatrix& S, LaplacianMethod method,
                               const GraphWeightOptions& graph = {});

// Inputs:
//   S             #S by n+1 simplices
//   vertex_count  #V
// Outputs:
//   DualOperator: D (centroids and ghosts by #V), neighbours, ghost facets
// Throws: InputError when a facet is shared by more than two simplices
//
// The dual operator of §4.2.1 with the ghost vertices of §4.4.2.
// Dual vertex s < #S is the centroid of simplex s; dual vertex #S + g is the
// ghost across boundary facet g: the centroid of the simplex obtained by
// reflecting the facet's opposite vertex v_l through the facet centroid
// (v_l' = (2/n)Σ_F v_k − v_l), i.e. ((n+2)/(n(n+1)))·Σ_F v_k − (1/(n+1))·v_l.
// For triangles this is ⅔(B+C) − ⅓A (Figure 4.8, footnote 1); it keeps the
// boundary facet and, being an affine combination, commutes with any motion.
struct DualOperator {
  SparseRowMatrix D;             // (#S + #G) by #V
  SimplexMatrix neighbours;      // #S by (n+1): the dual vertex across facet i of simplex s
  SimplexMatrix ghost_facets;    // #G by 2: (simplex, facet index) of each ghost
  // Outputs: #S and #G. Throws: nothing
  Index simplex_count() const { return static_cast<Index>(neighbours.rows()); }
  Index ghost_count() const { return static_cast<Index>(ghost_facets.rows()); }
};
DualOperator dual_operator(const SimplexMatrix& S, Index vertex_count);

// laplacian_system:
// Inputs:
//   V        #V by D points
//   S        #S by D simplices
//   options  method, graph weights, zero-detail vertices
// Outputs:
//   DifferentialSystem: L, Δ and, for the dual scheme, its operator and heights
// Throws: InputError for an invalid mesh or a method its simplices do not allow
//
// L V = Δ for the input points: L is rows by #V (#V rows for primal schemes,
// #S rows for the dual one), Δ = L·V exactly (so the input is reproduced
// when nothing moves), except for rows zeroed by `zero_detail_vertices`.
struct DifferentialSystem {
  LaplacianMethod method = LaplacianMethod::Dual;
  SparseRowMatrix L;
  PointMatrix delta;
  // Dual scheme only:
  DualOperator dual;
  SparseRowMatrix dual_weights;  // L' (#S by #S+#G): e_s − Σ β_sj e_j
  Eigen::VectorXd heights;       // δ'_s · n_s: signed distance from the neighbours' hyperplane
  std::vector<char> degenerate;  // neighbours affinely dependent: δ' is kept as is by restore
};
DifferentialSystem laplacian_system(const PointMatrix& V, const SimplexMatrix& S,
                                    const LaplacianOptions& options = {});

// Inputs:
//   C           (#S+#G) by D dual points (e.g. D·V)
//   neighbours  #S by D: DualOperator::neighbours, rows of C
// Outputs:
//   #S by D unit normals; zero rows where the neighbours are affinely dependent
// Throws: InputError when neighbours do not have D columns or an index is
//   outside C (simplex_normals)
//
// The normals of the hyperplanes through each dual vertex's neighbours,
// oriented by the facet order.
PointMatrix dual_hyperplane_normals(const PointMatrix& C, const SimplexMatrix& neighbours);

struct DeformerOptions {
  LaplacianOptions laplacian;
  BoundaryRule boundary = BoundaryRule::Grow;
  // Restore after each intermediate increment of deform(…, steps > 1).
  int step_restore_iterations = 50;
  double step_restore_tolerance = 1e-4;
  // 0: anchors and handles are hard constraints (eliminated from the
  // unknowns: anchors stay exactly, handles land exactly). > 0: soft rows
  // e_iᵀ·weight appended to L, as in the dissertation's L = [L̄; e_iᵀ].
  double constraint_weight = 0;
};

struct RestoreStatus {
  int iterations = 0;
  double motion = 0;       // last max vertex displacement / input bounding-box diagonal
  bool converged = false;  // motion < tolerance within the iteration cap
};

// What a Deformer built, for reports and tests.
struct DeformerInfo {
  Index rows = 0;              // rows of the least-squares system
  Index unknowns = 0;          // free vertices (hard) or all vertices (soft)
  Index ghosts = 0;            // ghost dual vertices (dual scheme)
  Index ghost_anchor_rows = 0; // rows added by BoundaryRule::GhostAnchors
  Index grown = 0;             // constraints added by BoundaryRule::Grow
  double rcond = 0;            // CHOLMOD's reciprocal condition estimate of the factor
  std::int64_t factor_nonzeros = 0;
  double factor_flops = 0;     // floating-point operations of the factorisation
  // BLAS calls of the factorisation that ran by tiles on thread_count()
  // threads: 0 when every supernode is small, or where CHOLMOD binds to
  // another BLAS than the core's tiled layer (Debian's blender 3.4 binary)
  std::int64_t factor_tiled_blas_calls = 0;
  // OpenMP teams of the factorisation (CHOLMOD's own loops ask for 4 threads)
  // held to thread_count(): 0 where CHOLMOD binds to the process's libgomp
  // directly (Debian's blender 3.4 binary) or when thread_count() >= 4
  std::int64_t factor_openmp_teams_capped = 0;
  // Seconds of the constructor's phases (summed over the boundary rule's
  // attempts), for reports and benchmarks only:
  double laplacian_seconds = 0;  // weights and L (laplacian_system)
  double normal_seconds = 0;     // the constrained rows and the normal matrix AᵀA
  double analyse_seconds = 0;    // CHOLMOD's fill-reducing ordering and symbolic analysis
  double factorise_seconds = 0;  // CHOLMOD's numerical factorisation
};

// affine_power (affine_maps.hpp): the increments of Deformer::deform's steps.

// Inputs (constructor):
//   V, S     #V by D points, #S by D simplices
//   anchors  vertices that stay
//   handles  vertices that follow deform()/deform_to()
//   options      Laplacian, boundary rule, constraint weight, restore settings
//   interrupter  told of the constructor's steps "checks", "laplacian" and
//                "factorising" (once per attempt at a full-rank system)
//   deform(), deform_to() and restore() take an interrupter too: told of
//   "deforming" before each increment and "restoring" before each round
//   (the intermediate restores of steps > 1 poll it only)
// Outputs: deform(), deform_to() and restore() give #V by D points
// Throws: InputError (see below and on each method); Cancelled when the
//   interrupter says so (points() is then the last finished increment or round)
//
// Laplacian editing with a kept factorisation.
//
//   Deformer d(V, S, anchors, handles, options);   // build L, factor once
//   PointMatrix W = d.deform(T);                   // (D+1) by (D+1) affine T
//   PointMatrix W2 = d.deform_to(P);               // or handle positions, H by D
//   RestoreStatus s = d.restore(50, 1e-6);          // dual: rotate δ' to new normals
//
// anchors and handles are vertex indices: disjoint, in range, without
// repeats, not both empty (InputError naming the culprit otherwise). The
// normal matrix AᵀA is factored once with CHOLMOD's supernodal Cholesky; a
// rank-deficient system (detected from the factorisation and confirmed by
// the inertia of AᵀA − τI) is treated by the boundary rule or refused with
// an InputError saying how many more constraints are needed.
//
// Threads: one Deformer may be shared. deform, deform_to, restore and
// points() take an internal mutex, so concurrent calls run one after the
// other (each as if alone: deform and deform_to start from the rest shape).
// The other accessors return what the constructor built and never changes.
class Deformer {
 public:
  Deformer(const PointMatrix& V, const SimplexMatrix& S, const IndexVector& anchors, const IndexVector& handles,
           const DeformerOptions& options = {}, const Interrupter& interrupter = {});
  ~Deformer();
  Deformer(Deformer&&) noexcept;
  Deformer& operator=(Deformer&&) noexcept;

  // Inputs:
  //   transform    (D+1) by (D+1) affine map T, last row [0 … 0 1]
  //   steps        >= 1: increments (dual scheme; primal schemes take 1)
  //   interrupter  told of "deforming" before each increment
  // Outputs:
  //   the new #V by D points (also points())
  // Throws: InputError for a transform of the wrong size, with non-finite entries
  //   or another last row, for steps < 1, and (steps > 1) for a transform
  //   affine_power refuses; MeshingError when CHOLMOD's solve fails; Cancelled
  //   when the interrupter says so
  //
  // Moves the handles by the affine map x ↦ T·[x; 1] and solves.
  //
  // The solution is affine in T, so the first deform by a transform solves
  // once for the rest shape with the handles at the origin and once for each
  // homogeneous coordinate of the handles (2D+1 right-hand sides, one
  // cholmod_solve), and every one-step deform is then that base plus a
  // dense (D+1)-term combination (deformer_response.hpp): equal to a fresh
  // solve up to rounding. deform_to, steps > 1 and restore solve afresh.
  //
  // steps > 1 (dual scheme) drags the handles there in `steps` equal
  // increments, restoring features after each but the last (a large rotation
  // applied at once can restore into a folded local minimum; Figure 4.11).
  // Increments are fractional powers of T: its polar factors R^s S^s about
  // T's fixed point (least-squares), plus s times the remaining translation;
  // a rotation by exactly π has no unique real power and is refused.
  // Primal schemes are linear, so they ignore `steps`.
  PointMatrix deform(const Eigen::MatrixXd& transform, int steps = 1, const Interrupter& interrupter = {});

  // Inputs:
  //   positions    H by D: where each handle given to the constructor goes, in that order
  //   steps        >= 1: increments (dual scheme; primal schemes take 1)
  //   interrupter  told of "deforming" before each increment
  // Outputs:
  //   the new #V by D points (also points())
  // Throws: InputError when positions are not H by D or not finite, or for
  //   steps < 1; MeshingError when CHOLMOD's solve fails; Cancelled when the
  //   interrupter says so
  //
  // Moves handle i to row i of `positions` and solves. Grown handles follow the displacement of
  // the handle they grew from. steps > 1 as above: increments follow
  // fractions of the handles' best-fit rigid motion (Kabsch) plus the same
  // fraction of what it leaves, so a rotated cap is not shrunk on the way.
  PointMatrix deform_to(const PointMatrix& positions, int steps = 1, const Interrupter& interrupter = {});

  // Inputs:
  //   max_iterations  >= 1: restore rounds at most
  //   tolerance       > 0: the largest vertex motion of a round that counts as
  //                   converged, in input bounding-box diagonals
  //   interrupter     told of "restoring" before each round
  // Outputs:
  //   RestoreStatus: rounds, last motion, converged; the points are points()
  // Throws: InputError for a primal scheme, before any deform, for
  //   max_iterations < 1 or tolerance <= 0; MeshingError when CHOLMOD's solve
  //   fails; Cancelled when the interrupter says so (points() is then the last
  //   finished round)
  //
  // Dual scheme: repeatedly rotates each δ'_s onto the normal of its
  // neighbours' deformed hyperplane (keeping its signed height) and re-solves
  // (Au et al.'s iteration), until the largest vertex motion of one such step
  // falls below `tolerance` times the input's bounding-box diagonal, or
  // `max_iterations`. The fixed-point iteration is Anderson-accelerated
  // (depth 5): plain, it oscillates with period two on large rotations.
  // Starts from the last deform.
  RestoreStatus restore(int max_iterations = 50, double tolerance = 1e-6, const Interrupter& interrupter = {});

  // Outputs: what the comment beside each says; points() takes the mutex, the others
  //   return what the constructor built
  // Throws: nothing
  PointMatrix points() const;               // a copy of the latest result (the input before any deform)
  const PointMatrix& rest_points() const;   // the input
  const IndexVector& anchors() const;       // after growth
  const IndexVector& handles() const;       // after growth (given handles first)
  const DifferentialSystem& system() const;
  const DeformerInfo& info() const;
  int dimension() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Inputs: as Deformer, plus transform ((D+1) by (D+1)), restore settings and steps
// Outputs:
//   #V by D deformed points
// Throws: InputError as Deformer, Deformer::deform and Deformer::restore (restore
//   runs only when restore_iterations > 0 and the scheme is dual); MeshingError
//   when CHOLMOD fails
//
// One-off: builds a Deformer, moves the handles by `transform` (in `steps`
// increments) and returns the points, restored (dual scheme) when
// `restore_iterations` > 0.
PointMatrix laplacian_deform(const PointMatrix& V, const SimplexMatrix& S, const IndexVector& anchors,
                             const IndexVector& handles, const Eigen::MatrixXd& transform,
                             const DeformerOptions& options = {}, int restore_iterations = 0,
                             double restore_tolerance = 1e-6, int steps = 1);

}  // namespace animanifold
