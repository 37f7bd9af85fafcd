// Points hashed on a grid of cubic cells, to find those near a query point:
// which points of one set lie within a distance of a point of another.
#pragma once

#include "animanifold/types.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace animanifold {

class PointGrid {
 public:
  // `reach`: the distance near() looks within (the cells' width), > 0.
  explicit PointGrid(double reach) : reach_(reach) {}

  void add(const Eigen::Vector3d& p, Index id) { cells_[key(p)].emplace_back(p, id); }

  // Calls visit(id, distance) for each point added at most `reach` from x.
  template <class Visit>
  void near(const Eigen::Vector3d& x, Visit&& visit) const {
    const Key k = key(x);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == cells_.end()) continue;
          for (const auto& [p, id] : it->second)
            if (const double d = (p - x).norm(); d <= reach_) visit(id, d);
        }
  }

 private:
  using Key = std::array<std::int64_t, 3>;
  Key key(const Eigen::Vector3d& p) const {
    return {static_cast<std::int64_t>(std::floor(p(0) / reach_)), static_cast<std::int64_t>(std::floor(p(1) / reach_)),
            static_cast<std::int64_t>(std::floor(p(2) / reach_))};
  }
  double reach_;
  std::map<Key, std::vector<std::pair<Eigen::Vector3d, Index>>> cells_;
};

}  // namespace animanifold
