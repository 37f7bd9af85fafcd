// d-dimensional Delaunay through Qhull, and Theorem 5.2.1's facet check.
#include "animanifold/delaunay.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"

#include <Eigen/Dense>
extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <utility>
#include <vector>
#include <stdexcept>

namespace animanifold {

namespace {

// Qhull reports errors to a FILE*; collect them in memory for the exception.
class MessageStream {
 public:
  MessageStream() : file_(open_memstream(&buffer_, &size_)) {}
  ~MessageStream() {
    if (file_) std::fclose(file_);
    std::free(buffer_);
  }
  FILE* file() const { return file_; }
  std::string text() {
    if (file_) std::fflush(file_);
    return buffer_ ? std::string(buffer_, size_) : std::string();
  }

 private:
  char* buffer_ = nullptr;
  size_t size_ = 0;
  FILE* file_;
};

}  // namespace

DelaunayTriangulation delaunay(const PointMatrix& points, bool joggle) {
  const int d = static_cast<int>(points.cols());
  const Index n = static_cast<Index>(points.rows());
  if (d < 2) fail<InputError>("Delaunay triangulation needs at least 2D points, got ", d, "D");
  if (n < d + 1) fail<InputError>("Delaunay triangulation in R^", d, " needs at least ", d + 1, " points, got ", n);
  for (Index r = 0; r < n; ++r)
    for (int c = 0; c < d; ++c)
      if (!std::isfinite(points(r, c))) fail<InputError>("point ", r, " has a non-finite coordinate");

  std::vector<coordT> coordinates(points.data(), points.data() + static_cast<size_t>(n) * d);
  MessageStream errors;
  qhT storage;
  qhT* qh = &storage;
  qh_zero(qh, errors.file());
  // d: Delaunay by lifting; Qt: triangulated output; Qbb: scale the lifted
  // coordinate (precision); Qz: point at infinity, which helps with the
  // cospherical sites two parallel cross-sections produce; Qx: exact
  // pre-merges, Qhull's own default once the lifted dimension reaches 5.
  std::string options = joggle ? "qhull d QJ Qbb" : d >= 4 ? "qhull d Qt Qbb Qz Qx" : "qhull d Qt Qbb Qz";
  const int exit_code =
      qh_new_qhull(qh, d, n, coordinates.data(), False, options.data(), nullptr, errors.file());

  // Corners of each lower facet, and its signed volume measured on the points
  // Qhull actually triangulated (joggled, with 'QJ').
  std::vector<Index> corners;
  std::vector<double> facet_volumes;
  if (exit_code == 0) {
    facetT* facet;
    vertexT *vertex, **vertexp;
    Eigen::MatrixXd corner_points(d + 1, d), edges(d, d);
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      int c = 0;
      FOREACHvertex_(facet->vertices) {
        corners.push_back(static_cast<Index>(qh_pointid(qh, vertex->point)));
        if (c <= d)
          for (int k = 0; k < d; ++k) corner_points(c, k) = vertex->point[k];
        ++c;
      }
      for (int r = 0; r < d; ++r) edges.row(r) = corner_points.row(r + 1) - corner_points.row(0);
      facet_volumes.push_back(edges.determinant());
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int still_allocated = 0, total_allocated = 0;
  qh_memfreeshort(qh, &still_allocated, &total_allocated);
  if (exit_code != 0) fail<MeshingError>("Qhull failed while triangulating ", n, " points in R^", d, ": ", errors.text());

  DelaunayTriangulation out;
  const Index count = static_cast<Index>(corners.size() / (d + 1));
  SimplexMatrix all = Eigen::Map<SimplexMatrix>(corners.data(), count, d + 1);
  const Eigen::VectorXd volumes = Eigen::Map<Eigen::VectorXd>(facet_volumes.data(), count);
  // A simplex is flat when its volume is negligible next to the product of
  // the lengths of its edges from one corner (Hadamard's bound on the
  // determinant, reached by a right-angled corner): a scale-free measure,
  // also when one axis is much longer than the others (time in frames).
  std::vector<Index> keep, flat;
  keep.reserve(count);
  double factorial = 1;
  for (int i = 2; i <= d; ++i) factorial *= i;
  for (Index s = 0; s < count; ++s) {
    double product = factorial;  // volumes here are d! times the simplex volume
    for (int a = 1; a < d + 1; ++a) product *= (points.row(all(s, a)) - points.row(all(s, 0))).norm();
    const double scale = product;
    // Joggled output is proper by construction: its orientation is trusted
    // even when the simplex is a sliver of the original points.
    if (!joggle && std::abs(volumes(s)) <= 1e-12 * scale) {
      ++out.flat_simplices;
      flat.push_back(s);
      continue;
    }
    if (volumes(s) < 0) std::swap(all(s, 0), all(s, 1));
    keep.push_back(s);
  }
  out.simplices.resize(static_cast<Index>(keep.size()), d + 1);
  for (size_t r = 0; r < keep.size(); ++r) out.simplices.row(static_cast<Index>(r)) = all.row(keep[r]);
  out.flat.resize(static_cast<Index>(flat.size()), d + 1);
  for (size_t r = 0; r < flat.size(); ++r) out.flat.row(static_cast<Index>(r)) = all.row(flat[r]);
  return out;
}

IndexVector missing_facets(const SimplexMatrix& simplices, const SimplexMatrix& faces) {
  const int k = static_cast<int>(faces.cols());
  const int s = static_cast<int>(simplices.cols());
  if (k < 1 || k > s || k > 5) fail<InputError>("faces of ", k, " vertices cannot be faces of ", s, "-vertex simplices");
  using Key = std::array<Index, 5>;
  auto sorted_key = [k](auto corner) {
    Key key;
    key.fill(-1);
    for (int c = 0; c < k; ++c) key[c] = corner(c);
    std::sort(key.begin(), key.begin() + k);
    return key;
  };
  // The faces, by their sorted corners; every k-subset of every simplex is
  // looked up among them: there are far fewer faces than subsets, and a set
  // of every subset of a large 4D fill is slow to build.
  std::vector<std::pair<Key, Index>> wanted(faces.rows());
  for (Index f = 0; f < faces.rows(); ++f) wanted[f] = {sorted_key([&](int c) { return faces(f, c); }), f};
  std::sort(wanted.begin(), wanted.end());
  auto by_key = [](const std::pair<Key, Index>& entry, const Key& key) { return entry.first < key; };
  // The k-subsets of s corners, once.
  std::vector<std::array<int, 5>> subsets;
  std::vector<bool> mask(s, false);
  std::fill(mask.begin(), mask.begin() + k, true);
  do {
    std::array<int, 5> subset{};
    for (int c = 0, j = 0; c < s; ++c)
      if (mask[c]) subset[j++] = c;
    subsets.push_back(subset);
  } while (std::prev_permutation(mask.begin(), mask.end()));
  std::vector<bool> found(faces.rows(), false);
  for (Index r = 0; r < simplices.rows(); ++r)
    for (const auto& subset : subsets) {
      const Key key = sorted_key([&](int c) { return simplices(r, subset[c]); });
      for (auto it = std::lower_bound(wanted.begin(), wanted.end(), key, by_key); it != wanted.end() && it->first == key; ++it)
        found[it->second] = true;
    }
  std::vector<Index> missing;
  for (Index f = 0; f < faces.rows(); ++f)
    if (!found[f]) missing.push_back(f);
  return Eigen::Map<IndexVector>(missing.data(), static_cast<Index>(missing.size()));
}

}  // namespace animanifold
