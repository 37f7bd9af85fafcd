// Faces outside an input without a free vertex, and their stellar splits
// after the fill (see morph_skeleton.hpp).
#include "animanifold/morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <unordered_set>
#include <vector>

namespace animanifold {

std::vector<std::vector<Index>> uncovered_outside_faces(const PlaneCells& shape) {
  const SimplexMatrix& cells = shape.cells;
  const int corners = static_cast<int>(cells.cols());  // n + 1
  using FaceKey = std::array<Index, 4>;
  struct Hash {
    size_t operator()(const FaceKey& k) const {
      size_t h = 1469598103934665603ull;
      for (Index v : k) h = (h ^ static_cast<size_t>(static_cast<std::uint32_t>(v))) * 1099511628211ull;
      return h;
    }
  };
  auto key_of = [&](Index c, unsigned mask) {
    FaceKey k{-1, -1, -1, -1};
    int j = 0;
    for (int i = 0; i < corners; ++i)
      if (mask & (1u << i)) k[j++] = cells(c, i);
    std::sort(k.begin(), k.begin() + j);
    return k;
  };
  auto size_of = [](unsigned mask) { return __builtin_popcount(mask); };
  // Faces of cells that are not outside (inside the shape, or flat on its
  // surface) lie inside or on the shape.
  std::unordered_set<FaceKey, Hash> covered, listed;
  for (Index c = 0; c < cells.rows(); ++c)
    if (!shape.outside[c] || shape.flat[c])
      for (unsigned mask = 1; mask < (1u << corners); ++mask)
        if (size_of(mask) >= 2) covered.insert(key_of(c, mask));
  std::vector<std::vector<Index>> faces;
  for (int size = 2; size <= corners; ++size)
    for (Index c = 0; c < cells.rows(); ++c) {
      if (!shape.outside[c] || shape.flat[c]) continue;
      bool has_free = false;
      for (int i = 0; i < corners; ++i) has_free = has_free || shape.free[cells(c, i)];
      if (has_free) continue;
      for (unsigned mask = 1; mask < (1u << corners); ++mask) {
        if (size_of(mask) != size) continue;
        const FaceKey key = key_of(c, mask);
        if (covered.count(key) || listed.count(key)) continue;
        bool split_below = false;  // one of its own faces is listed: it gets a free vertex from that split
        for (unsigned sub = (mask - 1) & mask; sub && !split_below; sub = (sub - 1) & mask)
          split_below = size_of(sub) >= 2 && listed.count(key_of(c, sub));
        if (split_below) continue;
        listed.insert(key);
        faces.emplace_back(key.begin(), key.begin() + size);
      }
    }
  return faces;
}

IndexVector split_faces(PointMatrix& P, SimplexMatrix& A, const std::vector<std::vector<Index>>& faces) {
  const int D = static_cast<int>(P.cols());
  IndexVector added(static_cast<Index>(faces.size()));
  if (faces.empty()) return added;
  // Which simplices hold each vertex, kept up to date through the splits.
  std::vector<std::vector<Index>> at_vertex(P.rows());
  for (Index s = 0; s < A.rows(); ++s)
    for (int c = 0; c <= D; ++c) at_vertex[A(s, c)].push_back(s);
  std::vector<Eigen::Matrix<Index, 1, Eigen::Dynamic>> appended;  // simplices past A's rows
  auto row_of = [&](Index s) -> Eigen::Matrix<Index, 1, Eigen::Dynamic> {
    return s < A.rows() ? Eigen::Matrix<Index, 1, Eigen::Dynamic>(A.row(s)) : appended[s - A.rows()];
  };
  auto set_row = [&](Index s, const Eigen::Matrix<Index, 1, Eigen::Dynamic>& row) {
    if (s < A.rows()) A.row(s) = row;
    else appended[s - A.rows()] = row;
  };
  std::vector<Eigen::RowVectorXd> new_points;
  // Not the centroid itself but a point near it, at random weights between
  // 1 and 2: on symmetric inputs (a shape and its mirror image) centroids of
  // chords line up with the input's own faces, and the cells they make are
  // slivers that hold the point at the plane when it is pushed.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> weight(1.0, 2.0);
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::vector<Index>& face = faces[f];
    const Index m = static_cast<Index>(P.rows() + new_points.size());
    Eigen::RowVectorXd point = Eigen::RowVectorXd::Zero(D);
    double total = 0;
    for (const Index v : face) {
      const double w = weight(rng);
      point += w * P.row(v);
      total += w;
    }
    new_points.push_back(point / total);
    at_vertex.emplace_back();
    added(static_cast<Index>(f)) = m;
    // The star of the face: simplices holding all its vertices.
    std::vector<Index> star;
    for (const Index s : at_vertex[face[0]]) {
      const auto row = row_of(s);
      bool holds = true;
      for (size_t i = 1; i < face.size() && holds; ++i)
        holds = std::find(row.data(), row.data() + D + 1, face[i]) != row.data() + D + 1;
      if (holds) star.push_back(s);
    }
    if (star.empty()) fail<std::runtime_error>("face ", f, " to split is not a face of the fill");
    for (const Index s : star) {
      const auto original = row_of(s);
      // Replacing a corner of a positive simplex by a point of a face that
      // holds the corner keeps it positive: the volume scales by the point's
      // barycentric weight at that corner.
      for (size_t i = 0; i < face.size(); ++i) {
        auto row = original;
        const int corner = static_cast<int>(std::find(row.data(), row.data() + D + 1, face[i]) - row.data());
        row(corner) = m;
        Index target = s;
        if (i > 0) {
          target = static_cast<Index>(A.rows() + appended.size());
          appended.push_back(row);
        } else {
          set_row(s, row);
        }
        for (int c = 0; c <= D; ++c)
          if (i > 0 || row(c) == m) at_vertex[row(c)].push_back(target);
      }
      // The first replaced corner no longer holds s.
      auto& list = at_vertex[face[0]];
      list.erase(std::find(list.begin(), list.end(), s));
    }
  }
  const Index old_points = static_cast<Index>(P.rows()), old_simplices = static_cast<Index>(A.rows());
  P.conservativeResize(old_points + static_cast<Index>(new_points.size()), D);
  for (size_t p = 0; p < new_points.size(); ++p) P.row(old_points + static_cast<Index>(p)) = new_points[p];
  A.conservativeResize(old_simplices + static_cast<Index>(appended.size()), D + 1);
  for (size_t s = 0; s < appended.size(); ++s) A.row(old_simplices + static_cast<Index>(s)) = appended[s];
  return added;
}

}  // namespace animanifold
