#include "animanifold/normals.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"
#include "animanifold/validation.hpp"

#include <Eigen/Dense>
#include <omp.h>
#include <algorithm>
#include <cstdint>
#include <cmath>
#include <vector>

namespace animanifold {

namespace {

// Fixed-size wedge of the rows of an n by n+1 matrix: N_j is the cofactor of
// e_j on the bottom row of eq. 2.2, (-1)^(D+j) times the minor without column
// j (1-based j, D = n+1).
template <int D>
Eigen::Matrix<double, D, 1> wedge_fixed(const Eigen::Matrix<double, D - 1, D>& rows) {
  Eigen::Matrix<double, D, 1> n;
  for (int j = 0; j < D; ++j) {
    Eigen::Matrix<double, D - 1, D - 1> minor;
    for (int c = 0, m = 0; c < D; ++c)
      if (c != j) minor.col(m++) = rows.col(c);
    const double sign = ((D + j + 1) % 2 == 0) ? 1.0 : -1.0;
    n(j) = sign * minor.determinant();
  }
  return n;
}

template <int D>
void simplex_normals_fixed(const PointMatrix& V, const SimplexMatrix& S, PointMatrix& N) {
  // Each simplex writes its own row: the same normals for any thread count.
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) {
    Eigen::Matrix<double, D - 1, D> edges;
    for (int i = 0; i < D - 1; ++i) edges.row(i) = V.row(S(s, i + 1)) - V.row(S(s, 0));
    N.row(s) = wedge_fixed<D>(edges).transpose();
  }
}

}  // namespace

Eigen::VectorXd wedge(const PointMatrix& vectors) {
  const int D = static_cast<int>(vectors.cols());
  if (vectors.rows() != D - 1)
    fail<InputError>("wedge product needs n vectors in R^(n+1); got ", vectors.rows(), " in R^", D);
  Eigen::VectorXd n(D);
  for (int j = 0; j < D; ++j) {
    Eigen::MatrixXd minor(D - 1, D - 1);
    for (int c = 0, m = 0; c < D; ++c)
      if (c != j) minor.col(m++) = vectors.col(c);
    const double sign = ((D + j + 1) % 2 == 0) ? 1.0 : -1.0;
    n(j) = D == 1 ? sign : sign * minor.determinant();
  }
  return n;
}

namespace {

// Weighted normals are products of D-1 coordinate differences, and their
// lengths square those: coordinates of 1e154 (3D) or far less (4D) overflow
// to inf, tiny ones underflow to 0, and the unit normals become NaN or zero.
// Scaling every point by one power of two is exact and keeps the weights'
// ratios (the unit normals are bit for bit those of the unscaled points), so
// points far from unit size are brought to it first.
PointMatrix scaled_for_products(const PointMatrix& V) {
  const double largest = V.size() ? V.cwiseAbs().maxCoeff() : 0.0;
  if (!std::isfinite(largest) || largest == 0 || (largest > 1e-32 && largest < 1e32)) return V;
  return V * std::ldexp(1.0, -std::ilogb(largest));
}

}  // namespace

PointMatrix simplex_normals(const PointMatrix& V, const SimplexMatrix& S) {
  const int D = static_cast<int>(V.cols());
  if (S.cols() != D)
    fail<InputError>("simplex normals need n-simplices in R^(n+1); got ", S.cols(), " vertices in R^", D);
  check_indices(S, V.rows(), "simplex");
  PointMatrix N(S.rows(), D);
  switch (D) {
    case 2: simplex_normals_fixed<2>(V, S, N); break;
    case 3: simplex_normals_fixed<3>(V, S, N); break;
    case 4: simplex_normals_fixed<4>(V, S, N); break;
    default: {
      PointMatrix edges(D - 1, D);
      for (Index s = 0; s < S.rows(); ++s) {
        for (int i = 0; i < D - 1; ++i) edges.row(i) = V.row(S(s, i + 1)) - V.row(S(s, 0));
        N.row(s) = wedge(edges).transpose();
      }
    }
  }
  return N;
}

PointMatrix vertex_normals(const PointMatrix& V, const SimplexMatrix& S) {
  const PointMatrix face_normals = simplex_normals(scaled_for_products(V), S);
  PointMatrix N = PointMatrix::Zero(V.rows(), V.cols());
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < S.cols(); ++c) N.row(S(s, c)) += face_normals.row(s);
  for (Index v = 0; v < N.rows(); ++v) {
    const double length = N.row(v).norm();
    if (length > 0) N.row(v) /= length;
  }
  return N;
}

PointMatrix drop_component(const PointMatrix& normals, int axis) {
  const int D = static_cast<int>(normals.cols());
  if (axis < 0 || axis >= D) fail<InputError>("axis ", axis, " is outside 0..", D - 1);
  PointMatrix out(normals.rows(), D - 1);
  for (Index r = 0; r < normals.rows(); ++r) {
    for (int c = 0, m = 0; c < D; ++c)
      if (c != axis) out(r, m++) = normals(r, c);
    const double length = out.row(r).norm();
    if (length > 0) out.row(r) /= length;
  }
  return out;
}

namespace {

// Faces from which frame normals run on OpenMP's threads.
constexpr Index kParallelFaces = 16384;

// Each face's normal, twice its area (3D) or its length (2D), summed onto
// its corners' rows of N (sized, not yet set) in face order, then each row made unit length.
// Fixed-size: this runs for every frame a slice writes.
//
// Each thread owns a range of rows and walks every face, adding only onto
// its own rows: every row still sums its faces' normals in face order, so
// the bits are those of one thread for any thread count (a face whose
// corners fall in two ranges has its normal computed by both, identically).
template <int d>
void add_face_normals(const PointMatrix& V, const SimplexMatrix& F, PointMatrix& N) {
  // Raw rows (both matrices are row-major, d wide): Eigen's dynamic-size row
  // views cost more than the arithmetic on a frame of a few hundred thousand faces.
  const Index faces = static_cast<Index>(F.rows());
  const double* points = V.data();
  const Index* corners = F.data();
  double* normals = N.data();
#pragma omp parallel num_threads(thread_count()) if (faces > kParallelFaces)
  {
    const std::int64_t rows = N.rows(), teams = omp_get_num_threads(), team = omp_get_thread_num();
    const Index lo = static_cast<Index>(rows * team / teams), hi = static_cast<Index>(rows * (team + 1) / teams);
    std::fill(normals + static_cast<std::int64_t>(lo) * d, normals + static_cast<std::int64_t>(hi) * d, 0.0);
    for (Index f = 0; f < faces; ++f) {
      const Index* corner = corners + static_cast<std::int64_t>(f) * d;
      bool mine = false;
      for (int c = 0; c < d; ++c) mine |= corner[c] >= lo && corner[c] < hi;
      if (!mine) continue;
      double n[d];
      if constexpr (d == 3) {
        const double* a = points + 3 * static_cast<std::int64_t>(corner[0]);
        const double* b = points + 3 * static_cast<std::int64_t>(corner[1]);
        const double* c = points + 3 * static_cast<std::int64_t>(corner[2]);
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
      } else {
        const double* a = points + 2 * static_cast<std::int64_t>(corner[0]);
        const double* b = points + 2 * static_cast<std::int64_t>(corner[1]);
        n[0] = b[1] - a[1];
        n[1] = -(b[0] - a[0]);
      }
      for (int c = 0; c < d; ++c) {
        if (corner[c] < lo || corner[c] >= hi) continue;
        double* row = normals + static_cast<std::int64_t>(corner[c]) * d;
        for (int k = 0; k < d; ++k) row[k] += n[k];
      }
    }
    for (Index v = lo; v < hi; ++v) {
      double* row = normals + static_cast<std::int64_t>(v) * d;
      double squared = 0;
      for (int k = 0; k < d; ++k) squared += row[k] * row[k];
      const double length = std::sqrt(squared);
      if (length > 0)
        for (int k = 0; k < d; ++k) row[k] /= length;
    }
  }
}

}  // namespace

PointMatrix frame_vertex_normals(const PointMatrix& V, const SimplexMatrix& F) {
  check_indices(F, V.rows(), "face");
  return frame_vertex_normals_unchecked(V, F);
}

PointMatrix frame_vertex_normals_unchecked(const PointMatrix& V, const SimplexMatrix& F) {
  const int d = static_cast<int>(V.cols());
  if (F.cols() != d) fail<InputError>("frame faces must have ", d, " corners in R^", d, ", got ", F.cols());
  if (F.rows() && d != 2 && d != 3) fail<InputError>("frames are 2D or 3D, got ", d, "D");
  // The products of tiny or huge coordinates need scaling (scaled_for_products); others are used as they are.
  const double largest = V.size() ? V.cwiseAbs().maxCoeff() : 0.0;
  const bool as_is = !std::isfinite(largest) || largest == 0 || (largest > 1e-32 && largest < 1e32);
  PointMatrix scaled;
  if (!as_is) scaled = scaled_for_products(V);
  const PointMatrix& points = as_is ? V : scaled;
  if (d != 2 && d != 3) return PointMatrix::Zero(V.rows(), d);  // no faces
  PointMatrix N(V.rows(), d);
  if (d == 3) add_face_normals<3>(points, F, N);
  else add_face_normals<2>(points, F, N);
  return N;
}

}  // namespace animanifold
