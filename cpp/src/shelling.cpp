#include "animanifold/shelling.hpp"

#include "animanifold/errors.hpp"
#include "simplex_key.hpp"

#include <algorithm>
#include <array>
#include <unordered_map>

namespace animanifold {

namespace {

using Key = SimplexKey<5>;
using KeyHash = SimplexKeyHash;

// The vertices of row r of S picked by the bits of `mask`, as a key.
Key face(const SimplexMatrix& S, Index r, unsigned mask) {
  Index ids[5];
  int j = 0;
  for (int c = 0; c < S.cols(); ++c)
    if (mask & (1u << c)) ids[j++] = S(r, c);
  return simplex_key<5>(ids, j);
}

}  // namespace

std::vector<bool> shell_off(const SimplexMatrix& S, const std::vector<Index>& candidates,
                            const std::function<bool(const Index* facet)>& may_open) {
  const int corners = static_cast<int>(S.cols());
  if (corners < 2 || corners > 5) fail<InputError>("shelling works on simplices of 1 to 4 dimensions, got ", corners - 1);
  const unsigned all = (1u << corners) - 1;
  std::vector<bool> removed(S.rows(), false);
  if (candidates.empty()) return removed;
  // How many simplices hold each facet, and how many boundary facets hold
  // each face (of any dimension) of the boundary.
  std::unordered_map<Key, int, KeyHash> holders, on_boundary;
  for (Index r = 0; r < S.rows(); ++r)
    for (int drop = 0; drop < corners; ++drop) ++holders[face(S, r, all & ~(1u << drop))];
  // The faces of a facet (given by the facet's mask in row r): every nonempty subset.
  auto each_face_of_facet = [&](Index r, unsigned facet_mask, int delta) {
    for (unsigned sub = facet_mask; sub; sub = (sub - 1) & facet_mask) {
      auto& count = on_boundary[face(S, r, sub)];
      count += delta;
    }
  };
  // Each boundary facet counted once, from the one simplex that holds it.
  for (Index r = 0; r < S.rows(); ++r)
    for (int drop = 0; drop < corners; ++drop) {
      const unsigned mask = all & ~(1u << drop);
      if (holders[face(S, r, mask)] == 1) each_face_of_facet(r, mask, +1);
    }
  for (bool changed = true; changed;) {
    changed = false;
    for (const Index r : candidates) {
      if (removed[r]) continue;
      unsigned open = 0;  // the candidate's facets on the boundary, by the vertex each drops
      bool allowed = true;
      for (int drop = 0; drop < corners && allowed; ++drop) {
        const Key k = face(S, r, all & ~(1u << drop));
        if (holders[k] != 1) continue;
        open |= 1u << drop;
        allowed = may_open(k.data());
      }
      if (!allowed || open == 0 || open == all) continue;
      // Faces holding every vertex opposite an open facet are not in any
      // open facet: on the boundary already, the removal would pinch there.
      bool pinches = false;
      for (unsigned sub = all; sub && !pinches; sub = (sub - 1) & all)
        if ((sub & open) == open && sub != all) {
          const auto it = on_boundary.find(face(S, r, sub));
          pinches = it != on_boundary.end() && it->second > 0;
        }
      if (pinches) continue;
      removed[r] = changed = true;
      for (int drop = 0; drop < corners; ++drop) {
        const unsigned mask = all & ~(1u << drop);
        const Key k = face(S, r, mask);
        if (open & (1u << drop)) {
          each_face_of_facet(r, mask, -1);  // off the boundary with the simplex
          holders[k] = 0;
        } else if (--holders[k] == 1) {
          each_face_of_facet(r, mask, +1);  // exposed
        }
      }
    }
  }
  return removed;
}

}  // namespace animanifold
