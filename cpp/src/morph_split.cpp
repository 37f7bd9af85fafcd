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

namespace {

// split_faces' state through its splits: the fill's simplices (A's rows, then
// those appended), which simplices hold each vertex, and the points so far.
class FaceSplitter {
 public:
  FaceSplitter(const PointMatrix& P, SimplexMatrix& A, Index face_count, const SplitOptions& options)
      : A_(A), options_(options), D_(static_cast<int>(P.cols())), old_points_(static_cast<Index>(P.rows())),
        at_vertex_(P.rows()), Q_(old_points_ + face_count, D_) {
    for (Index s = 0; s < A.rows(); ++s)
      for (int c = 0; c <= D_; ++c) at_vertex_[A(s, c)].push_back(s);
    // The new points are written into Q as they come: the checks of the
    // splits that follow need them.
    Q_.topRows(old_points_) = P;
  }

  // Splits face `f` (its vertices `face`) at a point inside it; the point's
  // index, or -1 when options.skip_unsafe and every point tried inverts a
  // simplex of the face's star.
  Index split(size_t f, const std::vector<Index>& face) {
    const std::vector<Index> star = star_of(face);
    if (star.empty()) fail<MeshingError>("face ", f, " to split is not a face of the fill");
    const Index m = old_points_ + made_;
    const auto [best, inverted] = best_point(f, face, star, m);
    if (inverted > 0 && options_.skip_unsafe) return -1;
    Q_.row(m) = best;
    ++made_;
    at_vertex_.emplace_back();
    replace_star(face, star, m);
    return m;
  }

  // The points (P's rows, then the split points) and the simplices with
  // those appended; `parents` (when asked) the row of A each comes from.
  void finish(PointMatrix& P, std::vector<Index>* parents) {
    const Index old_simplices = static_cast<Index>(A_.rows());
    Q_.conservativeResize(old_points_ + made_, D_);
    P = std::move(Q_);
    if (parents) {
      parents->resize(old_simplices + appended_.size());
      std::iota(parents->begin(), parents->begin() + old_simplices, Index{0});
      std::copy(appended_parent_.begin(), appended_parent_.end(), parents->begin() + old_simplices);
    }
    A_.conservativeResize(old_simplices + static_cast<Index>(appended_.size()), D_ + 1);
    for (size_t s = 0; s < appended_.size(); ++s) A_.row(old_simplices + static_cast<Index>(s)) = appended_[s];
  }

 private:
  Index parent_of(Index s) const { return s < A_.rows() ? s : appended_parent_[s - A_.rows()]; }
  Row row_of(Index s) const { return s < A_.rows() ? Row(A_.row(s)) : appended_[s - A_.rows()]; }
  void set_row(Index s, const Row& row) {
    if (s < A_.rows()) A_.row(s) = row;
    else appended_[s - A_.rows()] = row;
  }

  // The star of the face: simplices holding all its vertices.
  std::vector<Index> star_of(const std::vector<Index>& face) const {
    std::vector<Index> star;
    for (const Index s : at_vertex_[face[0]]) {
      const auto row = row_of(s);
      bool holds = true;
      for (size_t i = 1; i < face.size() && holds; ++i)
        holds = std::find(row.data(), row.data() + D_ + 1, face[i]) != row.data() + D_ + 1;
      if (holds) star.push_back(s);
    }
    return star;
  }

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
  // Returns the point and how many simplices it inverts.
  std::pair<Eigen::RowVectorXd, int> best_point(size_t f, const std::vector<Index>& face,
                                                const std::vector<Index>& star, Index m) {
    std::vector<bool> positive;
    for (const Index s : star) positive.push_back(exact_orientation(Q_, row_of(s).data()) > 0);
    Eigen::RowVectorXd best;
    int best_inverted = std::numeric_limits<int>::max();
    auto inverted_by = [&](const Eigen::RowVectorXd& point) {  // stops counting at the best so far
      Q_.row(m) = point;
      int inverted = 0;
      for (size_t k = 0; k < star.size() && inverted < best_inverted; ++k) {
        if (!positive[k]) continue;
        const Row row = row_of(star[k]);
        for (size_t i = 0; i < face.size() && inverted < best_inverted; ++i) {
          Row split = row;
          *std::find(split.data(), split.data() + D_ + 1, face[i]) = m;
          inverted += exact_orientation(Q_, split.data()) <= 0 ||
                      (options_.thinnest > 0 && relative_volume(Q_, split.data()) < options_.thinnest);
        }
      }
      return inverted;
    };
    if (options_.positions) best = options_.positions->row(static_cast<Index>(f)), best_inverted = 0;
    for (int attempt = 0; attempt < kSplitAttempts && best_inverted > 0; ++attempt) {
      std::vector<double> w(face.size());
      double total = 0;
      for (double& x : w) total += (x = weight_(rng_));
      Eigen::RowVectorXd point = Q_.row(face[0]);
      for (size_t i = 1; i < face.size(); ++i) point += (w[i] / total) * (Q_.row(face[i]) - Q_.row(face[0]));
      const int inverted = inverted_by(point);
      if (inverted < best_inverted) best_inverted = inverted, best = point;
    }
    return {best, best_inverted};
  }

  // Each simplex of the star becomes one per corner of the face, with that
  // corner replaced by point m (the first in place, the others appended).
  void replace_star(const std::vector<Index>& face, const std::vector<Index>& star, Index m) {
    for (const Index s : star) {
      const auto original = row_of(s);
      for (size_t i = 0; i < face.size(); ++i) {
        auto row = original;
        const int corner = static_cast<int>(std::find(row.data(), row.data() + D_ + 1, face[i]) - row.data());
        row(corner) = m;
        Index target = s;
        if (i > 0) {
          target = static_cast<Index>(A_.rows() + appended_.size());
          appended_.push_back(row);
          appended_parent_.push_back(parent_of(s));
        } else {
          set_row(s, row);
        }
        for (int c = 0; c <= D_; ++c)
          if (i > 0 || row(c) == m) at_vertex_[row(c)].push_back(target);
      }
      // The first replaced corner no longer holds s.
      auto& list = at_vertex_[face[0]];
      list.erase(std::find(list.begin(), list.end(), s));
    }
  }

  SimplexMatrix& A_;
  const SplitOptions& options_;
  int D_;
  Index old_points_;
  std::vector<std::vector<Index>> at_vertex_;  // kept up to date through the splits
  std::vector<Row> appended_;                  // simplices past A's rows
  std::vector<Index> appended_parent_;         // ... and the row of A each comes from
  PointMatrix Q_;
  Index made_ = 0;  // split points so far
  // Not the centroid itself but a point near it, at random weights between
  // 1 and 2: on symmetric inputs (a shape and its mirror image) centroids of
  // chords line up with the input's own faces, and the cells they make are
  // slivers that hold the point at the plane when it is pushed.
  std::mt19937_64 rng_{4242};
  std::uniform_real_distribution<double> weight_{1.0, 2.0};
};

}  // namespace

IndexVector split_faces(PointMatrix& P, SimplexMatrix& A, const std::vector<std::vector<Index>>& faces,
                        const SplitOptions& options) {
  IndexVector added(static_cast<Index>(faces.size()));
  if (faces.empty()) {
    if (options.parents) {
      options.parents->resize(A.rows());
      std::iota(options.parents->begin(), options.parents->end(), Index{0});
    }
    return added;
  }
  FaceSplitter splitter(P, A, static_cast<Index>(faces.size()), options);
  for (size_t f = 0; f < faces.size(); ++f) added(static_cast<Index>(f)) = splitter.split(f, faces[f]);
  splitter.finish(P, options.parents);
  return added;
}

}  // namespace animanifold
