#include "animanifold/laplacian.hpp"
#include "animanifold/simplex_qp.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

namespace {

// CSR triple (indptr, indices, data) and shape: numpy-only callers need no scipy.
py::tuple csr(const SparseRowMatrix& M) {
  SparseRowMatrix A = M;
  A.makeCompressed();
  const auto rows = A.rows(), nnz = A.nonZeros();
  py::array_t<std::int64_t> indptr(rows + 1);
  py::array_t<std::int32_t> indices(nnz);
  py::array_t<double> data(nnz);
  auto p = indptr.mutable_unchecked<1>();
  auto i = indices.mutable_unchecked<1>();
  auto x = data.mutable_unchecked<1>();
  for (Eigen::Index r = 0; r <= rows; ++r) p(r) = A.outerIndexPtr()[r];
  for (Eigen::Index k = 0; k < nnz; ++k) {
    i(k) = A.innerIndexPtr()[k];
    x(k) = A.valuePtr()[k];
  }
  return py::make_tuple(indptr, indices, data, py::make_tuple(A.rows(), A.cols()));
}

GraphWeightOptions graph_options(double lambda, double xi, double ridge) {
  GraphWeightOptions o;
  o.lambda = lambda;
  o.xi = xi;
  o.ridge = ridge;
  return o;
}

LaplacianOptions laplacian_options(LaplacianMethod method, double lambda, double xi, double ridge,
                                   IndicesRef zero_detail) {
  LaplacianOptions o;
  o.method = method;
  o.graph = graph_options(lambda, xi, ridge);
  o.zero_detail_vertices.assign(zero_detail.data(), zero_detail.data() + zero_detail.size());
  return o;
}

}  // namespace

// The Laplacian's building blocks, for the tests.
static void bind_laplacian_parts(py::module_& testing) {
  const GraphWeightOptions defaults;
  testing.def("simplex_qp",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double lower, int max_iterations) {
          const auto r = solve_simplex_qp(H, g, lower, max_iterations);
          return py::make_tuple(r.weights, r.objective, r.iterations, r.converged);
        },
        py::arg("H"), py::arg("g"), py::arg("lower"), py::arg("max_iterations") = 0,
        "min ½wᵀHw + gᵀw s.t. Σw = 1, w >= lower → (weights, objective, iterations, converged).");
  testing.def("primal_weights",
        [](PointsRef V, SimplicesRef S, LaplacianMethod method, double lambda, double xi, double ridge) {
          const GraphWeightOptions options = graph_options(lambda, xi, ridge);
          SparseRowMatrix W = without_gil([&] { return primal_weights(V, S, method, options); });
          return csr(W);
        },
        py::arg("points"), py::arg("simplices"), py::arg("method"), py::arg("lam") = defaults.lambda,
        py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge,
        "Primal weights W (#V by #V) as CSR (indptr, indices, data, shape); raises ValueError for an unknown method.");
  testing.def("boundary_vertices",
        [](SimplicesRef S, Index vertex_count) {
          const auto flags = boundary_vertices(S, vertex_count);
          py::array_t<bool> out(static_cast<py::ssize_t>(flags.size()));
          auto o = out.mutable_unchecked<1>();
          for (size_t i = 0; i < flags.size(); ++i) o(static_cast<py::ssize_t>(i)) = flags[i] != 0;
          return out;
        },
        py::arg("simplices"), py::arg("vertex_count"),
        "Whether each of the vertex_count vertices lies on a boundary facet of the simplices (#V bool vector).");
  testing.def("dual_operator",
        [](SimplicesRef S, Index vertex_count) {
          const DualOperator d = dual_operator(S, vertex_count);
          return py::make_tuple(csr(d.D), d.neighbours, d.ghost_facets);
        },
        py::arg("simplices"), py::arg("vertex_count"),
        "(D as CSR, neighbours (#S by n+1), ghost_facets (#G by 2)).");
  testing.def("laplacian_system",
        [](PointsRef V, SimplicesRef S, LaplacianMethod method, double lambda, double xi, double ridge,
           IndicesRef zero_detail) {
          const LaplacianOptions options = laplacian_options(method, lambda, xi, ridge, zero_detail);
          DifferentialSystem s = without_gil([&] { return laplacian_system(V, S, options); });
          return py::make_tuple(csr(s.L), s.delta);
        },
        py::arg("points"), py::arg("simplices"), py::arg("method") = LaplacianMethod::Dual, py::arg("lam") = defaults.lambda,
        py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge,
        py::arg("zero_detail_vertices") = IndexVector{}, "(L as CSR, delta): L V = Δ for the input.");

  testing.def("affine_power", &affine_power, py::arg("transform"), py::arg("s"),
        "T^s: the fraction s of an affine (D+1)x(D+1) transform (polar factors about its fixed point).");
}

// The Deformer and its results.
static void bind_deformer(py::module_& m) {
  const GraphWeightOptions defaults;
  py::class_<RestoreStatus>(m, "RestoreStatus", "How Deformer.restore() ended.")
      .def_readonly("iterations", &RestoreStatus::iterations, "Iterations run.")
      .def_readonly("motion", &RestoreStatus::motion,
                    "Last largest vertex displacement over the input's bounding-box diagonal.")
      .def_readonly("converged", &RestoreStatus::converged, "Whether motion fell below the tolerance in time.");
  py::class_<DeformerInfo>(m, "DeformerInfo", "Sizes and conditioning of a Deformer's least-squares system.")
      .def_readonly("rows", &DeformerInfo::rows, "Rows of the least-squares system.")
      .def_readonly("unknowns", &DeformerInfo::unknowns, "Free vertices (hard constraints) or all vertices (soft).")
      .def_readonly("ghosts", &DeformerInfo::ghosts, "Ghost dual vertices (dual scheme).")
      .def_readonly("ghost_anchor_rows", &DeformerInfo::ghost_anchor_rows, "Rows added by the ghost-anchors rule.")
      .def_readonly("grown", &DeformerInfo::grown, "Constraints added by the grow rule.")
      .def_readonly("rcond", &DeformerInfo::rcond, "CHOLMOD's reciprocal condition estimate of the factor.")
      .def_readonly("factor_nonzeros", &DeformerInfo::factor_nonzeros, "Non-zeros of the factor.")
      .def_readonly("factor_flops", &DeformerInfo::factor_flops, "Floating-point operations of the factorisation.")
      .def_readonly("factor_tiled_blas_calls", &DeformerInfo::factor_tiled_blas_calls,
                    "BLAS calls of the factorisation run by tiles on every thread (0: small, or another BLAS).")
      .def_readonly("factor_openmp_teams_capped", &DeformerInfo::factor_openmp_teams_capped,
                    "CHOLMOD's OpenMP teams held to the thread count (0: none asked for more, or another libgomp).")
      .def_readonly("laplacian_seconds", &DeformerInfo::laplacian_seconds,
                    "Seconds building the weights and L (for reports).")
      .def_readonly("normal_seconds", &DeformerInfo::normal_seconds,
                    "Seconds assembling the constrained rows and the normal matrix (for reports).")
      .def_readonly("analyse_seconds", &DeformerInfo::analyse_seconds,
                    "Seconds in CHOLMOD's ordering and symbolic analysis (for reports).")
      .def_readonly("factorise_seconds", &DeformerInfo::factorise_seconds,
                    "Seconds in CHOLMOD's numerical factorisation (for reports).");
  py::class_<Deformer>(m, "Deformer", "Laplacian editing with a kept CHOLMOD factorisation.")
      .def(py::init([](PointsRef V, SimplicesRef S, IndicesRef anchors, IndicesRef handles,
                       LaplacianMethod method, BoundaryRule boundary, double lambda, double xi, double ridge,
                       double constraint_weight, IndicesRef zero_detail, const py::object& progress,
                       const py::object& interrupted) {
             DeformerOptions o;
             o.laplacian = laplacian_options(method, lambda, xi, ridge, zero_detail);
             o.boundary = boundary;
             o.constraint_weight = constraint_weight;
             const PointMatrix points = V;
             const SimplexMatrix simplices = S;
             const Interrupter interrupter = interrupter_from(progress, interrupted);
             return without_gil(
                 [&] { return std::make_unique<Deformer>(points, simplices, anchors, handles, o, interrupter); });
           }),
           py::arg("points"), py::arg("simplices"), py::arg("anchors"), py::arg("handles"),
           py::arg("method") = LaplacianMethod::Dual, py::arg("boundary") = BoundaryRule::Grow, py::arg("lam") = defaults.lambda,
           py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge, py::arg("constraint_weight") = 0.0,
           py::arg("zero_detail_vertices") = IndexVector{}, py::kw_only(), py::arg("progress") = py::none(),
           py::arg("interrupted") = py::none(),
           (std::string("Builds and factors the Laplacian system of points (#V by D) and simplices with anchors and "
                        "handles fixed; raises ValueError for an unknown method or boundary rule, MeshingError when "
                        "CHOLMOD fails.") +
            kInterrupterDoc)
               .c_str())
      .def("deform",
           [](Deformer& d, const Eigen::MatrixXd& T, int steps, const py::object& progress,
              const py::object& interrupted) {
             const Interrupter interrupter = interrupter_from(progress, interrupted);
             return without_gil([&] { return d.deform(T, steps, interrupter); });
           },
           py::arg("transform"), py::arg("steps") = 1, py::kw_only(), py::arg("progress") = py::none(),
           py::arg("interrupted") = py::none(),
           (std::string("Points (#V by D) with the handles moved by the affine (D+1)x(D+1) transform, in `steps` "
                        "fractions, each a \"deforming\" step.") +
            kInterrupterDoc)
               .c_str())
      .def("deform_to",
           [](Deformer& d, const PointMatrix& P, int steps, const py::object& progress,
              const py::object& interrupted) {
             const Interrupter interrupter = interrupter_from(progress, interrupted);
             return without_gil([&] { return d.deform_to(P, steps, interrupter); });
           },
           py::arg("positions"), py::arg("steps") = 1, py::kw_only(), py::arg("progress") = py::none(),
           py::arg("interrupted") = py::none(),
           (std::string("Points (#V by D) with the handles moved to `positions` (#handles by D), in `steps` "
                        "fractions, each a \"deforming\" step.") +
            kInterrupterDoc)
               .c_str())
      .def("restore",
           [](Deformer& d, int max_iterations, double tolerance, const py::object& progress,
              const py::object& interrupted) {
             const Interrupter interrupter = interrupter_from(progress, interrupted);
             return without_gil([&] { return d.restore(max_iterations, tolerance, interrupter); });
           },
           py::arg("max_iterations") = 50, py::arg("tolerance") = 1e-6, py::kw_only(),
           py::arg("progress") = py::none(), py::arg("interrupted") = py::none(),
           (std::string("Iterates the rotation-restoring solve, each round a \"restoring\" step; returns a "
                        "RestoreStatus.") +
            kInterrupterDoc)
               .c_str())
      .def_property_readonly("points", [](const Deformer& d) { return d.points(); }, "Current points (#V by D).")
      .def_property_readonly("anchors", [](const Deformer& d) { return d.anchors(); }, "Fixed vertex indices.")
      .def_property_readonly("handles", [](const Deformer& d) { return d.handles(); }, "Moved vertex indices.")
      .def_property_readonly("laplacian", [](const Deformer& d) { return csr(d.system().L); },
                             "L as CSR (indptr, indices, data, shape).")
      .def_property_readonly("delta", [](const Deformer& d) { return d.system().delta; },
                             "The differential coordinates Δ = L V of the rest shape.")
      .def_property_readonly("info", [](const Deformer& d) { return d.info(); },
                             "The solve's sizes and conditioning (a DeformerInfo).");
}

void bind_laplacian(py::module_& m, py::module_& testing) {
  // Before the functions whose defaults are their values.
  bind_named_enum(m, "LaplacianMethod", "Laplacian method", kLaplacianMethodNames,
                  "Laplacian weights: dual (Au et al. 2006), graph (QP of eq. 4.2), uniform, cotangent.");
  bind_named_enum(m, "BoundaryRule", "boundary rule", kBoundaryRuleNames,
                  "What the dual method does when its ghost vertices leave too few constraints (§4.4.2).");
  bind_laplacian_parts(testing);
  bind_deformer(m);
}

}  // namespace animanifold::bindings
