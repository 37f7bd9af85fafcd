// A simplicial complex under stellar splits (chapter 6's split tuples with
// barycentric coordinates at a face's centroid): the field morph refines its
// tetrahedralizations with it, and replays the same splits on one facet of
// a slab of 4-simplices (morph_field_refine.cpp).
//
// Inputs: simplices of K vertices (tets: 4, 4-simplices: 5), each positively
// oriented. split(face, q) puts the new vertex q inside the face (any of its
// vertices, 2..K of them) and replaces every simplex containing the face by
// one child per face vertex, that vertex replaced by q in place: children
// keep their parent's orientation and the complex stays conforming after
// every split (§6.1). Throws MeshingError when no simplex contains the
// face.
#pragma once

#include "animanifold/errors.hpp"
#include "animanifold/types.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

namespace animanifold {

template <int K>
class StellarComplex {
 public:
  using Simplex = std::array<Index, K>;

  StellarComplex(std::vector<Simplex> simplices, Index vertex_count) : simplices_(std::move(simplices)) {
    alive_.assign(simplices_.size(), true);
    star_.resize(static_cast<size_t>(vertex_count));
    for (size_t s = 0; s < simplices_.size(); ++s)
      for (const Index v : simplices_[s]) star_[v].push_back(static_cast<Index>(s));
  }

  // The live simplices containing every vertex of `face`.
  std::vector<Index> around(const Index* face, int count) const {
    std::vector<Index> out;
    for (const Index s : star_[face[0]]) {
      if (!alive_[s]) continue;
      bool all = true;
      for (int k = 1; k < count && all; ++k)
        all = std::find(simplices_[s].begin(), simplices_[s].end(), face[k]) != simplices_[s].end();
      if (all) out.push_back(s);
    }
    return out;
  }

  void split(const Index* face, int count, Index q) {
    const std::vector<Index> parents = around(face, count);
    if (parents.empty()) fail<MeshingError>("a face to split lies in no simplex of the complex");
    if (star_.size() <= static_cast<size_t>(q)) star_.resize(static_cast<size_t>(q) + 1);
    for (const Index s : parents) {
      alive_[s] = false;
      for (int k = 0; k < count; ++k) {
        Simplex child = simplices_[s];
        *std::find(child.begin(), child.end(), face[k]) = q;
        const Index id = static_cast<Index>(simplices_.size());
        simplices_.push_back(child);
        alive_.push_back(true);
        for (const Index v : child) star_[v].push_back(id);
      }
    }
  }

  std::vector<Simplex> live() const {
    std::vector<Simplex> out;
    for (size_t s = 0; s < simplices_.size(); ++s)
      if (alive_[s]) out.push_back(simplices_[s]);
    return out;
  }

 private:
  std::vector<Simplex> simplices_;
  std::vector<bool> alive_;
  std::vector<std::vector<Index>> star_;
};

}  // namespace animanifold
