// Refinement of a half's tetrahedralization, and the slab that joins the
// refined half to the fill (morph_field_internal.hpp).
#include "animanifold/errors.hpp"
#include "morph_field_internal.hpp"
#include "stellar_complex.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_set>

namespace animanifold::morph_field {

namespace {

// A chord whose middle lies within this share of its length from the input
// lies in it but for rounding: the diagonal of a planar quad across the
// input's own diagonal (the Delaunay triangulation of four cocircular points
// holds both). It bounds a cell flat to rounding, which the zero set leaves
// out at the end: the end frame then holds that diagonal, the same surface.
constexpr double kFlatChord = 1e-9;
// An edge is looked at for a bridge when the field at both its ends is
// within this many edge lengths of zero at some layer (the zero set may pass
// near it); farther, its middle is of the same sign for any field with the
// distance's slope.
constexpr double kNearZero = 1.0;
// A crossed edge longer than this many lattice spacings is split.
constexpr double kCoarseEdge = 1.5;

using Tets = StellarComplex<4>;

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

class Refiner {
 public:
  Refiner(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
          const SimplexMatrix& constraints, const SignedDistance& own, const SignedDistance& dS,
          const SignedDistance& dT, const std::vector<double>& weights)
      : tets_(to_simplices(cells), static_cast<Index>(points.rows())),
        n_(static_cast<Index>(points.rows())),
        own_(own), dS_(dS), dT_(dT), weights_(weights), on_surface_(on_surface) {
    for (Index v = 0; v < points.rows(); ++v) positions_.push_back(points.row(v));
    s_ = dS.distances(points), t_ = dT.distances(points);
    sv_.assign(s_.data(), s_.data() + s_.size()), tv_.assign(t_.data(), t_.data() + t_.size());
    for (Index f = 0; f < constraints.rows(); ++f) {
      std::array<Index, 3> t{constraints(f, 0), constraints(f, 1), constraints(f, 2)};
      std::sort(t.begin(), t.end());
      surface_faces_.insert(t);
      for (int k = 0; k < 3; ++k) surface_edges_.insert(edge_key(t[k], t[(k + 1) % 3]));
    }
  }

  // Inside chords of the end facet (see morph_field.hpp): edges, then
  // triangles, then tets whose corners are all on the input and that are not
  // its own, inside it and not in it but for rounding.
  void split_chords() {
    for (const int count : {2, 3, 4}) {
      std::set<std::vector<Index>> chords;
      for (const auto& tet : tets_.live()) {
        std::vector<Index> z;
        for (const Index v : tet)
          if (zero(v)) z.push_back(v);
        std::sort(z.begin(), z.end());
        const int n = static_cast<int>(z.size());
        if (n < count) continue;
        if (count == 2) {
          for (int a = 0; a < n; ++a)
            for (int b = a + 1; b < n; ++b)
              if (!surface_edges_.count(edge_key(z[a], z[b]))) chords.insert({z[a], z[b]});
        } else if (count == 3) {
          for (int skip = 0; skip < (n == 3 ? 1 : n); ++skip) {
            std::array<Index, 3> t{};
            for (int k = 0, j = 0; k < n; ++k)
              if (n == 3 || k != skip) t[j++] = z[k];
            if (!surface_faces_.count(t)) chords.insert({t[0], t[1], t[2]});
          }
        } else if (n == 4) {
          chords.insert(z);
        }
      }
      for (const auto& chord : chords) {
        const auto [centre, longest] = centroid(chord);
        const double d = own_.distances(centre).value();
        if (d >= 0) ++report_.outside_chords;
        else if (std::abs(d) <= kFlatChord * longest) ++report_.flat_chords;
        else split(chord, centre), ++report_.chords;
      }
    }
  }

  // Edges the zero set needs split at some layer of the half: a bridge (its
  // ends of one sign, its middle of the other: the zero set would tunnel
  // through it) or a crossed edge longer than `spacing`.
  void split_edges(double spacing) {
    std::unordered_set<std::uint64_t> seen;
    std::vector<std::array<Index, 2>> candidates;
    std::vector<std::array<Index, 2>> coarse;
    for (const auto& tet : tets_.live())
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
          const Index u = tet[a], v = tet[b];
          // Edges between two points of the input are the chords' business.
          if ((zero(u) && zero(v)) || !seen.insert(edge_key(u, v)).second) continue;
          const double length = (positions_[u] - positions_[v]).norm();
          bool crossed = false, near = false;
          for (const double w : weights_) {
            const double pu = (1 - w) * sv_[u] + w * tv_[u], pv = (1 - w) * sv_[v] + w * tv_[v];
            crossed = crossed || ((pu < 0) != (pv < 0));
            near = near || (std::abs(pu) < kNearZero * length && std::abs(pv) < kNearZero * length);
          }
          if (crossed && length > kCoarseEdge * spacing) coarse.push_back({u, v});
          else if (!crossed && near) candidates.push_back({u, v});
        }
    // Bridges: the field at the candidates' middles.
    PointMatrix middles(static_cast<Index>(candidates.size()), 3);
    for (size_t e = 0; e < candidates.size(); ++e)
      middles.row(static_cast<Index>(e)) = 0.5 * (positions_[candidates[e][0]] + positions_[candidates[e][1]]);
    const Eigen::VectorXd ms = dS_.distances(middles), mt = dT_.distances(middles);
    for (size_t e = 0; e < candidates.size(); ++e) {
      const auto [u, v] = candidates[e];
      for (const double w : weights_) {
        const double pu = (1 - w) * sv_[u] + w * tv_[u];
        const double pm = (1 - w) * ms(static_cast<Index>(e)) + w * mt(static_cast<Index>(e));
        if ((pu < 0) != (pm < 0)) {
          split({u, v}, middles.row(static_cast<Index>(e)), ms(static_cast<Index>(e)), mt(static_cast<Index>(e)));
          ++report_.bridges;
          break;
        }
      }
    }
    for (const auto& e : coarse) {
      split({e[0], e[1]}, 0.5 * (positions_[e[0]] + positions_[e[1]]));
      ++report_.coarse;
    }
  }

  RefinedCells take() {
    const auto live = tets_.live();
    report_.cells.resize(static_cast<Index>(live.size()), 4);
    for (size_t c = 0; c < live.size(); ++c)
      for (int k = 0; k < 4; ++k) report_.cells(static_cast<Index>(c), k) = live[c][k];
    const Index added = static_cast<Index>(positions_.size()) - n_;
    report_.new_points.resize(added, 3);
    for (Index j = 0; j < added; ++j) report_.new_points.row(j) = positions_[n_ + j];
    return std::move(report_);
  }

 private:
  static std::vector<Tets::Simplex> to_simplices(const SimplexMatrix& cells) {
    std::vector<Tets::Simplex> out(static_cast<size_t>(cells.rows()));
    for (Index c = 0; c < cells.rows(); ++c) out[c] = {cells(c, 0), cells(c, 1), cells(c, 2), cells(c, 3)};
    return out;
  }

  bool zero(Index v) const { return v < n_ && on_surface_[v]; }

  std::pair<Eigen::RowVector3d, double> centroid(const std::vector<Index>& face) const {
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    double longest = 0;
    for (const Index v : face) {
      centre += positions_[v];
      for (const Index w : face) longest = std::max(longest, (positions_[v] - positions_[w]).norm());
    }
    return {centre / static_cast<double>(face.size()), longest};
  }

  void split(const std::vector<Index>& face, const Eigen::RowVector3d& at) {
    split(face, at, dS_.distances(at).value(), dT_.distances(at).value());
  }

  void split(const std::vector<Index>& face, const Eigen::RowVector3d& at, double s, double t) {
    const Index q = static_cast<Index>(positions_.size());
    tets_.split(face.data(), static_cast<int>(face.size()), q);
    positions_.push_back(at);
    sv_.push_back(s), tv_.push_back(t);
    report_.splits.push_back(face);
  }

  Tets tets_;
  Index n_;
  const SignedDistance &own_, &dS_, &dT_;
  std::vector<double> weights_;
  const std::vector<bool>& on_surface_;
  std::vector<Eigen::RowVector3d> positions_;
  Eigen::VectorXd s_, t_;
  std::vector<double> sv_, tv_;
  std::set<std::array<Index, 3>> surface_faces_;
  std::unordered_set<std::uint64_t> surface_edges_;
  RefinedCells report_;
};

}  // namespace

RefinedCells refine_cells(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                          const SimplexMatrix& constraints, const SignedDistance& own, const SignedDistance& dS,
                          const SignedDistance& dT, const std::vector<double>& weights, double spacing, int rounds) {
  Refiner refiner(cells, points, on_surface, constraints, own, dS, dT, weights);
  refiner.split_chords();
  for (int r = 0; r < rounds; ++r) refiner.split_edges(spacing);
  return refiner.take();
}

std::vector<Simplex4> transition_slab(const SimplexMatrix& cells, const std::vector<std::vector<Index>>& splits,
                                      Index n, Index refined_count, bool refined_at_bottom) {
  // Local ids: the refined layer's points are 0..refined_count-1 (the first
  // n are the unrefined layer's too), the unrefined layer's are
  // refined_count + v.
  const Index refined = 0, plain = refined_count;
  std::vector<Simplex4> prisms(4 * static_cast<size_t>(cells.rows()));
  for (Index c = 0; c < cells.rows(); ++c)
    prism_simplices(cells.row(c).data(), refined_at_bottom ? refined : plain, refined_at_bottom ? plain : refined,
                    &prisms[4 * static_cast<size_t>(c)]);
  StellarComplex<5> slab(std::move(prisms), refined_count + n);
  for (size_t j = 0; j < splits.size(); ++j)
    slab.split(splits[j].data(), static_cast<int>(splits[j].size()), n + static_cast<Index>(j));
  return slab.live();
}

}  // namespace animanifold::morph_field
