// Bounded bisector polygons of a Voronoi diagram, read off its dual Delaunay
// triangulation: the bisector of sites a and b is dual to the Delaunay edge
// ab, and its corners are the Voronoi vertices of the simplices around that
// edge, in the order the simplices turn around it.
#include "skeleton_internal.hpp"

#include <tuple>
#include <utility>

namespace animanifold::skeleton_detail {

namespace {

// A Delaunay simplex t around the edge (a, b), a < b; in 3D c and d are the
// tetrahedron's other two vertices, which it shares with its neighbours
// around the edge.
struct EdgeIncidence {
  Index a, b, c, d, t;
};

void sort_by_edge(std::vector<EdgeIncidence>& incidences) {
  std::sort(incidences.begin(), incidences.end(), [](const EdgeIncidence& x, const EdgeIncidence& y) {
    return std::tie(x.a, x.b, x.t) < std::tie(y.a, y.b, y.t);
  });
}

// End of the run of incidences of the same edge as incidences[i].
size_t edge_run_end(const std::vector<EdgeIncidence>& incidences, size_t i) {
  size_t j = i;
  while (j < incidences.size() && incidences[j].a == incidences[i].a && incidences[j].b == incidences[i].b) ++j;
  return j;
}

// 2D: a Delaunay edge between two triangles is dual to a bounded Voronoi edge.
void add_polygons_2d(const Delaunay& del, Index n, BisectorPolygons& out) {
  const Index T = static_cast<Index>(del.simplices.rows());
  std::vector<EdgeIncidence> incidences;
  incidences.reserve(static_cast<size_t>(T) * 3);
  for (Index t = 0; t < T; ++t)
    for (int k = 0; k < 3; ++k) {
      Index a = del.simplices(t, k), b = del.simplices(t, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      if (b < n) incidences.push_back({a, b, -1, -1, t});
    }
  sort_by_edge(incidences);
  for (size_t i = 0; i < incidences.size();) {
    const size_t j = edge_run_end(incidences, i);
    if (j - i == 2) {
      const Index c0 = del.center[incidences[i].t], c1 = del.center[incidences[i + 1].t];
      if (c0 != c1) out.add(incidences[i].a, incidences[i].b, {c0, c1}, {});
    }
    i = j;
  }
}

// The tetrahedra around one edge in turning order (ring) with the link
// vertex each shares with the next (link); false when they do not close up.
// Scratch buffers are kept between edges.
class RingWalker {
 public:
  bool walk(const EdgeIncidence* around, size_t m, std::vector<Index>& ring, std::vector<Index>& link) {
    ring.clear();
    link.clear();
    if (m < 3) return false;
    return m <= 12 ? walk_by_search(around, m, ring, link) : walk_by_pairing(around, m, ring, link);
  }

 private:
  // Small rings: look for the next tetrahedron among the unused ones.
  bool walk_by_search(const EdgeIncidence* around, size_t m, std::vector<Index>& ring, std::vector<Index>& link) {
    used_.assign(m, 0);
    bool closed = true;
    size_t cur = 0;
    Index from = around[0].c, to = around[0].d;
    used_[0] = 1;
    ring.push_back(around[0].t);
    for (size_t step = 1; step < m; ++step) {
      size_t found = m;
      for (size_t k = 0; k < m; ++k)
        if (!used_[k] && (around[k].c == to || around[k].d == to)) {
          found = k;
          break;
        }
      if (found == m) {
        closed = false;
        break;
      }
      link.push_back(to);
      used_[found] = 1;
      cur = found;
      to = around[cur].c == to ? around[cur].d : around[cur].c;
      ring.push_back(around[cur].t);
    }
    if (closed && to != from) closed = false;
    link.push_back(from);
    return closed;
  }

  // Large rings (near-cospherical input): pair the tetrahedra through their
  // link vertices, each of which must be shared by exactly two.
  bool walk_by_pairing(const EdgeIncidence* around, size_t m, std::vector<Index>& ring, std::vector<Index>& link) {
    occurrences_.clear();
    for (size_t k = 0; k < m; ++k) {
      occurrences_.push_back({around[k].c, static_cast<Index>(k)});
      occurrences_.push_back({around[k].d, static_cast<Index>(k)});
    }
    std::sort(occurrences_.begin(), occurrences_.end());
    partner_.assign(2 * m, -1);  // partner_[2k + s]: the other tetrahedron sharing link vertex s of k
    for (size_t o = 0; o < occurrences_.size(); o += 2) {
      if (o + 1 >= occurrences_.size() || occurrences_[o].first != occurrences_[o + 1].first ||
          (o + 2 < occurrences_.size() && occurrences_[o + 2].first == occurrences_[o].first))
        return false;
      const Index k0 = occurrences_[o].second, k1 = occurrences_[o + 1].second;
      const Index v = occurrences_[o].first;
      partner_[2 * k0 + (around[k0].c == v ? 0 : 1)] = k1;
      partner_[2 * k1 + (around[k1].c == v ? 0 : 1)] = k0;
    }
    Index k = 0, to = around[0].d;
    for (size_t step = 0; step < m; ++step) {
      ring.push_back(around[k].t);
      link.push_back(to);
      const Index next = partner_[2 * k + (around[k].c == to ? 0 : 1)];
      to = around[next].c == to ? around[next].d : around[next].c;
      k = next;
    }
    return k == 0;
  }

  std::vector<char> used_;
  std::vector<std::pair<Index, Index>> occurrences_;
  std::vector<Index> partner_;
};

// The ring's Voronoi vertices with consecutive duplicates (triangulated
// pieces of one cospherical region) merged, each keeping the link of its last piece.
void merge_cospherical(const IndexVector& center, const std::vector<Index>& ring, const std::vector<Index>& link,
                       std::vector<Index>& corners, std::vector<Index>& links) {
  corners.clear();
  links.clear();
  for (size_t k = 0; k < ring.size(); ++k) {
    const Index c = center[ring[k]];
    if (!corners.empty() && corners.back() == c) {
      links.back() = link[k];
      continue;
    }
    corners.push_back(c);
    links.push_back(link[k]);
  }
  while (corners.size() > 1 && corners.front() == corners.back()) {
    corners.pop_back();
    links.pop_back();
  }
}

// 3D: a Delaunay edge whose tetrahedra close up around it is dual to a
// bounded Voronoi polygon.
void add_polygons_3d(const Delaunay& del, Index n, BisectorPolygons& out) {
  const Index T = static_cast<Index>(del.simplices.rows());
  std::vector<EdgeIncidence> incidences;
  incidences.reserve(static_cast<size_t>(T) * 6);
  static constexpr int pairs[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                      {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  for (Index t = 0; t < T; ++t)
    for (const auto& pr : pairs) {
      Index a = del.simplices(t, pr[0]), b = del.simplices(t, pr[1]);
      if (a > b) std::swap(a, b);
      if (b < n) incidences.push_back({a, b, del.simplices(t, pr[2]), del.simplices(t, pr[3]), t});
    }
  sort_by_edge(incidences);
  RingWalker walker;
  std::vector<Index> ring, link, corners, links;
  for (size_t i = 0; i < incidences.size();) {
    const size_t j = edge_run_end(incidences, i);
    if (walker.walk(incidences.data() + i, j - i, ring, link)) {
      merge_cospherical(del.center, ring, link, corners, links);
      if (corners.size() >= 3) out.add(incidences[i].a, incidences[i].b, corners, links);
    }
    i = j;
  }
}

}  // namespace

void BisectorPolygons::add(Index site_a, Index site_b, const std::vector<Index>& corners,
                           const std::vector<Index>& links) {
  a.push_back(site_a);
  b.push_back(site_b);
  ring.insert(ring.end(), corners.begin(), corners.end());
  if (links.empty()) link.insert(link.end(), corners.size(), -1);
  else link.insert(link.end(), links.begin(), links.end());
  start.push_back(static_cast<Index>(ring.size()));
}

BisectorPolygons bisector_polygons(const Delaunay& del, Index n) {
  BisectorPolygons out;
  if (del.simplices.cols() == 3) add_polygons_2d(del, n, out);
  else add_polygons_3d(del, n, out);
  return out;
}

VoronoiEdgeGraph voronoi_edge_graph(const BisectorPolygons& polygons, size_t centre_count) {
  VoronoiEdgeGraph graph;
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(2 * polygons.ring.size());
  graph.site.assign(centre_count, -1);
  for (size_t k = 0; k < polygons.size(); ++k) {
    const Index s0 = polygons.start[k], s1 = polygons.start[k + 1], m = s1 - s0;
    for (Index i = 0; i < m; ++i) {
      const Index u = polygons.ring[s0 + i], v = polygons.ring[s0 + (i + 1) % m];
      if (graph.site[u] < 0) graph.site[u] = polygons.a[k];
      if (m == 2 && i == 1) break;  // a 2D polygon is one edge, not a cycle
      if (u == v) continue;
      pairs.emplace_back(u, v);
      pairs.emplace_back(v, u);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  graph.first.assign(centre_count + 1, 0);
  for (const auto& pr : pairs) ++graph.first[pr.first + 1];
  for (size_t c = 0; c < centre_count; ++c) graph.first[c + 1] += graph.first[c];
  graph.neighbour.reserve(pairs.size());
  for (const auto& pr : pairs) graph.neighbour.push_back(pr.second);
  return graph;
}

}  // namespace animanifold::skeleton_detail
