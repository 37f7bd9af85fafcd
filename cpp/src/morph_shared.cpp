// Prisms of the fill over cells that the source and the target share and
// that lie outside both (see morph_skeleton.hpp).
#include "morph_skeleton.hpp"
#include "simplex_key.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace animanifold {

namespace {

using Key = SimplexKey<4>;  // the corners of a cell (n + 1 <= 4)
using KeyHash = SimplexKeyHash;

struct PositionHash {
  size_t operator()(const std::array<std::uint64_t, 3>& p) const {
    return static_cast<size_t>((p[0] * 0x9e3779b97f4a7c15ull) ^ (p[1] * 0xbf58476d1ce4e5b9ull) ^ (p[2] * 0x94d049bb133111ebull));
  }
};

std::unordered_set<Key, KeyHash> outside_keys(const PlaneCells& plane) {
  std::unordered_set<Key, KeyHash> keys;
  for (Index c = 0; c < plane.cells.rows(); ++c) {
    if (!plane.outside[c] || plane.flat[c]) continue;
    keys.insert(simplex_key<4>(plane.cells.row(c).data(), static_cast<int>(plane.cells.cols())));
  }
  return keys;
}

}  // namespace

std::vector<Prism> shared_prisms(const PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& in_source,
                                        const std::vector<bool>& in_target, const PlaneCells& source_plane,
                                        const PlaneCells& target_plane) {
  const int n = static_cast<int>(P.cols()) - 1;
  std::vector<Prism> prism(A.rows(), Prism::NotShared);
  // Each target vertex's twin: the source vertex at the same place, bit for bit.
  auto bits = [&](Index v) {
    std::array<std::uint64_t, 3> b{0, 0, 0};
    for (int c = 0; c < n; ++c) {
      const double x = P(v, c) + 0.0;
      std::memcpy(&b[c], &x, sizeof x);
    }
    return b;
  };
  std::unordered_map<std::array<std::uint64_t, 3>, Index, PositionHash> source_at;
  for (Index v = 0; v < P.rows(); ++v)
    if (in_source[v]) source_at.emplace(bits(v), v);
  std::vector<Index> twin(P.rows(), -1);  // target vertex -> source vertex
  bool any = false;
  for (Index v = 0; v < P.rows(); ++v)
    if (in_target[v])
      if (const auto it = source_at.find(bits(v)); it != source_at.end()) twin[v] = it->second, any = true;
  if (!any) return prism;
  const auto source_outside = outside_keys(source_plane), target_outside = outside_keys(target_plane);
  std::unordered_map<Index, Index> target_of;  // source vertex -> its target twin
  for (Index v = 0; v < P.rows(); ++v)
    if (twin[v] >= 0) target_of.emplace(twin[v], v);
  for (Index s = 0; s < A.rows(); ++s) {
    Key at_source{-1, -1, -1, -1};  // the simplex's places, named by their source vertices
    int places = 0;
    bool shared = true;
    for (int c = 0; c < n + 2 && shared; ++c) {
      const Index v = A(s, c);
      const Index place = in_source[v] ? v : (in_target[v] ? twin[v] : -1);
      if (place < 0 || (in_source[v] && !target_of.count(v))) {
        shared = false;  // a vertex off the planes, or without a twin in the other plane
        break;
      }
      if (std::find(at_source.begin(), at_source.begin() + places, place) == at_source.begin() + places) {
        if (places == n + 1) {
          shared = false;
          break;
        }
        at_source[places++] = place;
      }
    }
    if (!shared || places != n + 1) continue;  // not in one prism (n + 1 places, every place a column)
    std::sort(at_source.begin(), at_source.begin() + places);
    Key at_target{-1, -1, -1, -1};
    for (int i = 0; i < places; ++i) at_target[i] = target_of.at(at_source[i]);
    std::sort(at_target.begin(), at_target.begin() + places);
    prism[s] = source_outside.count(at_source) && target_outside.count(at_target) ? Prism::SharedOutside
                                                                                   : Prism::SharedInside;
  }
  return prism;
}

}  // namespace animanifold
