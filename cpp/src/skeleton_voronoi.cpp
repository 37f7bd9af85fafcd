// Qhull (reentrant libqhull_r) wrappers for the Voronoi skeleton: the Delaunay
// triangulation with its Voronoi vertices, and the convex hull's facets.
#include "skeleton_internal.hpp"

#include "animanifold/errors.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace animanifold::skeleton_detail {

std::vector<Vec3> to_vec3(const PointMatrix& V) {
  std::vector<Vec3> out(static_cast<size_t>(V.rows()), Vec3::Zero());
  for (Index i = 0; i < V.rows(); ++i)
    for (int c = 0; c < std::min<int>(3, static_cast<int>(V.cols())); ++c) out[i][c] = V(i, c);
  return out;
}

namespace {

// One Qhull run: owns the qhT state and the error stream, frees both.
class QhullRun {
 public:
  QhullRun(const PointMatrix& P, const char* options) : points_(P.data(), P.data() + P.size()) {
    errors_ = open_memstream(&error_text_, &error_size_);
    qh_zero(&qh_, errors_);
    const int dim = static_cast<int>(P.cols());
    std::string flags = std::string("qhull ") + options;
    exitcode_ = qh_new_qhull(&qh_, dim, static_cast<int>(P.rows()), points_.data(), False, flags.data(), nullptr,
                             errors_);
  }
  ~QhullRun() {
    qh_freeqhull(&qh_, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(&qh_, &curlong, &totlong);
    if (errors_) std::fclose(errors_);
    std::free(error_text_);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;

  qhT* qh() { return &qh_; }
  void check(const char* what) {
    if (exitcode_ == 0) return;
    std::fflush(errors_);
    std::string text = error_text_ ? std::string(error_text_, error_size_) : std::string();
    if (text.size() > 600) text.resize(600);
    throw MeshingError(std::string("Qhull failed to compute the ") + what + " (exit code " +
                             std::to_string(exitcode_) + "): " + text);
  }

 private:
  qhT qh_;
  std::vector<coordT> points_;
  FILE* errors_ = nullptr;
  char* error_text_ = nullptr;
  size_t error_size_ = 0;
  int exitcode_ = 0;
};

}  // namespace

Delaunay qhull_delaunay(const PointMatrix& P) {
  const int d = static_cast<int>(P.cols());
  if (P.rows() < d + 2) fail<InputError>("a Voronoi diagram in R^", d, " needs at least ", d + 2, " points, got ",
                                         P.rows());
  QhullRun run(P, "v Qbb Qt Qz");
  run.check("Delaunay triangulation");
  qhT* qh = run.qh();
  qh_setvoronoi_all(qh);

  std::vector<Index> simplices;
  std::vector<Index> center_of;
  std::vector<double> centers;
  std::unordered_map<const coordT*, Index> center_id;
  facetT* facet;
  vertexT *vertex, **vertexp;
  FORALLfacets {
    if (facet->upperdelaunay) continue;
    if (!facet->center) facet->center = qh_facetcenter(qh, facet->vertices);
    int count = 0;
    FOREACHvertex_(facet->vertices) {
      simplices.push_back(static_cast<Index>(qh_pointid(qh, vertex->point)));
      ++count;
    }
    if (count != d + 1) throw MeshingError("Qhull returned a non-simplicial Delaunay facet despite 'Qt'");
    auto [it, inserted] = center_id.emplace(facet->center, static_cast<Index>(centers.size() / d));
    if (inserted)
      for (int c = 0; c < d; ++c) centers.push_back(facet->center[c]);
    center_of.push_back(it->second);
  }
  Delaunay out;
  const Index T = static_cast<Index>(center_of.size());
  out.simplices.resize(T, d + 1);
  std::copy(simplices.begin(), simplices.end(), out.simplices.data());
  out.center = Eigen::Map<IndexVector>(center_of.data(), T);
  out.centers.resize(static_cast<Index>(centers.size() / d), d);
  std::copy(centers.begin(), centers.end(), out.centers.data());
  for (Index t = 0; t < T; ++t)
    for (int c = 0; c <= d; ++c)
      if (out.simplices(t, c) < 0 || out.simplices(t, c) >= P.rows())
        throw MeshingError("Qhull returned a Delaunay simplex with an unknown point");
  return out;
}

Hull qhull_convex_hull(const PointMatrix& P) {
  const int d = static_cast<int>(P.cols());
  QhullRun run(P, "Qt");
  run.check("convex hull");
  qhT* qh = run.qh();
  std::vector<double> normals, offsets;
  std::vector<Index> facets;
  facetT* facet;
  vertexT *vertex, **vertexp;
  FORALLfacets {
    for (int c = 0; c < d; ++c) normals.push_back(facet->normal[c]);
    offsets.push_back(facet->offset);
    int count = 0;
    FOREACHvertex_(facet->vertices) {
      if (count < d) facets.push_back(static_cast<Index>(qh_pointid(qh, vertex->point)));
      ++count;
    }
    if (count != d) throw MeshingError("Qhull returned a non-simplicial hull facet despite 'Qt'");
  }
  Hull hull;
  hull.normals.resize(static_cast<Index>(offsets.size()), d);
  std::copy(normals.begin(), normals.end(), hull.normals.data());
  hull.offsets = Eigen::Map<Eigen::VectorXd>(offsets.data(), static_cast<Index>(offsets.size()));
  hull.facets.resize(static_cast<Index>(offsets.size()), d);
  std::copy(facets.begin(), facets.end(), hull.facets.data());
  return hull;
}

}  // namespace animanifold::skeleton_detail
