#include "animanifold/laplacian.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/validation.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/simplex_qp.hpp"
#include "animanifold/threads.hpp"
#include "laplacian_input.hpp"
#include "least_squares.hpp"
#include "normal_equations.hpp"
#include "sparse_rows.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>

namespace animanifold {

// ---------------------------------------------------------------------------
// Names

LaplacianMethod parse_laplacian_method(const std::string& name) {
  return parse_name(name, kLaplacianMethodNames, "Laplacian method");
}

BoundaryRule parse_boundary_rule(const std::string& name) {
  return parse_name(name, kBoundaryRuleNames, "boundary rule");
}

std::string to_string(LaplacianMethod method) { return name_of(method, kLaplacianMethodNames); }

std::string to_string(BoundaryRule rule) { return name_of(rule, kBoundaryRuleNames); }

// ---------------------------------------------------------------------------
// Combinatorics

VertexAdjacency vertex_adjacency(const SimplexMatrix& S, Index vertex_count) {
  check_indices(S, vertex_count, "simplex");
  const int k = static_cast<int>(S.cols());
  std::vector<std::pair<Index, Index>> edges;
  edges.reserve(static_cast<size_t>(S.rows()) * k * (k - 1));
  for (Index s = 0; s < S.rows(); ++s)
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b)
        if (a != b) edges.emplace_back(S(s, a), S(s, b));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  VertexAdjacency adjacency;
  adjacency.offsets.assign(static_cast<size_t>(vertex_count) + 1, 0);
  adjacency.neighbours.reserve(edges.size());
  for (const auto& [a, b] : edges) {
    ++adjacency.offsets[a + 1];
    adjacency.neighbours.push_back(b);
  }
  for (Index v = 0; v < vertex_count; ++v) adjacency.offsets[v + 1] += adjacency.offsets[v];
  return adjacency;
}

std::vector<char> boundary_vertices(const SimplexMatrix& S, Index vertex_count) {
  check_indices(S, vertex_count, "simplex");
  std::vector<char> on_boundary(vertex_count, 0);
  const SimplexMatrix B = boundary_facets(S);
  for (Index r = 0; r < B.rows(); ++r)
    for (int c = 0; c < B.cols(); ++c) on_boundary[B(r, c)] = 1;
  return on_boundary;
}

void check_laplacian_input(const PointMatrix& V, const SimplexMatrix& S, const char* what) {
  const int D = static_cast<int>(V.cols());
  if (D != 3 && D != 4)
    fail<InputError>(what, " needs points in R^3 (triangles) or R^4 (tets), got ", D, " columns");
  if (S.cols() != D)
    fail<InputError>(what, " needs n-simplices in R^(n+1): ", D, "D points need simplices of ", D,
                     " vertices, got ", S.cols());
  if (S.rows() == 0) fail<InputError>(what, " needs at least one simplex");
  for (Index v = 0; v < V.rows(); ++v)
    for (int c = 0; c < D; ++c)
      if (!std::isfinite(V(v, c))) fail<InputError>("vertex ", v, " has a non-finite coordinate ", c);
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < D; ++c) {
      if (S(s, c) < 0 || S(s, c) >= V.rows())
        fail<InputError>("simplex ", s, " refers to vertex ", S(s, c), ", outside 0..", V.rows() - 1);
      for (int d = 0; d < c; ++d)
        if (S(s, c) == S(s, d)) fail<InputError>("simplex ", s, " repeats vertex ", S(s, c));
    }
}

// ---------------------------------------------------------------------------
// Primal weights

Eigen::VectorXd graph_laplacian_weights(const PointMatrix& edges, const GraphWeightOptions& options) {
  const Index k = static_cast<Index>(edges.rows());
  if (k == 0) return Eigen::VectorXd();
  if (!(options.lambda >= 0) || !(options.xi >= 0) || !(options.ridge > 0))
    fail<InputError>("graph Laplacian needs lambda >= 0, xi >= 0 and ridge > 0 (got lambda = ", options.lambda,
                     ", xi = ", options.xi, ", ridge = ", options.ridge, ")");
  const Eigen::VectorXd lengths2 = edges.rowwise().squaredNorm();
  const double mean2 = lengths2.mean();
  if (!(mean2 > 0)) return Eigen::VectorXd::Constant(k, 1.0 / k);
  Eigen::MatrixXd H = (2.0 / mean2) * (edges * edges.transpose());
  H.diagonal().array() += 2.0 * options.ridge;
  const Eigen::VectorXd g = (options.lambda / mean2) * lengths2;
  const double xi = std::min(options.xi, 0.5 / k);
  return solve_simplex_qp(H, g, xi).weights;
}

namespace {

void cotangent_triplets(const PointMatrix& V, const SimplexMatrix& S, std::vector<Eigen::Triplet<double>>& out) {
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < 3; ++c) {
      const Index a = S(s, (c + 1) % 3), b = S(s, (c + 2) % 3), o = S(s, c);
      const Eigen::Vector3d u = (V.row(a) - V.row(o)).transpose(), w = (V.row(b) - V.row(o)).transpose();
      const double sine = u.cross(w).norm();
      if (!(sine > 0)) fail<InputError>("simplex ", s, " is degenerate (zero area): no cotangent weight");
      const double cot = u.dot(w) / sine;
      out.emplace_back(a, b, cot);
      out.emplace_back(b, a, cot);
    }
}

}  // namespace

SparseRowMatrix primal_weights(const PointMatrix& V, const SimplexMatrix& S, LaplacianMethod method,
                               const GraphWeightOptions& graph) {
  check_laplacian_input(V, S, "a Laplacian");
  if (method == LaplacianMethod::Dual) fail<InputError>("primal_weights: the dual Laplacian has no primal weights");
  if (method == LaplacianMethod::Cotangent && (V.cols() != 3 || S.cols() != 3))
    fail<InputError>("cotangent weights exist only for triangle meshes in R^3 (2-manifolds); this complex has ",
                     S.cols() - 1, "-simplices in R^", V.cols(), ": use method 'dual', 'graph' or 'uniform'");
  const Index n = static_cast<Index>(V.rows());
  const VertexAdjacency adjacency = vertex_adjacency(S, n);
  const std::vector<char> on_boundary = boundary_vertices(S, n);

  SparseRowMatrix cot;
  if (method == LaplacianMethod::Cotangent) {
    std::vector<Eigen::Triplet<double>> triplets;
    cotangent_triplets(V, S, triplets);
    cot.resize(n, n);
    cot.setFromTriplets(triplets.begin(), triplets.end());
  }
  GraphWeightOptions boundary_options = graph;
  boundary_options.lambda = 0;  // eq. 4.3

  // Each vertex's weights go to its own slots (its adjacency range), so the
  // loop gives the same bits on any thread count; the first failure by vertex
  // index is rethrown after it (an exception may not leave an OpenMP region).
  std::vector<double> weights(adjacency.neighbours.size());
  std::vector<std::exception_ptr> failures(static_cast<size_t>(n));
#pragma omp parallel for schedule(dynamic, 256) num_threads(thread_count())
  for (Index i = 0; i < n; ++i) {
    const Index begin = adjacency.offsets[i], end = adjacency.offsets[i + 1], k = end - begin;
    if (k == 0) continue;
    try {
      if (on_boundary[i] || method == LaplacianMethod::Graph) {
        PointMatrix edges(k, V.cols());
        for (Index j = 0; j < k; ++j) edges.row(j) = V.row(adjacency.neighbours[begin + j]) - V.row(i);
        const Eigen::VectorXd w = graph_laplacian_weights(edges, on_boundary[i] ? boundary_options : graph);
        for (Index j = 0; j < k; ++j) weights[begin + j] = w(j);
      } else if (method == LaplacianMethod::Uniform) {
        for (Index j = begin; j < end; ++j) weights[j] = 1.0 / k;
      } else {  // cotangent, interior vertex: cot's row i has the same sorted columns as the adjacency
        double total = 0;
        for (SparseRowMatrix::InnerIterator it(cot, i); it; ++it) total += it.value();
        if (!(total > 1e-12))
          fail<InputError>("the cotangent weights of vertex ", i, " sum to ", total,
                           " (degenerate or very obtuse triangles around it): use method 'graph' or 'dual'");
        Index j = begin;
        for (SparseRowMatrix::InnerIterator it(cot, i); it; ++it) weights[j++] = it.value() / total;
      }
    } catch (...) {
      failures[i] = std::current_exception();
    }
  }
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(adjacency.neighbours.size());
  for (Index i = 0; i < n; ++i)
    for (Index j = adjacency.offsets[i]; j < adjacency.offsets[i + 1]; ++j)
      triplets.emplace_back(i, adjacency.neighbours[j], weights[j]);
  SparseRowMatrix W(n, n);
  W.setFromTriplets(triplets.begin(), triplets.end());
  return W;
}

// ---------------------------------------------------------------------------
// Dual operator

DualOperator dual_operator(const SimplexMatrix& S, Index vertex_count) {
  check_indices(S, vertex_count, "simplex");
  const int k = static_cast<int>(S.cols());  // n + 1 vertices per simplex
  const int n = k - 1;
  const Index simplex_count = static_cast<Index>(S.rows());
  const FacetAdjacency adjacency = facet_adjacency(S);
  DualOperator dual;
  dual.neighbours.resize(simplex_count, k);
  std::vector<std::pair<Index, int>> ghosts;
  for (Index s = 0; s < simplex_count; ++s)
    for (int i = 0; i < k; ++i) {
      const Index across = adjacency.neighbour(s, i);
      if (across >= 0) {
        dual.neighbours(s, i) = across;
      } else {
        dual.neighbours(s, i) = simplex_count + static_cast<Index>(ghosts.size());
        ghosts.emplace_back(s, i);
      }
    }
  dual.ghost_facets.resize(static_cast<Index>(ghosts.size()), 2);
  for (size_t g = 0; g < ghosts.size(); ++g) {
    dual.ghost_facets(static_cast<Index>(g), 0) = ghosts[g].first;
    dual.ghost_facets(static_cast<Index>(g), 1) = ghosts[g].second;
  }
  const double facet_weight = double(n + 2) / (double(n) * (n + 1));
  const double opposite_weight = -1.0 / (n + 1);
  // A simplex's row: its centroid; a ghost's: the reflection of the
  // simplex's centroid through the centroid of its boundary facet.
  dual.D = rows_of_width(simplex_count + static_cast<Index>(ghosts.size()), vertex_count, k,
                         [&](Index row, Index* columns, double* values) {
                           const bool ghost = row >= simplex_count;
                           const Index s = ghost ? ghosts[row - simplex_count].first : row;
                           const int i = ghost ? ghosts[row - simplex_count].second : -1;
                           for (int c = 0; c < k; ++c) {
                             columns[c] = S(s, c);
                             values[c] = !ghost ? 1.0 / k : c == i ? opposite_weight : facet_weight;
                           }
                         });
  return dual;
}

PointMatrix dual_hyperplane_normals(const PointMatrix& C, const SimplexMatrix& neighbours) {
  PointMatrix N = simplex_normals(C, neighbours);
  for (Index s = 0; s < N.rows(); ++s) {
    // Relative size of the wedge: zero when the neighbours are affinely dependent.
    double product = 1;
    for (int j = 1; j < neighbours.cols(); ++j) product *= (C.row(neighbours(s, j)) - C.row(neighbours(s, 0))).norm();
    const double length = N.row(s).norm();
    if (length > 1e-9 * product && length > 0) N.row(s) /= length;
    else N.row(s).setZero();
  }
  return N;
}

// ---------------------------------------------------------------------------
// The differential system

namespace {

std::vector<char> flags_of(const std::vector<Index>& vertices, Index vertex_count, const char* what) {
  std::vector<char> flags(vertex_count, 0);
  for (Index v : vertices) {
    if (v < 0 || v >= vertex_count) fail<InputError>(what, " vertex ", v, " is outside 0..", vertex_count - 1);
    flags[v] = 1;
  }
  return flags;
}

void primal_system(const PointMatrix& V, const SimplexMatrix& S, const LaplacianOptions& options,
                   DifferentialSystem& system) {
  const Index n = static_cast<Index>(V.rows());
  SparseRowMatrix W = primal_weights(V, S, options.method, options.graph);
  const std::vector<char> zero = flags_of(options.zero_detail_vertices, n, "zero-detail");
  if (!options.zero_detail_vertices.empty()) {
    // §4.5.1: new vertices get uniform weights (and δ = 0 below).
    const VertexAdjacency adjacency = vertex_adjacency(S, n);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(W.nonZeros());
    for (Index i = 0; i < n; ++i) {
      if (zero[i]) {
        const Index begin = adjacency.offsets[i], k = adjacency.offsets[i + 1] - begin;
        for (Index j = 0; j < k; ++j) triplets.emplace_back(i, adjacency.neighbours[begin + j], 1.0 / k);
      } else {
        for (SparseRowMatrix::InnerIterator it(W, i); it; ++it) triplets.emplace_back(i, it.col(), it.value());
      }
    }
    W.setZero();
    W.setFromTriplets(triplets.begin(), triplets.end());
  }
  SparseRowMatrix I(n, n);
  I.setIdentity();
  system.L = I - W;
  system.L.makeCompressed();
  system.delta = system.L * V;
  for (Index i = 0; i < n; ++i)
    if (zero[i]) system.delta.row(i).setZero();
}

void dual_system(const PointMatrix& V, const SimplexMatrix& S, const LaplacianOptions& options,
                 DifferentialSystem& system) {
  const Index vertex_count = static_cast<Index>(V.rows());
  const Index simplex_count = static_cast<Index>(S.rows());
  const int k = static_cast<int>(S.cols());
  const int n = k - 1;
  system.dual = dual_operator(S, vertex_count);
  const DualOperator& dual = system.dual;
  const PointMatrix C = dual.D * V;
  const Index dual_count = static_cast<Index>(C.rows());
  system.degenerate.assign(simplex_count, 0);

  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1>;
  // Each simplex's neighbour weights go to its own row of `weights`: the same bits on any thread count.
  PointMatrix weights(simplex_count, k);
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index s = 0; s < simplex_count; ++s) {
    // Barycentric coordinates of the projection of c_s onto the hyperplane of its n+1 neighbours.
    Small B(k, n);
    const auto p0 = C.row(dual.neighbours(s, 0));
    double product = 1;
    for (int j = 1; j < k; ++j) {
      B.col(j - 1) = (C.row(dual.neighbours(s, j)) - p0).transpose();
      product *= B.col(j - 1).squaredNorm();
    }
    const SmallVector r = (C.row(s) - p0).transpose();
    const Small gram = B.transpose() * B;
    SmallVector a;
    if (gram.determinant() > 1e-18 * product) {
      a = gram.ldlt().solve(B.transpose() * r);
    } else {
      system.degenerate[s] = 1;
      a = minimum_norm_solution(B, r);
    }
    weights(s, 0) = -(1.0 - a.sum());
    for (int j = 1; j < k; ++j) weights(s, j) = -a(j - 1);
  }
  system.dual_weights = rows_of_width(simplex_count, dual_count, k + 1, [&](Index s, Index* columns, double* values) {
    columns[0] = s, values[0] = 1.0;
    for (int j = 0; j < k; ++j) columns[j + 1] = dual.neighbours(s, j), values[j + 1] = weights(s, j);
  });
  system.L = product_by_row_blocks(system.dual_weights, dual.D);
  system.delta = system.L * V;

  const PointMatrix normals = dual_hyperplane_normals(C, dual.neighbours);
  system.heights.resize(simplex_count);
  for (Index s = 0; s < simplex_count; ++s) {
    system.heights(s) = system.delta.row(s).dot(normals.row(s));
    if (normals.row(s).squaredNorm() == 0) system.degenerate[s] = 1;
  }
  if (!options.zero_detail_vertices.empty()) {
    const std::vector<char> zero = flags_of(options.zero_detail_vertices, vertex_count, "zero-detail");
    for (Index s = 0; s < simplex_count; ++s)
      for (int c = 0; c < k; ++c)
        if (zero[S(s, c)]) {
          system.delta.row(s).setZero();
          system.heights(s) = 0;
        }
  }
}

}  // namespace

DifferentialSystem laplacian_system(const PointMatrix& V, const SimplexMatrix& S, const LaplacianOptions& options) {
  check_laplacian_input(V, S, "a Laplacian");
  DifferentialSystem system;
  system.method = options.method;
  if (options.method == LaplacianMethod::Dual) dual_system(V, S, options, system);
  else primal_system(V, S, options, system);
  return system;
}

}  // namespace animanifold
