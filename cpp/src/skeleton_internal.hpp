// Internal pieces shared by the skeleton_*.cpp files (not a public header).
#pragma once

#include "animanifold/skeleton.hpp"
#include "animanifold/types.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace animanifold::skeleton_detail {

using Vec3 = Eigen::Vector3d;

// Points as 3-vectors (z = 0 for R^2 input).
std::vector<Vec3> to_vec3(const PointMatrix& V);

// ---- Qhull (skeleton_voronoi.cpp) -------------------------------------------

// Delaunay triangulation of `P` (#P by d, d = 2 or 3) by Qhull ("v Qbb Qt Qz")
// with the Voronoi vertex of every simplex. Triangulated pieces of one
// cospherical region share one Voronoi vertex, so `center` ids are welded.
struct Delaunay {
  SimplexMatrix simplices;  // #T by d+1 point indices
  IndexVector center;       // #T: row of `centers`
  PointMatrix centers;      // #C by d Voronoi vertices
};
Delaunay qhull_delaunay(const PointMatrix& P);

// Convex hull facets by Qhull ("Qt"): outward unit normals and offsets, so
// that a point x is inside when normal·x + offset <= 0 for every facet.
struct Hull {
  PointMatrix normals;       // #H by d
  Eigen::VectorXd offsets;   // #H
  SimplexMatrix facets;      // #H by d point indices (orientation not fixed)
};
Hull qhull_convex_hull(const PointMatrix& P);

// The wrap's points alone (skeleton_wrap.cpp); empty for WrapShape::None.
PointMatrix wrap_points(const PointMatrix& V, WrapShape shape, int density, double margin);

// ---- uniform grid over points (skeleton_separability.cpp) -------------------

class PointGrid {
 public:
  PointGrid(const std::vector<Vec3>& points, double cell);
  // Calls visit(index) for every point whose cell overlaps the box [lo, hi].
  template <class Visit>
  void query(const Vec3& lo, const Vec3& hi, Visit visit) const {
    std::array<long, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = std::clamp<long>(static_cast<long>(std::floor((lo[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
      b[k] = std::clamp<long>(static_cast<long>(std::floor((hi[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
      if (hi[k] < origin_[k] || lo[k] > origin_[k] + cell_ * dims_[k]) return;
    }
    for (long z = a[2]; z <= b[2]; ++z)
      for (long y = a[1]; y <= b[1]; ++y)
        for (long x = a[0]; x <= b[0]; ++x) {
          const long c = (z * dims_[1] + y) * dims_[0] + x;
          for (Index i = start_[c]; i < start_[c + 1]; ++i) visit(items_[i]);
        }
  }

 private:
  Vec3 origin_;
  double cell_;
  std::array<long, 3> dims_;
  std::vector<Index> start_, items_;
};

// ---- surface helpers --------------------------------------------------------

// Unique undirected edges of a triangle mesh with their two faces and the
// vertices opposite them (the mesh is closed and manifold).
struct EdgeTable {
  std::vector<std::array<Index, 2>> edge;      // a < b
  std::vector<std::array<Index, 2>> opposite;  // apex of each incident face
  std::vector<std::array<Index, 3>> face_edges;  // per face: edges (v0v1, v1v2, v2v0)
};
EdgeTable edge_table(const SimplexMatrix& F);

// Sorted neighbour lists of every vertex along mesh edges (segments or triangle edges).
std::vector<std::vector<Index>> vertex_neighbours(const SimplexMatrix& F, Index vertex_count);

}  // namespace animanifold::skeleton_detail
