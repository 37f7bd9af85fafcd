// Laplacian editing with a kept factorisation (laplacian.hpp's Deformer):
// the constrained least-squares system, its factorisation under the boundary
// rule, deformation by transforms or positions in steps, and restoring.
#include "animanifold/laplacian.hpp"

#include "animanifold/affine_maps.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/simplex_qp.hpp"
#include "animanifold/threads.hpp"
#include "deformer_response.hpp"
#include "laplacian_input.hpp"
#include "least_squares.hpp"
#include "normal_equations.hpp"
#include "sparse_cholesky.hpp"
#include "sparse_rows.hpp"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>

namespace animanifold {

namespace {

using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Number of eigenvalues of the symmetric N (lower triangle given) below tau,
// from the inertia of the LDLᵀ factorisation of N − τI (Sylvester's law).
Index eigenvalues_below(const ColMatrix& N_lower, double tau) {
  Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower> ldlt;
  ldlt.setShift(-tau);
  ldlt.compute(N_lower);
  if (ldlt.info() != Eigen::Success) return 1;  // a zero pivot: at least one
  Index count = 0;
  const auto& d = ldlt.vectorD();
  for (Index i = 0; i < d.size(); ++i)
    if (!(d(i) > 0)) ++count;
  return count;
}

}  // namespace

struct Deformer::Impl {
  PointMatrix V0, V;
  SimplexMatrix S;
  DeformerOptions options;
  DifferentialSystem system;
  int dim = 0;
  double diagonal = 1;

  std::vector<Index> given_handles;
  IndexVector anchors, handles;
  std::vector<Index> handle_source;  // per entry of `handles`: position in given_handles

  // The least-squares system: rows = [L ; ghost-anchor rows] (+ soft constraint rows).
  Index laplacian_rows = 0;
  PointMatrix extra_rhs;         // ghost-anchor rows' right-hand side
  std::vector<Index> free_vertices;
  std::vector<Index> constrained;  // anchors then handles
  ColMatrix A_free_t;            // unknowns by rows (hard), or Aᵀ of all vertices (soft)
  SparseRowMatrix A_constrained;  // rows by constraints (hard only)
  SparseCholesky cholesky;
  PointMatrix delta;             // current differential coordinates (restore rotates them)
  PointMatrix constraint_positions;  // constraints by dim, in `constrained` order
  AffineResponse response;       // deform by a transform, once built (first such deform)
  bool deformed = false;
  DeformerInfo info;
  // deform, deform_to, restore and points() take it: they read and write V,
  // delta and the constraint positions, and the bindings call them with the
  // GIL released, so Python threads may share one Deformer.
  mutable std::mutex mutex;

  Index build_and_factor();
  void place_handles_by_transform(const Eigen::MatrixXd& transform);
  void place_handles_at(const PointMatrix& positions, double s, const Eigen::MatrixXd* fit);
  void grow_constraints(const VertexAdjacency& adjacency);
  void factor_under_boundary_rule(const Interrupter& interrupter);
  PointMatrix solve() const;
  PointMatrix solve_columns(const PointMatrix& delta_cols, const PointMatrix& extra_cols,
                            const PointMatrix& constraint_cols) const;
  void build_response();
  RestoreStatus restore(int max_iterations, double tolerance, const Interrupter& interrupter = {});
};

Index Deformer::Impl::build_and_factor() {
  const Index vertex_count = static_cast<Index>(V0.rows());
  const bool soft = options.constraint_weight > 0;
  const auto assembly_start = Clock::now();
  const bool ghost_rows = system.method == LaplacianMethod::Dual && options.boundary == BoundaryRule::GhostAnchors &&
                          system.dual.ghost_count() > 0;
  const Index ghost_count = ghost_rows ? system.dual.ghost_count() : 0;
  const Index simplex_count = system.dual.simplex_count();

  // All rows over all vertices, row-major.
  SparseRowMatrix A(laplacian_rows + ghost_count, vertex_count);
  if (ghost_rows) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(system.L.nonZeros() + system.dual.D.nonZeros());
    for (Index r = 0; r < laplacian_rows; ++r)
      for (SparseRowMatrix::InnerIterator it(system.L, r); it; ++it) triplets.emplace_back(r, it.col(), it.value());
    for (Index g = 0; g < ghost_count; ++g)
      for (SparseRowMatrix::InnerIterator it(system.dual.D, simplex_count + g); it; ++it)
        triplets.emplace_back(laplacian_rows + g, it.col(), it.value());
    A.setFromTriplets(triplets.begin(), triplets.end());
    extra_rhs = system.dual.D.bottomRows(ghost_count) * V0;
  } else {
    A = system.L;
    extra_rhs.resize(0, dim);
  }
  info.rows = static_cast<Index>(A.rows());
  info.ghosts = system.method == LaplacianMethod::Dual ? system.dual.ghost_count() : 0;
  info.ghost_anchor_rows = ghost_count;

  constrained.assign(anchors.data(), anchors.data() + anchors.size());
  constrained.insert(constrained.end(), handles.data(), handles.data() + handles.size());
  std::vector<Index> column(vertex_count, -1);  // free index, or -(constraint index) - 2
  for (size_t c = 0; c < constrained.size(); ++c) column[constrained[c]] = -static_cast<Index>(c) - 2;
  free_vertices.clear();
  for (Index v = 0; v < vertex_count; ++v)
    if (column[v] == -1) {
      column[v] = static_cast<Index>(free_vertices.size());
      free_vertices.push_back(v);
    }

  ColMatrix N_lower;
  if (soft) {
    A_free_t = A.transpose();
    N_lower = normal_matrix_lower(A_free_t);
    const double w2 = options.constraint_weight * options.constraint_weight;
    for (Index v : constrained) N_lower.coeffRef(v, v) += w2;
    N_lower.makeCompressed();
    info.unknowns = vertex_count;
    info.rows += static_cast<Index>(constrained.size());
  } else {
    split_columns(A, column, static_cast<Index>(free_vertices.size()), static_cast<Index>(constrained.size()),
                  A_free_t, A_constrained);
    info.unknowns = static_cast<Index>(free_vertices.size());
    if (free_vertices.empty()) {
      info.rcond = 1;
      info.factor_nonzeros = 0;
      info.normal_seconds += seconds_since(assembly_start);
      return 0;
    }
    N_lower = normal_matrix_lower(A_free_t);
  }
  info.normal_seconds += seconds_since(assembly_start);
  const bool positive = cholesky.factor(N_lower);
  info.analyse_seconds += cholesky.analyse_seconds();
  info.factorise_seconds += cholesky.factorise_seconds();
  info.rcond = positive ? cholesky.rcond() : 0;
  info.factor_nonzeros = cholesky.factor_nonzeros();
  info.factor_flops = cholesky.factor_flops();
  info.factor_tiled_blas_calls += cholesky.tiled_blas_calls();
  info.factor_openmp_teams_capped += cholesky.openmp_teams_capped();
  if (positive && info.rcond > 1e-12) return 0;
  // Possibly rank-deficient: count the (numerically) zero eigenvalues.
  const double tau = 1e-10 * N_lower.diagonal().cwiseAbs().maxCoeff();
  Index deficiency = eigenvalues_below(N_lower, tau);
  if (!positive) deficiency = std::max<Index>(deficiency, 1);
  return deficiency;
}

void Deformer::Impl::grow_constraints(const VertexAdjacency& adjacency) {
  const Index vertex_count = static_cast<Index>(V0.rows());
  std::vector<int> label(vertex_count, 0);  // 1 anchor, 2 handle
  std::vector<Index> source(vertex_count, -1);
  for (Index i = 0; i < anchors.size(); ++i) label[anchors(i)] = 1;
  for (Index i = 0; i < handles.size(); ++i) {
    label[handles(i)] = 2;
    source[handles(i)] = handle_source[i];
  }
  std::vector<Index> new_anchors, new_handles;
  std::vector<Index> new_sources;
  for (Index v = 0; v < vertex_count; ++v) {
    if (label[v] != 0) continue;
    int chosen = 0;
    Index from = -1;
    for (Index j = adjacency.offsets[v]; j < adjacency.offsets[v + 1]; ++j) {
      const Index u = adjacency.neighbours[j];
      if (label[u] == 1) { chosen = 1; break; }  // anchors win ties
      if (label[u] == 2 && chosen == 0) { chosen = 2; from = source[u]; }
    }
    if (chosen == 1) new_anchors.push_back(v);
    else if (chosen == 2) { new_handles.push_back(v); new_sources.push_back(from); }
  }
  const Index grown = static_cast<Index>(new_anchors.size() + new_handles.size());
  if (grown == 0) return;
  IndexVector a(anchors.size() + new_anchors.size());
  a << anchors, Eigen::Map<IndexVector>(new_anchors.data(), static_cast<Index>(new_anchors.size()));
  IndexVector h(handles.size() + new_handles.size());
  h << handles, Eigen::Map<IndexVector>(new_handles.data(), static_cast<Index>(new_handles.size()));
  anchors = a;
  handles = h;
  handle_source.insert(handle_source.end(), new_sources.begin(), new_sources.end());
  info.grown += grown;
}

PointMatrix Deformer::Impl::solve() const { return solve_columns(delta, extra_rhs, constraint_positions); }

// The least-squares solution for any number of right-hand-side columns: the
// Laplacian rows' targets (laplacian_rows by k), the ghost-anchor rows'
// (extra_rhs.rows() by k) and the constraints' positions (constraints by k).
// Returns #V by k, linear in the three.
PointMatrix Deformer::Impl::solve_columns(const PointMatrix& delta_cols, const PointMatrix& extra_cols,
                                          const PointMatrix& constraint_cols) const {
  const Index vertex_count = static_cast<Index>(V0.rows());
  const Index k = static_cast<Index>(delta_cols.cols());
  // Right-hand side of the full rows: [Δ ; ghost-anchor positions].
  PointMatrix rhs(laplacian_rows + extra_cols.rows(), k);
  rhs.topRows(laplacian_rows) = delta_cols;
  if (extra_cols.rows()) rhs.bottomRows(extra_cols.rows()) = extra_cols;
  PointMatrix out(vertex_count, k);
  if (options.constraint_weight > 0) {
    Eigen::MatrixXd b = A_free_t * rhs;
    const double w2 = options.constraint_weight * options.constraint_weight;
    for (size_t c = 0; c < constrained.size(); ++c) b.row(constrained[c]) += w2 * constraint_cols.row(c);
    out = cholesky.solve(b);
    return out;
  }
  for (size_t c = 0; c < constrained.size(); ++c) out.row(constrained[c]) = constraint_cols.row(c);
  if (free_vertices.empty()) return out;
  rhs -= A_constrained * constraint_cols;
  const Eigen::MatrixXd b = A_free_t * rhs;
  const Eigen::MatrixXd x = cholesky.solve(b);
  for (size_t f = 0; f < free_vertices.size(); ++f) out.row(free_vertices[f]) = x.row(f);
  return out;
}

// The base (handles at the origin) and the response to each homogeneous
// coordinate of the handles' rest positions, as one solve of 2D+1 columns.
void Deformer::Impl::build_response() {
  const Index anchor_count = static_cast<Index>(anchors.size());
  const Index constraint_count = static_cast<Index>(constrained.size());
  const int k = 2 * dim + 1;
  PointMatrix delta_cols = PointMatrix::Zero(laplacian_rows, k);
  delta_cols.leftCols(dim) = system.delta;
  PointMatrix extra_cols = PointMatrix::Zero(extra_rhs.rows(), k);
  extra_cols.leftCols(dim) = extra_rhs;
  PointMatrix constraint_cols = PointMatrix::Zero(constraint_count, k);
  for (Index c = 0; c < anchor_count; ++c) constraint_cols.row(c).head(dim) = V0.row(anchors(c));
  for (Index h = 0; h < handles.size(); ++h) {
    constraint_cols.row(anchor_count + h).segment(dim, dim) = V0.row(handles(h));
    constraint_cols(anchor_count + h, 2 * dim) = 1;
  }
  const PointMatrix X = solve_columns(delta_cols, extra_cols, constraint_cols);
  response.base = X.leftCols(dim);
  response.linear = X.rightCols(dim + 1);
}

namespace {

// Anchors and handles: disjoint vertex indices in range, without repeats, not both empty.
void check_constraints(const IndexVector& anchors, const IndexVector& handles, Index vertex_count) {
  if (anchors.size() + handles.size() == 0)
    fail<InputError>("no anchors and no handles: a Laplacian deformation needs at least one constrained vertex");
  std::vector<int> seen(vertex_count, 0);  // 1 anchor, 2 handle
  for (Index i = 0; i < anchors.size(); ++i) {
    const Index v = anchors(i);
    if (v < 0 || v >= vertex_count) fail<InputError>("anchor ", i, " is vertex ", v, ", outside 0..", vertex_count - 1);
    if (seen[v]) fail<InputError>("vertex ", v, " is listed twice as an anchor");
    seen[v] = 1;
  }
  for (Index i = 0; i < handles.size(); ++i) {
    const Index v = handles(i);
    if (v < 0 || v >= vertex_count) fail<InputError>("handle ", i, " is vertex ", v, ", outside 0..", vertex_count - 1);
    if (seen[v] == 1) fail<InputError>("vertex ", v, " is both an anchor and a handle");
    if (seen[v] == 2) fail<InputError>("vertex ", v, " is listed twice as a handle");
    seen[v] = 2;
  }
}

}  // namespace

// Factors the constrained system, growing the constraints (BoundaryRule::Grow)
// until it has full rank; each attempt is a "factorising" step.
void Deformer::Impl::factor_under_boundary_rule(const Interrupter& interrupter) {
  const Index vertex_count = static_cast<Index>(V.rows());
  VertexAdjacency adjacency;
  for (int attempt = 0;; ++attempt) {
    interrupter.step("factorising", 0.9 - 0.6 / (attempt + 1));
    const Index deficiency = build_and_factor();
    if (deficiency == 0) return;
    const std::string ghosts =
        info.ghosts > 0 ? " (the dual Laplacian has " + std::to_string(info.ghosts) +
                              " ghost vertices at the boundary, which can leave directions free)"
                        : "";
    if (options.boundary == BoundaryRule::Grow) {
      if (adjacency.offsets.empty()) adjacency = vertex_adjacency(S, vertex_count);
      const Index before = info.grown;
      grow_constraints(adjacency);
      if (info.grown > before) continue;
      fail<InputError>("the constrained system stays rank-deficient by ", deficiency,
                       " after growing the constraints over every reachable vertex", ghosts,
                       ": some part of the complex has no anchor or handle in its component");
    }
    fail<InputError>("the constrained system is rank-deficient: at least ", deficiency,
                     " more independent constraint(s) (anchor or handle vertices) are needed", ghosts,
                     "; ", anchors.size(), " anchors and ", handles.size(),
                     " handles were given. Add constraints, or use boundary='grow'",
                     options.boundary == BoundaryRule::GhostAnchors ? "" : " or 'ghost_anchors'");
  }
}

Deformer::Deformer(const PointMatrix& V, const SimplexMatrix& S, const IndexVector& anchors,
                   const IndexVector& handles, const DeformerOptions& options, const Interrupter& interrupter)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  interrupter.step("checks", 0);
  check_laplacian_input(V, S, "a Laplacian deformation");
  if (!(options.constraint_weight >= 0) || !std::isfinite(options.constraint_weight))
    fail<InputError>("constraint_weight must be >= 0 (0: hard constraints), got ", options.constraint_weight);
  check_constraints(anchors, handles, static_cast<Index>(V.rows()));
  d.V0 = V;
  d.V = V;
  d.S = S;
  d.options = options;
  d.dim = static_cast<int>(V.cols());
  d.diagonal = std::max((V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(), 1e-300);
  d.anchors = anchors;
  d.handles = handles;
  d.given_handles.assign(handles.data(), handles.data() + handles.size());
  d.handle_source.resize(handles.size());
  std::iota(d.handle_source.begin(), d.handle_source.end(), 0);

  interrupter.step("laplacian", 0.1);
  const auto laplacian_start = Clock::now();
  d.system = laplacian_system(V, S, options.laplacian);
  d.info.laplacian_seconds = seconds_since(laplacian_start);
  d.laplacian_rows = static_cast<Index>(d.system.L.rows());
  d.delta = d.system.delta;

  d.factor_under_boundary_rule(interrupter);
  d.constraint_positions.resize(static_cast<Index>(d.constrained.size()), d.dim);
  for (size_t c = 0; c < d.constrained.size(); ++c) d.constraint_positions.row(c) = V.row(d.constrained[c]);
}

Deformer::~Deformer() = default;
Deformer::Deformer(Deformer&&) noexcept = default;
Deformer& Deformer::operator=(Deformer&&) noexcept = default;



void Deformer::Impl::place_handles_by_transform(const Eigen::MatrixXd& transform) {
  const Eigen::MatrixXd linear = transform.topLeftCorner(dim, dim);
  const Eigen::RowVectorXd translation = transform.topRightCorner(dim, 1).transpose();
  const Index anchor_count = static_cast<Index>(anchors.size());
  for (Index c = 0; c < anchor_count; ++c) constraint_positions.row(c) = V0.row(anchors(c));
  for (Index h = 0; h < handles.size(); ++h)
    constraint_positions.row(anchor_count + h) = V0.row(handles(h)) * linear.transpose() + translation;
}

void Deformer::Impl::place_handles_at(const PointMatrix& positions, double s, const Eigen::MatrixXd* fit) {
  const Index anchor_count = static_cast<Index>(anchors.size());
  for (Index c = 0; c < anchor_count; ++c) constraint_positions.row(c) = V0.row(anchors(c));
  Eigen::MatrixXd fit_s;
  if (fit) fit_s = affine_power(*fit, s);
  for (Index h = 0; h < handles.size(); ++h) {
    const Index source = handle_source[h];
    const Eigen::RowVectorXd rest = V0.row(handles(h));
    const Eigen::RowVectorXd target = rest + positions.row(source) - V0.row(given_handles[source]);
    if (!fit || s == 1) {
      constraint_positions.row(anchor_count + h) = rest + s * (target - rest);
      continue;
    }
    // Along the best-fit rigid motion, plus the fraction s of what it misses.
    const auto apply = [&](const Eigen::MatrixXd& T) -> Eigen::RowVectorXd {
      return rest * T.topLeftCorner(dim, dim).transpose() + T.topRightCorner(dim, 1).transpose();
    };
    constraint_positions.row(anchor_count + h) = apply(fit_s) + s * (target - apply(*fit));
  }
}


PointMatrix Deformer::deform(const Eigen::MatrixXd& transform, int steps, const Interrupter& interrupter) {
  Impl& d = *impl_;
  const std::lock_guard lock(d.mutex);
  check_affine_transform(transform, d.dim);
  if (steps < 1) fail<InputError>("steps must be at least 1, got ", steps);
  if (d.system.method != LaplacianMethod::Dual) steps = 1;
  d.delta = d.system.delta;
  if (steps == 1) {
    interrupter.step("deforming", 0);
    d.place_handles_by_transform(transform);
    if (d.response.empty()) d.build_response();
    d.V = d.response.apply(transform);
    // Hard constraints land exactly where place_handles_by_transform put them.
    if (d.options.constraint_weight == 0)
      for (size_t c = 0; c < d.constrained.size(); ++c) d.V.row(d.constrained[c]) = d.constraint_positions.row(c);
    d.deformed = true;
    return d.V;
  }
  const Interrupter poll_only{{}, interrupter.interrupted};
  for (int k = 1; k <= steps; ++k) {
    interrupter.step("deforming", loop_fraction(0, 1, k - 1, steps));
    d.place_handles_by_transform(k == steps ? transform : affine_power(transform, double(k) / steps));
    d.V = d.solve();
    d.deformed = true;
    if (k < steps) d.restore(d.options.step_restore_iterations, d.options.step_restore_tolerance, poll_only);
  }
  return d.V;
}

PointMatrix Deformer::deform_to(const PointMatrix& positions, int steps, const Interrupter& interrupter) {
  Impl& d = *impl_;
  const std::lock_guard lock(d.mutex);
  const Index given = static_cast<Index>(d.given_handles.size());
  if (positions.rows() != given || positions.cols() != d.dim)
    fail<InputError>("handle positions must be ", given, " by ", d.dim, " (one row per handle), got ",
                     positions.rows(), " by ", positions.cols());
  if (!positions.allFinite()) fail<InputError>("handle positions have non-finite entries");
  if (steps < 1) fail<InputError>("steps must be at least 1, got ", steps);
  if (d.system.method != LaplacianMethod::Dual) steps = 1;
  d.delta = d.system.delta;
  // Intermediate handle positions follow fractions of the handles' best-fit
  // rigid motion (a linear blend would shrink a rotated cap on the way);
  // a fit rotating by exactly π has no unique fraction: blend linearly then.
  Eigen::MatrixXd fit;
  bool use_fit = steps > 1;
  if (use_fit) {
    PointMatrix rest(given, d.dim);
    for (Index h = 0; h < given; ++h) rest.row(h) = d.V0.row(d.given_handles[h]);
    fit = best_fit_rigid(rest, positions);
    try {
      affine_power(fit, 0.5);
    } catch (const InputError&) {
      use_fit = false;
    }
  }
  const Interrupter poll_only{{}, interrupter.interrupted};
  for (int k = 1; k <= steps; ++k) {
    interrupter.step("deforming", loop_fraction(0, 1, k - 1, steps));
    d.place_handles_at(positions, double(k) / steps, use_fit ? &fit : nullptr);
    d.V = d.solve();
    d.deformed = true;
    if (k < steps) d.restore(d.options.step_restore_iterations, d.options.step_restore_tolerance, poll_only);
  }
  return d.V;
}

RestoreStatus Deformer::restore(int max_iterations, double tolerance, const Interrupter& interrupter) {
  const std::lock_guard lock(impl_->mutex);
  return impl_->restore(max_iterations, tolerance, interrupter);
}

RestoreStatus Deformer::Impl::restore(int max_iterations, double tolerance, const Interrupter& interrupter) {
  Impl& d = *this;
  if (d.system.method != LaplacianMethod::Dual)
    fail<InputError>("restore applies to the dual Laplacian only (this Deformer uses '", to_string(d.system.method),
                     "')");
  if (!d.deformed) fail<InputError>("restore needs a deformation first: call deform or deform_to");
  if (max_iterations < 1) fail<InputError>("max_iterations must be at least 1, got ", max_iterations);
  if (!(tolerance > 0)) fail<InputError>("tolerance must be positive, got ", tolerance);
  RestoreStatus status;
  const Index simplex_count = d.system.dual.simplex_count();
  // One restore step G: rotate each δ'_s onto its neighbours' current normal, re-solve.
  auto step = [&](const PointMatrix& X) {
    const PointMatrix C = d.system.dual.D * X;
    const PointMatrix normals = dual_hyperplane_normals(C, d.system.dual.neighbours);
    for (Index s = 0; s < simplex_count; ++s) {
      if (d.system.degenerate[s] || normals.row(s).squaredNorm() == 0) continue;
      d.delta.row(s) = d.system.heights(s) * normals.row(s);
    }
    return d.solve();
  };
  // The plain iteration V ← G(V) is Au et al.'s non-linear Gauss-Seidel; on
  // large rotations it converges slowly or oscillates with period two (an
  // eigenvalue of G' near −1). Anderson acceleration (depth 5) on the fixed
  // point removes both; the reported motion is always that of the plain
  // step, |G(V) − V|, so convergence means a true fixed point.
  constexpr int depth = 5;
  const Eigen::Index size = d.V.size();
  std::vector<Eigen::VectorXd> dF, dG;
  Eigen::VectorXd f_prev, g_prev;
  PointMatrix X = d.V;
  double best = std::numeric_limits<double>::infinity();
  for (int it = 0; it < max_iterations; ++it) {
    interrupter.step("restoring", loop_fraction(0, 1, it, max_iterations));
    const PointMatrix G = step(X);
    const Eigen::VectorXd g = Eigen::Map<const Eigen::VectorXd>(G.data(), size);
    const Eigen::VectorXd f = g - Eigen::Map<const Eigen::VectorXd>(X.data(), size);
    status.iterations = it + 1;
    status.motion = (G - X).rowwise().norm().maxCoeff() / d.diagonal;
    d.V = G;
    if (!std::isfinite(status.motion)) break;
    if (status.motion < tolerance) {
      status.converged = true;
      break;
    }
    if (status.motion > 10 * best) {  // acceleration went astray: restart from the plain step
      dF.clear();
      dG.clear();
      f_prev.resize(0);
    }
    best = std::min(best, status.motion);
    if (f_prev.size()) {
      dF.push_back(f - f_prev);
      dG.push_back(g - g_prev);
      if (static_cast<int>(dF.size()) > depth) {
        dF.erase(dF.begin());
        dG.erase(dG.begin());
      }
    }
    f_prev = f;
    g_prev = g;
    Eigen::VectorXd next = g;
    if (!dF.empty()) {
      Eigen::MatrixXd M(size, static_cast<Eigen::Index>(dF.size()));
      for (size_t j = 0; j < dF.size(); ++j) M.col(static_cast<Eigen::Index>(j)) = dF[j];
      const Eigen::VectorXd gamma = least_squares_solution(M, f);
      if (gamma.allFinite())
        for (size_t j = 0; j < dG.size(); ++j) next -= gamma(static_cast<Eigen::Index>(j)) * dG[j];
    }
    X = Eigen::Map<const PointMatrix>(next.data(), d.V.rows(), d.V.cols());
  }
  return status;
}

PointMatrix Deformer::points() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->V;
}
const PointMatrix& Deformer::rest_points() const { return impl_->V0; }
const IndexVector& Deformer::anchors() const { return impl_->anchors; }
const IndexVector& Deformer::handles() const { return impl_->handles; }
const DifferentialSystem& Deformer::system() const { return impl_->system; }
const DeformerInfo& Deformer::info() const { return impl_->info; }
int Deformer::dimension() const { return impl_->dim; }

PointMatrix laplacian_deform(const PointMatrix& V, const SimplexMatrix& S, const IndexVector& anchors,
                             const IndexVector& handles, const Eigen::MatrixXd& transform,
                             const DeformerOptions& options, int restore_iterations, double restore_tolerance,
                             int steps) {
  Deformer deformer(V, S, anchors, handles, options);
  PointMatrix out = deformer.deform(transform, options.laplacian.method == LaplacianMethod::Dual ? steps : 1);
  if (restore_iterations > 0 && options.laplacian.method == LaplacianMethod::Dual) {
    deformer.restore(restore_iterations, restore_tolerance);
    out = deformer.points();
  }
  return out;
}

}  // namespace animanifold
