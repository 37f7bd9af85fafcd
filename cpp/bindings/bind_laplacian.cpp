#include "animanifold/laplacian.hpp"
#include "animanifold/simplex_qp.hpp"
#include "bindings.hpp"

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

LaplacianOptions laplacian_options(const std::string& method, double lambda, double xi, double ridge,
                                   const std::vector<Index>& zero_detail) {
  LaplacianOptions o;
  o.method = parse_laplacian_method(method);
  o.graph = graph_options(lambda, xi, ridge);
  o.zero_detail_vertices = zero_detail;
  return o;
}

py::dict status_dict(const RestoreStatus& s) {
  py::dict out;
  out["iterations"] = s.iterations;
  out["motion"] = s.motion;
  out["converged"] = s.converged;
  return out;
}

}  // namespace

void bind_laplacian(py::module_& m) {
  const GraphWeightOptions defaults;
  m.def("simplex_qp",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double lower, int max_iterations) {
          const auto r = solve_simplex_qp(H, g, lower, max_iterations);
          return py::make_tuple(r.weights, r.objective, r.iterations, r.converged);
        },
        py::arg("H"), py::arg("g"), py::arg("lower"), py::arg("max_iterations") = 0,
        "min ½wᵀHw + gᵀw s.t. Σw = 1, w >= lower → (weights, objective, iterations, converged).");
  m.def("graph_laplacian_weights",
        [](PointsRef edges, double lambda, double xi, double ridge) {
          return graph_laplacian_weights(edges, graph_options(lambda, xi, ridge));
        },
        py::arg("edges"), py::arg("lam") = defaults.lambda, py::arg("xi") = defaults.xi,
        py::arg("ridge") = defaults.ridge, "Eq. 4.2 weights of one vertex from its one-ring edges v_j − v_i (k by D).");
  m.def("primal_weights",
        [](PointsRef V, SimplicesRef S, const std::string& method, double lambda, double xi, double ridge) {
          SparseRowMatrix W;
          {
            py::gil_scoped_release release;
            W = primal_weights(V, S, parse_laplacian_method(method), graph_options(lambda, xi, ridge));
          }
          return csr(W);
        },
        py::arg("points"), py::arg("simplices"), py::arg("method"), py::arg("lam") = defaults.lambda,
        py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge,
        "Primal weights W (#V by #V) as CSR (indptr, indices, data, shape).");
  m.def("boundary_vertices",
        [](SimplicesRef S, Index vertex_count) {
          const auto flags = boundary_vertices(S, vertex_count);
          py::array_t<bool> out(static_cast<py::ssize_t>(flags.size()));
          auto o = out.mutable_unchecked<1>();
          for (size_t i = 0; i < flags.size(); ++i) o(static_cast<py::ssize_t>(i)) = flags[i] != 0;
          return out;
        },
        py::arg("simplices"), py::arg("vertex_count"));
  m.def("dual_operator",
        [](SimplicesRef S, Index vertex_count) {
          const DualOperator d = dual_operator(S, vertex_count);
          return py::make_tuple(csr(d.D), d.neighbours, d.ghost_facets);
        },
        py::arg("simplices"), py::arg("vertex_count"),
        "(D as CSR, neighbours (#S by n+1), ghost_facets (#G by 2)).");
  m.def("laplacian_system",
        [](PointsRef V, SimplicesRef S, const std::string& method, double lambda, double xi, double ridge,
           const std::vector<Index>& zero_detail) {
          DifferentialSystem s;
          {
            py::gil_scoped_release release;
            s = laplacian_system(V, S, laplacian_options(method, lambda, xi, ridge, zero_detail));
          }
          return py::make_tuple(csr(s.L), s.delta);
        },
        py::arg("points"), py::arg("simplices"), py::arg("method") = "dual", py::arg("lam") = defaults.lambda,
        py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge,
        py::arg("zero_detail_vertices") = std::vector<Index>{}, "(L as CSR, delta): L V = Δ for the input.");

  m.def("affine_power", &affine_power, py::arg("transform"), py::arg("s"),
        "T^s: the fraction s of an affine (D+1)x(D+1) transform (polar factors about its fixed point).");
  py::class_<Deformer>(m, "Deformer", "Laplacian editing with a kept CHOLMOD factorisation.")
      .def(py::init([](PointsRef V, SimplicesRef S, const IndexVector& anchors, const IndexVector& handles,
                       const std::string& method, const std::string& boundary, double lambda, double xi, double ridge,
                       double constraint_weight, const std::vector<Index>& zero_detail) {
             DeformerOptions o;
             o.laplacian = laplacian_options(method, lambda, xi, ridge, zero_detail);
             o.boundary = parse_boundary_rule(boundary);
             o.constraint_weight = constraint_weight;
             const PointMatrix points = V;
             const SimplexMatrix simplices = S;
             py::gil_scoped_release release;
             return std::make_unique<Deformer>(points, simplices, anchors, handles, o);
           }),
           py::arg("points"), py::arg("simplices"), py::arg("anchors"), py::arg("handles"),
           py::arg("method") = "dual", py::arg("boundary") = "grow", py::arg("lam") = defaults.lambda,
           py::arg("xi") = defaults.xi, py::arg("ridge") = defaults.ridge, py::arg("constraint_weight") = 0.0,
           py::arg("zero_detail_vertices") = std::vector<Index>{})
      .def("deform",
           [](Deformer& d, const Eigen::MatrixXd& T, int steps) {
             py::gil_scoped_release release;
             return d.deform(T, steps);
           },
           py::arg("transform"), py::arg("steps") = 1)
      .def("deform_to",
           [](Deformer& d, const PointMatrix& P, int steps) {
             py::gil_scoped_release release;
             return d.deform_to(P, steps);
           },
           py::arg("positions"), py::arg("steps") = 1)
      .def("restore",
           [](Deformer& d, int max_iterations, double tolerance) {
             RestoreStatus s;
             {
               py::gil_scoped_release release;
               s = d.restore(max_iterations, tolerance);
             }
             return status_dict(s);
           },
           py::arg("max_iterations") = 50, py::arg("tolerance") = 1e-6)
      .def_property_readonly("points", [](const Deformer& d) { return d.points(); })
      .def_property_readonly("anchors", [](const Deformer& d) { return d.anchors(); })
      .def_property_readonly("handles", [](const Deformer& d) { return d.handles(); })
      .def_property_readonly("laplacian", [](const Deformer& d) { return csr(d.system().L); })
      .def_property_readonly("delta", [](const Deformer& d) { return d.system().delta; })
      .def_property_readonly("info", [](const Deformer& d) {
        const DeformerInfo& i = d.info();
        py::dict out;
        out["rows"] = i.rows;
        out["unknowns"] = i.unknowns;
        out["ghosts"] = i.ghosts;
        out["ghost_anchor_rows"] = i.ghost_anchor_rows;
        out["grown"] = i.grown;
        out["rcond"] = i.rcond;
        out["factor_nonzeros"] = i.factor_nonzeros;
        return out;
      });
}

}  // namespace animanifold::bindings
