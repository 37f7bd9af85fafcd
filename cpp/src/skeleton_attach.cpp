// §8.6.2: attaching to the skeleton the mesh vertices whose Voronoi cell
// meets it only in an edge or a vertex (they are the site of no kept
// polygon), so that every mesh vertex is joined to the skeleton.
#include "skeleton_internal.hpp"

namespace animanifold::skeleton_detail {

namespace {

using Simplices = std::vector<std::array<Index, 3>>;

// 3D edge contacts: triangles (vertex, skeleton edge) from the Voronoi edges
// of kept polygons whose link vertex is not a site. Marks the vertices attached.
void attach_to_edges(Index n, const SkeletonAssembly& assembly, const Simplices& edge_candidates,
                     std::vector<char>& has_edge, Simplices& attach) {
  const auto& centre_out = assembly.centre_vertex();
  const auto& is_site = assembly.is_site();
  for (const auto& e : edge_candidates) {
    const Index v = e[0], u = centre_out[e[1]], w = centre_out[e[2]];
    if (is_site[v] || u < 0 || w < 0 || u == w) continue;
    attach.push_back({v, n + u, n + w});
    has_edge[v] = 1;
  }
}

// 3D vertex-only contacts: the skeleton vertices among the Voronoi vertices
// of each vertex's Delaunay tetrahedra, sorted, per vertex not otherwise attached.
std::vector<std::vector<Index>> vertex_contacts(const Delaunay& del, Index n, const SkeletonAssembly& assembly,
                                                const std::vector<char>& has_edge) {
  const auto& centre_out = assembly.centre_vertex();
  const auto& is_site = assembly.is_site();
  std::vector<std::vector<Index>> contact(static_cast<size_t>(n));
  for (Index t = 0; t < del.simplices.rows(); ++t) {
    const Index c = centre_out[del.center[t]];
    if (c < 0) continue;
    for (int k = 0; k < 4; ++k) {
      const Index v = del.simplices(t, k);
      if (v < n && !is_site[v] && !has_edge[v]) contact[v].push_back(c);
    }
  }
  for (auto& cv : contact) {
    std::sort(cv.begin(), cv.end());
    cv.erase(std::unique(cv.begin(), cv.end()), cv.end());
  }
  return contact;
}

// 3D: triangles (vertex, mesh neighbour, skeleton vertex), paired with a
// neighbour touching the same skeleton vertex (emitted once for the pair),
// else with any neighbour.
void attach_to_vertices(Index n, const std::vector<std::vector<Index>>& contact,
                        const std::vector<std::vector<Index>>& neighbours, Simplices& attach) {
  for (Index v = 0; v < n; ++v)
    for (Index c : contact[v]) {
      Index partner = -1;
      for (Index w : neighbours[v])
        if (std::binary_search(contact[w].begin(), contact[w].end(), c)) {
          partner = w;
          break;
        }
      if (partner >= 0 && partner < v) continue;  // emitted from the partner's side
      if (partner < 0) partner = neighbours[v].front();
      attach.push_back({v, partner, n + c});
    }
}

// 2D: segments from each non-site vertex to the skeleton vertices of its Delaunay triangles.
void attach_2d(const Delaunay& del, Index n, const SkeletonAssembly& assembly, Simplices& attach) {
  const auto& centre_out = assembly.centre_vertex();
  const auto& is_site = assembly.is_site();
  for (Index t = 0; t < del.simplices.rows(); ++t) {
    const Index c = centre_out[del.center[t]];
    if (c < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const Index v = del.simplices(t, k);
      if (v < n && !is_site[v]) attach.push_back({v, n + c, -1});
    }
  }
  std::sort(attach.begin(), attach.end());
  attach.erase(std::unique(attach.begin(), attach.end()), attach.end());
}

}  // namespace

SimplexMatrix attachment_simplices(const Delaunay& del, Index n, int D, const SkeletonAssembly& assembly,
                                   const std::vector<std::vector<Index>>& neighbours,
                                   const std::vector<std::array<Index, 3>>& edge_candidates) {
  Simplices attach;
  if (D == 3) {
    std::vector<char> has_edge(static_cast<size_t>(n), 0);
    attach_to_edges(n, assembly, edge_candidates, has_edge, attach);
    attach_to_vertices(n, vertex_contacts(del, n, assembly, has_edge), neighbours, attach);
  } else {
    attach_2d(del, n, assembly, attach);
  }
  SimplexMatrix out(static_cast<Index>(attach.size()), D);
  for (size_t r = 0; r < attach.size(); ++r)
    for (int k = 0; k < D; ++k) out(static_cast<Index>(r), k) = attach[r][k];
  return out;
}

}  // namespace animanifold::skeleton_detail
