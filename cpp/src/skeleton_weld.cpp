// The skeleton's output assembly: polygon corners welded into shared
// vertices so that neighbouring bisector polygons form one complex.
#include "skeleton_internal.hpp"

namespace animanifold::skeleton_detail {

SkeletonAssembly::SkeletonAssembly(size_t centre_count, Index site_count)
    : centre_out_(centre_count, -1), is_site_(static_cast<size_t>(site_count), 0) {}

Index SkeletonAssembly::vertex(const Corner& c, bool on_mesh) {
  if (c.key[1] == -1) {  // a Voronoi vertex
    Index& slot = centre_out_[c.key[0]];
    if (slot < 0) {
      slot = static_cast<Index>(vertices_.size());
      vertices_.push_back(c.p);
      on_mesh_.push_back(on_mesh ? 1 : 0);
    }
    return slot;
  }
  if (c.key[0] == -2) {  // a cut of an edge an earlier hull plane made: no other polygon has it
    vertices_.push_back(c.p);
    on_mesh_.push_back(0);
    return static_cast<Index>(vertices_.size() - 1);
  }
  auto [it, fresh] = cut_out_.emplace(c.key, static_cast<Index>(vertices_.size()));
  if (fresh) {
    vertices_.push_back(c.p);
    on_mesh_.push_back(0);
  }
  return it->second;
}

Index SkeletonAssembly::begin_polygon(Index a, Index b) {
  is_site_[a] = is_site_[b] = 1;
  return polygon_count_++;
}

void SkeletonAssembly::add_face(const std::array<Index, 3>& face, bool inside, Index a, Index b, Index polygon) {
  faces_.push_back(face);
  side_.push_back(inside ? 0 : 1);
  sites_.push_back({a, b});
  polygon_.push_back(polygon);
}

void SkeletonAssembly::drop_unused(int D) {
  std::vector<char> used(vertices_.size(), 0);
  for (const auto& t : faces_)
    for (int k = 0; k < D; ++k) used[t[k]] = 1;
  std::vector<Index> remap(vertices_.size(), -1);
  Index kept = 0;
  for (size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      remap[v] = kept;
      vertices_[kept] = vertices_[v];
      on_mesh_[kept] = on_mesh_[v];
      ++kept;
    }
  vertices_.resize(static_cast<size_t>(kept));
  on_mesh_.resize(static_cast<size_t>(kept));
  for (auto& t : faces_)
    for (int k = 0; k < D; ++k) t[k] = remap[t[k]];
  for (auto& c : centre_out_)
    if (c >= 0) c = remap[c];
}

void SkeletonAssembly::write(VoronoiSkeleton& out, int D) const {
  const Index S = static_cast<Index>(vertices_.size());
  out.vertices.resize(S, D);
  out.on_mesh.resize(S);
  for (Index s = 0; s < S; ++s) {
    for (int k = 0; k < D; ++k) out.vertices(s, k) = vertices_[s][k];
    out.on_mesh[s] = on_mesh_[s];
  }
  const Index Fo = static_cast<Index>(faces_.size());
  out.faces.resize(Fo, D);
  out.side.resize(Fo);
  out.sites.resize(Fo, 2);
  out.polygon.resize(Fo);
  for (Index f = 0; f < Fo; ++f) {
    for (int k = 0; k < D; ++k) out.faces(f, k) = faces_[f][k];
    out.side[f] = side_[f];
    out.sites(f, 0) = sites_[f][0];
    out.sites(f, 1) = sites_[f][1];
    out.polygon[f] = polygon_[f];
  }
}

}  // namespace animanifold::skeleton_detail
