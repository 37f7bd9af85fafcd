// Faces outside an input without a free vertex, and their stellar splits
// after the fill (see morph_skeleton.hpp).
#include "morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/exact_orientation.hpp"
#include "simplex_key.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <unordered_set>
#include <vector>

namespace animanifold {

namespace {
// A simplex's corners (up to five) on the stack.
using Row = Eigen::Matrix<Index, 1, Eigen::Dynamic, Eigen::RowMajor, 1, 5>;
// Draws of a split point's weights before the fewest inverted simplices are
// accepted (split_faces).
constexpr int kSplitAttempts = 16;

}  // namespace

std::vector<std::vector<Index>> uncovered_outside_faces(const PlaneCells& shape) {
  const SimplexMatrix& cells = shape.cells;
  const int corners = static_cast<int>(cells.cols());  // n + 1
  using FaceKey = SimplexKey<4>;
  auto key_of = [&](Index c, unsigned mask) {
    Index ids[4];
    int j = 0;
    for (int i = 0; i < corners; ++i)
      if (mask & (1u << i)) ids[j++] = cells(c, i);
    return simplex_key<4>(ids, j);
  };
  auto size_of = [](unsigned mask) { return __builtin_popcount(mask); };
  // Faces of cells that are not outside (inside the shape, or flat on its
  // surface) lie inside or on the shape.
  std::unordered_set<FaceKey, SimplexKeyHash> covered, listed;
  for (Index c = 0; c < cells.rows(); ++c)
    if (!shape.outside[c] || shape.flat[c])
      for (unsigned mask = 1; mask < (1u << corners); ++mask)
        if (size_of(mask) >= 2) covered.insert(key_of(c, mask));
  std::vector<std::vector<Index>> faces;
  for (int size = 2; size <= corners; ++size)
    for (Index c = 0; c < cells.rows(); ++c) {
      if (!shape.outside[c] || shape.flat[c]) continue;
      for (unsigned mask = 1; mask < (1u << corners); ++mask) {
        if (size_of(mask) != size) continue;
        // A face with a free vertex leaves the plane with it; one without
        // stays there, whatever the cell's other corners do.
        bool has_free = false;
        for (int i = 0; i < corners; ++i) has_free = has_free || ((mask & (1u << i)) && shape.free[cells(c, i)]);
        if (has_free) continue;
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

IndexVector split_faces(PointMatrix& P, SimplexMatrix& A, const std::vector<std::vector<Index>>& faces,
                        const SplitOptions& options) {
  const PointMatrix* positions = options.positions;
  std::vector<Index>* parents = options.parents;
  const int D = static_cast<int>(P.cols());
  IndexVector added(static_cast<Index>(faces.size()));
  if (faces.empty()) {
    if (parents) parents->resize(A.rows()), std::iota(parents->begin(), parents->end(), Index{0});
    return added;
  }
  // Which simplices hold each vertex, kept up to date through the splits.
  std::vector<std::vector<Index>> at_vertex(P.rows());
  for (Index s = 0; s < A.rows(); ++s)
    for (int c = 0; c <= D; ++c) at_vertex[A(s, c)].push_back(s);
  std::vector<Row> appended;  // simplices past A's rows
  std::vector<Index> appended_parent;                             // ... and the row of A each comes from
  auto parent_of = [&](Index s) { return s < A.rows() ? s : appended_parent[s - A.rows()]; };
  auto row_of = [&](Index s) -> Row {
    return s < A.rows() ? Row(A.row(s)) : appended[s - A.rows()];
  };
  auto set_row = [&](Index s, const Row& row) {
    if (s < A.rows()) A.row(s) = row;
    else appended[s - A.rows()] = row;
  };
  // The new points are written into `Q` as they come: the checks below
  // need them for the splits that follow.
  const Index old_points = static_cast<Index>(P.rows()), old_simplices = static_cast<Index>(A.rows());
  PointMatrix Q(old_points + static_cast<Index>(faces.size()), D);
  Q.topRows(old_points) = P;
  // Not the centroid itself but a point near it, at random weights between
  // 1 and 2: on symmetric inputs (a shape and its mirror image) centroids of
  // chords line up with the input's own faces, and the cells they make are
  // slivers that hold the point at the plane when it is pushed.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> weight(1.0, 2.0);
  std::vector<Index> star;
  std::vector<bool> positive;
  Index made = 0;  // split points so far
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::vector<Index>& face = faces[f];
    const Index m = old_points + made;
    // The star of the face: simplices holding all its vertices.
    star.clear();
    for (const Index s : at_vertex[face[0]]) {
      const auto row = row_of(s);
      bool holds = true;
      for (size_t i = 1; i < face.size() && holds; ++i)
        holds = std::find(row.data(), row.data() + D + 1, face[i]) != row.data() + D + 1;
      if (holds) star.push_back(s);
    }
    if (star.empty()) fail<MeshingError>("face ", f, " to split is not a face of the fill");
    // Replacing a corner of a positive simplex by a point of a face that
    // holds the corner keeps it positive: the volume scales by the point's
    // barycentric weight at that corner — for a point exactly on the face.
    // In doubles the point is only near it, and a sliver of the star (far
    // thinner than the rounding) can come out inverted. So the point is
    // taken from the face's first corner along differences (coordinates all
    // its corners share stay exact: a face in a flat side, a chord along a
    // hull edge), and every new simplex is checked by the exact predicate;
    // other weights are drawn while one fails (kept: the fewest failures).
    // Simplices of the star that are not positive before have nothing to keep.
    positive.clear();
    for (const Index s : star) positive.push_back(exact_orientation(Q, row_of(s).data()) > 0);
    Eigen::RowVectorXd best;
    int best_inverted = std::numeric_limits<int>::max();
    auto inverted_by = [&](const Eigen::RowVectorXd& point) {  // stops counting at the best so far
      Q.row(m) = point;
      int inverted = 0;
      for (size_t k = 0; k < star.size() && inverted < best_inverted; ++k) {
        if (!positive[k]) continue;
        const Row row = row_of(star[k]);
        for (size_t i = 0; i < face.size() && inverted < best_inverted; ++i) {
          Row split = row;
          *std::find(split.data(), split.data() + D + 1, face[i]) = m;
          inverted += exact_orientation(Q, split.data()) <= 0 ||
                      (options.thinnest > 0 && relative_volume(Q, split.data()) < options.thinnest);
        }
      }
      return inverted;
    };
    if (positions) best = positions->row(static_cast<Index>(f)), best_inverted = 0;
    for (int attempt = 0; attempt < kSplitAttempts && best_inverted > 0; ++attempt) {
      std::vector<double> w(face.size());
      double total = 0;
      for (double& x : w) total += (x = weight(rng));
      Eigen::RowVectorXd point = Q.row(face[0]);
      for (size_t i = 1; i < face.size(); ++i) point += (w[i] / total) * (Q.row(face[i]) - Q.row(face[0]));
      const int inverted = inverted_by(point);
      if (inverted < best_inverted) best_inverted = inverted, best = point;
    }
    if (best_inverted > 0 && options.skip_unsafe) {
      added(static_cast<Index>(f)) = -1;
      continue;
    }
    Q.row(m) = best;
    ++made;
    at_vertex.emplace_back();
    added(static_cast<Index>(f)) = m;
    for (const Index s : star) {
      const auto original = row_of(s);
      for (size_t i = 0; i < face.size(); ++i) {
        auto row = original;
        const int corner = static_cast<int>(std::find(row.data(), row.data() + D + 1, face[i]) - row.data());
        row(corner) = m;
        Index target = s;
        if (i > 0) {
          target = static_cast<Index>(A.rows() + appended.size());
          appended.push_back(row);
          appended_parent.push_back(parent_of(s));
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
  Q.conservativeResize(old_points + made, D);
  P = std::move(Q);
  if (parents) {
    parents->resize(old_simplices + appended.size());
    std::iota(parents->begin(), parents->begin() + old_simplices, Index{0});
    std::copy(appended_parent.begin(), appended_parent.end(), parents->begin() + old_simplices);
  }
  A.conservativeResize(old_simplices + static_cast<Index>(appended.size()), D + 1);
  for (size_t s = 0; s < appended.size(); ++s) A.row(old_simplices + static_cast<Index>(s)) = appended[s];
  return added;
}

}  // namespace animanifold
