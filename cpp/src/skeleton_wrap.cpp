// wrap (§7.6.4): enclose the input in a box or a sphere so that every input
// vertex has a bounded Voronoi cell.
#include "animanifold/errors.hpp"
#include "animanifold/skeleton.hpp"
#include "skeleton_internal.hpp"

#include <Eigen/Geometry>
#include <map>

namespace animanifold {

using namespace skeleton_detail;

WrapShape parse_wrap_shape(const std::string& name) {
  if (name.empty()) return WrapShape::None;
  return parse_name(name, kWrapShapeNames, "wrap shape");
}

namespace {

// Wrap points and faces (indices local to the wrap), oriented inward.
void make_wrap(const PointMatrix& V, WrapShape shape, int density, double margin, PointMatrix& W, SimplexMatrix& T) {
  const int D = static_cast<int>(V.cols());
  const Eigen::RowVectorXd lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  const double diag = std::max((hi - lo).norm(), 1e-12);
  const Eigen::RowVectorXd centre = 0.5 * (lo + hi);
  const double m = margin * diag;
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::array<Index, 3>> tris;
  if (D == 2) {
    std::vector<Eigen::Vector2d> ring;
    if (shape == WrapShape::Box) {
      const Eigen::Vector2d a(lo[0] - m, lo[1] - m), b(hi[0] + m, hi[1] + m);
      const Eigen::Vector2d corners[4] = {a, {a[0], b[1]}, b, {b[0], a[1]}};  // clockwise
      for (int s = 0; s < 4; ++s)
        for (int i = 0; i < density; ++i)
          ring.push_back(corners[s] + (corners[(s + 1) % 4] - corners[s]) * (double(i) / density));
    } else {
      const double r = 0.5 * diag + m;
      const int n = 4 * density;
      for (int i = 0; i < n; ++i) {
        const double t = -2 * M_PI * i / n;  // clockwise
        ring.emplace_back(centre[0] + r * std::cos(t), centre[1] + r * std::sin(t));
      }
    }
    const Index n = static_cast<Index>(ring.size());
    W.resize(n, 2);
    T.resize(n, 2);
    for (Index i = 0; i < n; ++i) {
      W.row(i) = ring[i].transpose();
      T(i, 0) = i;
      T(i, 1) = (i + 1) % n;
    }
    return;
  }
  const Eigen::Vector3d c3(centre[0], centre[1], centre[2]);
  if (shape == WrapShape::Box) {
    const Eigen::Vector3d a = Eigen::Vector3d(lo[0], lo[1], lo[2]) - Eigen::Vector3d::Constant(m);
    const Eigen::Vector3d b = Eigen::Vector3d(hi[0], hi[1], hi[2]) + Eigen::Vector3d::Constant(m);
    std::map<std::array<int, 3>, Index> id;
    auto vertex = [&](std::array<int, 3> ijk) {
      auto [it, fresh] = id.emplace(ijk, static_cast<Index>(pts.size()));
      if (fresh) {
        Eigen::Vector3d p;
        for (int k = 0; k < 3; ++k) p[k] = a[k] + (b[k] - a[k]) * ijk[k] / density;
        pts.push_back(p);
      }
      return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {0, density}) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int i = 0; i < density; ++i)
          for (int j = 0; j < density; ++j) {
            std::array<int, 3> q[4];
            const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
            for (int k = 0; k < 4; ++k) {
              q[k][axis] = side;
              q[k][u] = i + di[k];
              q[k][v] = j + dj[k];
            }
            const Index ids[4] = {vertex(q[0]), vertex(q[1]), vertex(q[2]), vertex(q[3])};
            tris.push_back({ids[0], ids[1], ids[2]});
            tris.push_back({ids[0], ids[2], ids[3]});
          }
      }
  } else {
    const int n = 6 * density * density + 2;
    const double r = 0.5 * diag + m;
    const double golden = M_PI * (3 - std::sqrt(5.0));
    PointMatrix S(n, 3);
    for (int i = 0; i < n; ++i) {
      const double z = 1 - 2 * (i + 0.5) / n, rho = std::sqrt(1 - z * z), t = golden * i;
      pts.push_back(c3 + r * Eigen::Vector3d(rho * std::cos(t), rho * std::sin(t), z));
      S.row(i) = pts.back().transpose();
    }
    const Hull hull = qhull_convex_hull(S);
    for (Index h = 0; h < hull.facets.rows(); ++h) tris.push_back({hull.facets(h, 0), hull.facets(h, 1), hull.facets(h, 2)});
  }
  W.resize(static_cast<Index>(pts.size()), 3);
  for (size_t i = 0; i < pts.size(); ++i) W.row(static_cast<Index>(i)) = pts[i].transpose();
  T.resize(static_cast<Index>(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) {
    auto f = tris[t];
    const Eigen::Vector3d &p = pts[f[0]], &q = pts[f[1]], &s = pts[f[2]];
    // Inward: the normal points towards the centre.
    if ((q - p).cross(s - p).dot(c3 - (p + q + s) / 3) < 0) std::swap(f[1], f[2]);
    for (int k = 0; k < 3; ++k) T(static_cast<Index>(t), k) = f[k];
  }
}

}  // namespace

WrapResult wrap(const PointMatrix& V, const SimplexMatrix& F, WrapShape shape, int density, double margin) {
  check_closed_oriented(V, F);
  if (density < 1) fail<InputError>("wrap density must be >= 1, got ", density);
  if (!(margin > 0)) fail<InputError>("wrap margin must be > 0, got ", margin);
  WrapResult out;
  out.input_vertices = static_cast<Index>(V.rows());
  out.input_faces = static_cast<Index>(F.rows());
  if (shape == WrapShape::None) {
    out.vertices = V;
    out.faces = F;
    return out;
  }
  PointMatrix W;
  SimplexMatrix T;
  make_wrap(V, shape, density, margin, W, T);
  out.vertices.resize(V.rows() + W.rows(), V.cols());
  out.vertices << V, W;
  out.faces.resize(F.rows() + T.rows(), F.cols());
  out.faces << F, (T.array() + static_cast<Index>(V.rows())).matrix();
  return out;
}

// Used by the extraction: the wrap's points only.
namespace skeleton_detail {
PointMatrix wrap_points(const PointMatrix& V, WrapShape shape, int density, double margin) {
  if (shape == WrapShape::None) return PointMatrix(0, V.cols());
  PointMatrix W;
  SimplexMatrix T;
  make_wrap(V, shape, density, margin, W, T);
  return W;
}
}  // namespace skeleton_detail

}  // namespace animanifold
