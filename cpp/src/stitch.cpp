#include "animanifold/stitch.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/memory_estimates.hpp"
#include "animanifold/threads.hpp"
#include "animanifold/validation.hpp"
#include "huge_pages.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace animanifold {

namespace {

// The keyframe count m and vertices per keyframe k, checked against the
// arrays' shapes and the 32-bit index.
void check_shape(const StitchInput& in, Index& m, Index& k, int& d) {
  d = static_cast<int>(in.frames.cols());
  if (d != 2 && d != 3) fail<InputError>("keyframe points must be 2D or 3D, got ", d, " coordinates");
  if (in.faces.cols() != d)
    fail<InputError>("faces must have ", d, " vertices for ", d, "D keyframes (", d == 3 ? "triangles" : "edges",
                     "), got ", in.faces.cols());
  if (in.times.size() < 2) fail<InputError>("an animation manifold needs at least two keyframes, got ", in.times.size());
  if (in.frames.rows() % in.times.size() != 0)
    fail<InputError>(in.frames.rows(), " keyframe points do not split into ", in.times.size(),
                     " keyframes of equal size");
  check_stitch_size(in.times.size(), in.frames.rows() / in.times.size(), in.faces.rows(), d);
  m = static_cast<Index>(in.times.size());
  k = static_cast<Index>(in.frames.rows() / m);
  if (k == 0) fail<InputError>("keyframes have no vertices");
  if (in.faces.rows() == 0) fail<InputError>("keyframes have no faces");
}

void check_times_and_points(const StitchInput& in, Index m, Index k, int d) {
  for (Index i = 0; i < m; ++i) {
    if (!std::isfinite(in.times(i))) fail<InputError>("time of keyframe ", i, " is not finite");
    if (i > 0 && !(in.times(i) > in.times(i - 1)))
      fail<InputError>("keyframe times must increase strictly: keyframe ", i, " at t=", in.times(i),
                       " follows t=", in.times(i - 1));
  }
  // Slicing measures positions along the time axis by differences of times.
  if (!std::isfinite(in.times(m - 1) - in.times(0)))
    fail<InputError>("keyframe times from t=", in.times(0), " (keyframe 0) to t=", in.times(m - 1), " (keyframe ",
                     m - 1, ") span more than a double can hold");
  for (Index r = 0; r < in.frames.rows(); ++r)
    for (int c = 0; c < d; ++c)
      if (!std::isfinite(in.frames(r, c)))
        fail<InputError>("keyframe ", r / k, ", vertex ", r % k, " has a non-finite coordinate");
}

// A face and its exact reverse bound nothing between them: both cancel in
// every slice, so no keyframe would be reproduced.
void check_no_reversed_faces(const SimplexMatrix& faces) {
  struct Record {
    std::array<Index, 3> key;
    int parity;
    Index face;
  };
  const int d = static_cast<int>(faces.cols());
  std::vector<Record> records(faces.rows());
  for (Index f = 0; f < faces.rows(); ++f) {
    Record& r = records[f];
    r.key = {-1, -1, -1};
    std::copy(faces.row(f).data(), faces.row(f).data() + d, r.key.begin());
    r.parity = permutation_parity(r.key.data(), d);
    std::sort(r.key.begin(), r.key.begin() + d);
    r.face = f;
  }
  std::sort(records.begin(), records.end(),
            [](const Record& a, const Record& b) { return a.key < b.key || (a.key == b.key && a.face < b.face); });
  for (size_t i = 0; i + 1 < records.size(); ++i) {
    const Record &a = records[i], &b = records[i + 1];
    if (a.key == b.key && a.parity != b.parity)
      fail<InputError>("faces ", a.face, " and ", b.face, " are one ", d == 3 ? "triangle" : "edge",
                       " in opposite orientations: they cancel in every slice, so no keyframe would be reproduced");
  }
}

void check_faces(const StitchInput& in, Index k, int d) {
  for (Index f = 0; f < in.faces.rows(); ++f)
    for (int a = 0; a < d; ++a) {
      const Index v = in.faces(f, a);
      if (v < 0 || v >= k) fail<InputError>("face ", f, " refers to vertex ", v, ", outside 0..", k - 1);
      for (int b = a + 1; b < d; ++b)
        if (in.faces(f, b) == v) fail<InputError>("face ", f, " repeats vertex ", v);
    }
  check_no_reversed_faces(in.faces);
}

void check_attributes(const StitchInput& in, Index m, Index k) {
  for (const auto& [name, table] : in.vertex_attributes)
    if (table.rows() != k && table.rows() != static_cast<Eigen::Index>(m) * k)
      fail<InputError>("vertex attribute '", name, "' has ", table.rows(), " rows; expected ", k,
                       " (one per keyframe vertex) or ", static_cast<Eigen::Index>(m) * k, " (per keyframe)");
  for (const auto& [name, table] : in.face_attributes)
    if (table.rows() != in.faces.rows())
      fail<InputError>("face attribute '", name, "' has ", table.rows(), " rows for ", in.faces.rows(), " faces");
}

void validate(const StitchInput& in, Index& m, Index& k, int& d) {
  check_shape(in, m, k, d);
  check_times_and_points(in, m, k, d);
  check_faces(in, k, d);
  check_attributes(in, m, k);
}

// The staircase split of the prism over a face whose vertices, sorted by
// index, are v0 < v1 < ... < v_{n-1}: simplex r is
// [p0 .. p_{n-1-r}, q_{n-1-r} .. q_{n-1}] (p at the earlier keyframe, q at
// the later). A side quad (vi, vj), i < j, is always cut by the diagonal
// p_i–q_j, whichever prism it belongs to, so neighbours agree.
//
// Orientation: every simplex gets the orientation of the "tent"
// [L, f0, ..., f_{n-1}] over the face f (in the face's own order), L being f0
// lifted to the later keyframe. The tent's facet opposite L is f itself, so
// the first keyframe appears in the boundary in its own orientation and an
// iso-slice (the outward facet of the part above the cut) reproduces every
// keyframe's orientation. Orientations are compared by the sign of the
// determinant in the prism's reference coordinates (face vertex j at the
// origin or unit vector e_{j-1}; time last), which is exact.
template <int n>
int tent_determinant_sign() {
  // Rows L - f0, f1 - f0 ... as edges from L: (f_j - L) = e_{j-1} - t.
  Eigen::Matrix<double, n, n> edges = Eigen::Matrix<double, n, n>::Zero();
  for (int j = 0; j < n; ++j) {
    if (j > 0) edges(j, j - 1) = 1.0;
    edges(j, n - 1) = -1.0;
  }
  return edges.determinant() > 0 ? 1 : -1;
}

template <int n>
void split_prism(const Index* face, Index bottom, Index top, const IndexVector& rank, Index* out /* n*(n+1) */) {
  std::array<Index, n> sorted;
  std::copy(face, face + n, sorted.begin());
  // The split follows a global order of the keyframe vertices (their rank):
  // any order makes neighbouring prisms agree on their shared side quad.
  std::sort(sorted.begin(), sorted.end(), [&](Index a, Index b) { return rank(a) < rank(b); });
  // Reference coordinates of each face vertex: its position in the face's own order.
  std::array<int, n> slot{};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (face[j] == sorted[i]) slot[i] = j;

  for (int r = 0; r < n; ++r) {
    Index* simplex = out + r * (n + 1);
    Eigen::Matrix<double, n + 1, n> reference;  // rows: vertices; cols: (barycentric axes..., t)
    int c = 0;
    auto add = [&](int i, bool upper) {
      simplex[c] = sorted[i] + (upper ? top : bottom);
      reference.row(c).setZero();
      if (slot[i] > 0) reference(c, slot[i] - 1) = 1.0;
      reference(c, n - 1) = upper ? 1.0 : 0.0;
      ++c;
    };
    for (int i = 0; i < n - r; ++i) add(i, false);
    for (int i = n - 1 - r; i < n; ++i) add(i, true);
    Eigen::Matrix<double, n, n> edges;
    for (int i = 0; i < n; ++i) edges.row(i) = reference.row(i + 1) - reference.row(0);
    if ((edges.determinant() > 0) != (tent_determinant_sign<n>() > 0)) std::swap(simplex[0], simplex[1]);
  }
}

}  // namespace

void check_stitch_size(std::int64_t keyframes, std::int64_t vertices, std::int64_t faces, int corners) {
  // Each factor is checked alone first, so that no product below can overflow 64 bits.
  checked_index_count(keyframes, "keyframes");
  checked_index_count(vertices, "vertices per keyframe");
  checked_index_count(faces, "faces");
  checked_index_count(keyframes * vertices, "the manifold's points (keyframes times vertices)");
  const Index prisms = checked_index_count((keyframes - 1) * faces, "the manifold's prisms");
  checked_index_count(std::int64_t{prisms} * corners, "the manifold's simplices");
}

Complex stitch(const StitchInput& in, const Interrupter& interrupter) {
  interrupter.step("checks", 0);
  check_memory(stitch_memory(in));
  Index m = 0, k = 0;
  int d = 0;
  validate(in, m, k, d);
  const Index l = static_cast<Index>(in.faces.rows());
  const int n = d;  // simplices per prism == vertices per face

  Complex out;
  out.V.resize(static_cast<Eigen::Index>(m) * k, d + 1);
  advise_huge_pages(out.V.data(), sizeof(double) * out.V.size());
  for (Index i = 0; i < m; ++i) {
    out.V.block(static_cast<Eigen::Index>(i) * k, 0, k, d) = in.frames.block(static_cast<Eigen::Index>(i) * k, 0, k, d);
    out.V.block(static_cast<Eigen::Index>(i) * k, d, k, 1).setConstant(in.times(i));
  }

  IndexVector rank(k);
  if (in.vertex_order.size() == 0) {
    for (Index v = 0; v < k; ++v) rank(v) = v;
  } else {
    // vertex_order lists the vertices in order; rank is its inverse.
    std::vector<bool> seen(k, false);
    for (Index r = 0; r < k; ++r) {
      const Index v = in.vertex_order(r);
      if (v < 0 || v >= k || seen[v])
        fail<InputError>("vertex_order must list every keyframe vertex 0..", k - 1, " once; entry ", r, " is ", v);
      seen[v] = true;
      rank(v) = r;
    }
  }
  const Eigen::Index prism_count = static_cast<Eigen::Index>(m - 1) * l;
  out.S.resize(prism_count * n, d + 1);
  advise_huge_pages(out.S.data(), sizeof(Index) * out.S.size());
  for (Index i = 0; i + 1 < m; ++i) {
    interrupter.step("prisms", loop_fraction(0.1, 0.9, i, m - 1));
    // Each prism writes its own rows (stitched_simplex), so any thread count gives the same simplices.
#pragma omp parallel for schedule(static) num_threads(thread_count())
    for (Index f = 0; f < l; ++f) {
      Index* dst = out.S.row(stitched_simplex(i, f, l, n)).data();
      if (n == 3) split_prism<3>(in.faces.row(f).data(), i * k, (i + 1) * k, rank, dst);
      else split_prism<2>(in.faces.row(f).data(), i * k, (i + 1) * k, rank, dst);
    }
  }
  interrupter.step("attributes", 0.9);

  for (const auto& [name, table] : in.vertex_attributes) {
    if (table.rows() == out.V.rows()) {
      out.vertex_attributes[name] = table;
    } else {
      PointMatrix repeated(out.V.rows(), table.cols());
      for (Index i = 0; i < m; ++i) repeated.block(static_cast<Eigen::Index>(i) * k, 0, k, table.cols()) = table;
      out.vertex_attributes[name] = std::move(repeated);
    }
  }
  for (const auto& [name, table] : in.face_attributes) {
    SimplexMatrix carried(out.S.rows(), table.cols());
    advise_huge_pages(carried.data(), sizeof(Index) * carried.size());
#pragma omp parallel for schedule(static) num_threads(thread_count())
    for (Eigen::Index p = 0; p < prism_count; ++p)
      for (int r = 0; r < n; ++r) carried.row(p * n + r) = table.row(p % l);
    out.simplex_attributes[name] = std::move(carried);
  }
  return out;
}

}  // namespace animanifold
