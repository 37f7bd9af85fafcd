// Internal pieces shared by the skeleton_*.cpp files (not a public header).
#pragma once

#include "animanifold/skeleton.hpp"
#include "animanifold/types.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
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

// ---- bisector polygons (skeleton_bisectors.cpp) -----------------------------

// The bounded bisector polygons b_ab between mesh vertices a < b < n, read
// off the Delaunay triangulation: polygon k has sites a[k], b[k] and corners
// ring[start[k] .. start[k + 1]) (Voronoi vertices, rows of
// Delaunay::centers) in cyclic order; two corners in 2D. link holds, per
// polygon edge i -> i + 1, the Delaunay vertex dual to it (3D; -1 in 2D).
struct BisectorPolygons {
  std::vector<Index> a, b, start{0}, ring, link;
  size_t size() const { return a.size(); }
  std::vector<Index> corners(size_t k) const { return {ring.begin() + start[k], ring.begin() + start[k + 1]}; }
  std::vector<Index> links(size_t k) const { return {link.begin() + start[k], link.begin() + start[k + 1]}; }
  void add(Index site_a, Index site_b, const std::vector<Index>& corners, const std::vector<Index>& links);
};
// `n` is the number of mesh vertices: the first n Delaunay points.
BisectorPolygons bisector_polygons(const Delaunay& del, Index n);

// The Voronoi edges of the polygons as an undirected graph over Voronoi
// vertices (compressed rows: the neighbours of u are
// neighbour[first[u] .. first[u + 1])), and per Voronoi vertex the first
// site of a polygon it is a corner of (-1 for a vertex of no polygon).
struct VoronoiEdgeGraph {
  std::vector<Index> first, neighbour, site;
};
VoronoiEdgeGraph voronoi_edge_graph(const BisectorPolygons& polygons, size_t centre_count);

// ---- welded output (skeleton_weld.cpp) ---------------------------------------

// A polygon corner during clipping: its position, how it is keyed for
// welding, and the carrier of the edge leaving it (a Voronoi edge u-v, or -1
// for an edge cut along a hull plane).
struct Corner {
  Vec3 p;
  std::array<Index, 3> key;  // {center, -1, -1}, {u, v, plane} or {-2, serial, 0}
  std::array<Index, 2> carrier;
};

// The skeleton being assembled: corners welded by key (one vertex per
// Voronoi vertex and per Voronoi edge cut by a hull plane; cuts of hull-cut
// edges are never shared), faces with their side, sites and polygon.
class SkeletonAssembly {
 public:
  SkeletonAssembly(size_t centre_count, Index site_count);
  // The output vertex of a corner; `on_mesh` is recorded when it is new.
  Index vertex(const Corner& c, bool on_mesh);
  const Vec3& position(Index v) const { return vertices_[v]; }
  // A new polygon between sites a and b: its id.
  Index begin_polygon(Index a, Index b);
  void add_face(const std::array<Index, 3>& face, bool inside, Index a, Index b, Index polygon);
  // Drops vertices no face uses (corners of polygons that collapsed when welded).
  void drop_unused(int D);
  void write(VoronoiSkeleton& out, int D) const;
  // Per Voronoi vertex: its output vertex, or -1.
  const std::vector<Index>& centre_vertex() const { return centre_out_; }
  // Per mesh vertex: whether a kept polygon has it as a site.
  const std::vector<char>& is_site() const { return is_site_; }

 private:
  std::vector<Index> centre_out_;
  std::map<std::array<Index, 3>, Index> cut_out_;
  std::vector<Vec3> vertices_;
  std::vector<Index> on_mesh_;
  std::vector<std::array<Index, 3>> faces_;
  std::vector<Index> side_, polygon_;
  std::vector<std::array<Index, 2>> sites_;
  std::vector<char> is_site_;
  Index polygon_count_ = 0;
};

// ---- attachment (skeleton_attach.cpp) ----------------------------------------

// §8.6.2: simplices attaching the mesh vertices whose Voronoi cell meets the
// skeleton only in an edge or a vertex, over [mesh vertices; skeleton
// vertices] (see VoronoiSkeleton::attachment). `edge_candidates` holds the
// Voronoi edges of kept polygons as (link vertex, centre, centre) (3D).
SimplexMatrix attachment_simplices(const Delaunay& del, Index n, int D, const SkeletonAssembly& assembly,
                                   const std::vector<std::vector<Index>>& neighbours,
                                   const std::vector<std::array<Index, 3>>& edge_candidates);

}  // namespace animanifold::skeleton_detail
