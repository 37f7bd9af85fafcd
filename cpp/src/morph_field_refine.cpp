// Refinement of a half's tetrahedralization, and the slab that joins the
// refined half to the fill (morph_field_internal.hpp).
#include "animanifold/errors.hpp"
#include "morph_field_internal.hpp"
#include "point_grid.hpp"
#include "stellar_complex.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <set>
#include <functional>
#include <unordered_set>

namespace animanifold::morph_field {

namespace {

// A chord whose middle lies within this share of its length from the input
// lies in it but for rounding: the diagonal of a planar quad across the
// input's own diagonal (the Delaunay triangulation of four cocircular points
// can hold both). It bounds a cell flat to rounding, which the conforming end
// mends (flat_surface_cells, conforming_mend.hpp) and reports where it
// cannot (MorphReport::flat_cells). One left is not split: the zero set
// leaves it out at the end, and the end frame holds that diagonal, the same
// surface.
constexpr double kFlatChord = 1e-9;
// A crossed edge longer than this many lattice spacings is split.
constexpr double kCoarseEdge = 1.5;
constexpr double kMiddleJitter = 0.05;
// A curved edge's middle within this share of the input's extent from a
// point already there is that point but for rounding, and is not added.
constexpr double kCoincidentMiddle = 1e-9;

using Tets = StellarComplex<4>;

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The chords of the end facet (`tets`), `count` corners each: edges, or
// triangles, or tets whose corners are all zero (on the input) and that are
// not edges or faces of the refined input.
std::set<std::vector<Index>> chords_of(const std::vector<Tets::Simplex>& tets, int count,
                                       const std::function<bool(Index)>& zero,
                                       const std::unordered_set<std::uint64_t>& surface_edges,
                                       const std::set<std::array<Index, 3>>& surface_faces) {
  std::set<std::vector<Index>> chords;
  for (const auto& tet : tets) {
    std::vector<Index> z;
    for (const Index v : tet)
      if (zero(v)) z.push_back(v);
    std::sort(z.begin(), z.end());
    const int n = static_cast<int>(z.size());
    if (n < count) continue;
    if (count == 2) {
      for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
          if (!surface_edges.count(edge_key(z[a], z[b]))) chords.insert({z[a], z[b]});
    } else if (count == 3) {
      for (int skip = 0; skip < (n == 3 ? 1 : n); ++skip) {
        std::array<Index, 3> t{};
        for (int k = 0, j = 0; k < n; ++k)
          if (n == 3 || k != skip) t[j++] = z[k];
        if (!surface_faces.count(t)) chords.insert({t[0], t[1], t[2]});
      }
    } else if (n == 4) {
      chords.insert(z);
    }
  }
  return chords;
}

}  // namespace

void EndDistances::extend(const PointMatrix& points, const SignedDistance& dS, const SignedDistance& dT) {
  const Index known = s.size(), added = points.rows() - known;
  if (added <= 0) return;
  const PointMatrix more = points.bottomRows(added);
  s.conservativeResize(points.rows()), t.conservativeResize(points.rows());
  s.tail(added) = dS.distances(more), t.tail(added) = dT.distances(more);
}

PointMatrix refinement_points(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                              const PointMatrix& V, const SimplexMatrix& F, const SignedDistance& own,
                              const SignedDistance& dS, const SignedDistance& dT, const EndDistances& at_points,
                              const std::vector<double>& weights, double spacing) {
  if (at_points.s.size() != points.rows() || at_points.t.size() != points.rows())
    fail<InputError>("refinement_points needs the distances at all ", points.rows(), " points, got ", at_points.s.size());
  auto field = [&](Index v, double w) { return at_points.blend(v, w); };
  std::unordered_set<std::uint64_t> seen;
  std::vector<std::array<Index, 2>> candidates;
  std::vector<double> xyz;
  for (Index c = 0; c < cells.rows(); ++c)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Index u = cells(c, a), v = cells(c, b);
        if ((on_surface[u] && on_surface[v]) || !seen.insert(edge_key(u, v)).second) continue;
        const double length = (points.row(u) - points.row(v)).norm();
        bool crossed = false, near = false;
        for (const double w : weights) {
          const double pu = field(u, w), pv = field(v, w);
          crossed = crossed || ((pu < 0) != (pv < 0));
          near = near || (std::abs(pu) < 0.5 * length && std::abs(pv) < 0.5 * length);
        }
        if (crossed && length > kCoarseEdge * spacing) {
          const Eigen::RowVector3d m = 0.5 * (points.row(u) + points.row(v));
          xyz.insert(xyz.end(), {m(0), m(1), m(2)});
        } else if (!crossed && near) {  // the blend changes by at most half the edge to its middle
          candidates.push_back({u, v});
        }
      }
  // Bridges: the field at the candidates' middles.
  PointMatrix middles(static_cast<Index>(candidates.size()), 3);
  for (size_t e = 0; e < candidates.size(); ++e)
    middles.row(static_cast<Index>(e)) = 0.5 * (points.row(candidates[e][0]) + points.row(candidates[e][1]));
  const Eigen::VectorXd ms = dS.distances(middles), mt = dT.distances(middles);
  for (size_t e = 0; e < candidates.size(); ++e) {
    const Index u = candidates[e][0], r = static_cast<Index>(e);
    for (const double w : weights)
      if ((field(u, w) < 0) != (at_points.blend(ms(r), mt(r), w) < 0)) {
        xyz.insert(xyz.end(), {middles(r, 0), middles(r, 1), middles(r, 2)});
        break;
      }
  }
  // Off the middle by a little (kMiddleJitter of the edge, or of the lattice
  // spacing): the middle is collinear with the edge's ends, and middles of
  // edges in one plane are coplanar with them — flat tets once triangulated.
  PointMatrix found = Eigen::Map<const PointMatrix>(xyz.data(), static_cast<Index>(xyz.size() / 3), 3);
  for (Index r = 0; r < found.rows(); ++r)
    for (int a = 0; a < 3; ++a) found(r, a) += kMiddleJitter * spacing * jitter(r, a, 0x3d1d, 0);
  const std::vector<bool> clear = clear_of_surface(found, V, F, own);
  std::vector<Index> keep;
  for (Index r = 0; r < found.rows(); ++r)
    if (clear[r]) keep.push_back(r);
  return found(keep, Eigen::all);
}

PointMatrix points_off_flat_cells(const SimplexMatrix& cells, const PointMatrix& points,
                                  const std::vector<bool>& on_surface, double reach) {
  // Flat as conforming_mend.cpp's flat_surface_cells() judges it.
  constexpr double kFlatCell = 1e-9;
  // Heights off the plane, as shares of the cell's size: unequal, so that
  // the two points and the cell's corners are not cospherical again.
  constexpr double kAbove = 0.31, kBelow = 0.37;
  std::vector<double> xyz;
  for (Index c = 0; c < cells.rows(); ++c) {
    const Index* t = cells.row(c).data();
    if (!(on_surface[t[0]] && on_surface[t[1]] && on_surface[t[2]] && on_surface[t[3]])) continue;
    const Eigen::Vector3d p0 = points.row(t[0]), p1 = points.row(t[1]), p2 = points.row(t[2]), p3 = points.row(t[3]);
    double longest = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (points.row(t[a]) - points.row(t[b])).norm());
    if (std::abs((p1 - p0).dot((p2 - p0).cross(p3 - p0))) > kFlatCell * longest * longest * longest) continue;
    // The normal of the plane: the largest of the corner triangles' normals.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& n : {Eigen::Vector3d((p1 - p0).cross(p2 - p0)), Eigen::Vector3d((p1 - p0).cross(p3 - p0)),
                                     Eigen::Vector3d((p2 - p0).cross(p3 - p0))})
      if (n.norm() > normal.norm()) normal = n;
    if (normal.norm() == 0) continue;
    normal.normalize();
    const Eigen::Vector3d centre = 0.25 * (p0 + p1 + p2 + p3);
    for (const double height : {kAbove, -kBelow}) {
      const Eigen::Vector3d q = centre + reach * height * longest * normal;
      xyz.insert(xyz.end(), {q(0), q(1), q(2)});
    }
  }
  return Eigen::Map<const PointMatrix>(xyz.data(), static_cast<Index>(xyz.size() / 3), 3);
}

RefinedCells split_chords(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                          const SimplexMatrix& constraints, const SignedDistance& own) {
  const Index n = static_cast<Index>(points.rows());
  std::vector<Tets::Simplex> simplices(static_cast<size_t>(cells.rows()));
  for (Index c = 0; c < cells.rows(); ++c) simplices[c] = {cells(c, 0), cells(c, 1), cells(c, 2), cells(c, 3)};
  Tets tets(std::move(simplices), n);
  std::unordered_set<std::uint64_t> surface_edges;
  std::set<std::array<Index, 3>> surface_faces;
  for (Index f = 0; f < constraints.rows(); ++f) {
    std::array<Index, 3> t{constraints(f, 0), constraints(f, 1), constraints(f, 2)};
    std::sort(t.begin(), t.end());
    surface_faces.insert(t);
    for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(t[k], t[(k + 1) % 3]));
  }
  auto zero = [&](Index v) { return v < n && on_surface[v]; };
  RefinedCells out;
  std::vector<Eigen::RowVector3d> added;
  auto position = [&](Index v) -> Eigen::RowVector3d { return v < n ? Eigen::RowVector3d(points.row(v)) : added[v - n]; };
  for (const int count : {2, 3, 4})
    for (const auto& chord : chords_of(tets.live(), count, zero, surface_edges, surface_faces)) {
      Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
      double longest = 0;
      for (const Index v : chord) {
        centre += position(v);
        for (const Index w : chord) longest = std::max(longest, (position(v) - position(w)).norm());
      }
      centre /= static_cast<double>(chord.size());
      const double d = own.distances(centre).value();
      if (d >= 0) {
        ++out.outside_chords;  // outside at the collar too: harmless (morph_field.hpp)
      } else if (std::abs(d) <= kFlatChord * longest) {
        ++out.flat_chords;
      } else {
        tets.split(chord.data(), static_cast<int>(chord.size()), n + static_cast<Index>(added.size()));
        added.push_back(centre);
        out.splits.push_back(chord);
        out.shares.emplace_back(chord.size(), 1.0 / static_cast<double>(chord.size()));
      }
    }
  const auto live = tets.live();
  out.cells.resize(static_cast<Index>(live.size()), 4);
  for (size_t c = 0; c < live.size(); ++c)
    for (int k = 0; k < 4; ++k) out.cells(static_cast<Index>(c), k) = live[c][k];
  out.new_points.resize(static_cast<Index>(added.size()), 3);
  for (size_t j = 0; j < added.size(); ++j) out.new_points.row(static_cast<Index>(j)) = added[j];
  return out;
}

namespace {

// The edges of `tets` from a point of the input to one off it, no shorter
// than `shortest`, where the blend at one of `weights` changes sign along
// them or both ends are within half the edge of zero: where the zero set
// runs at one of those layers, in the tets the input's faces bound. Edges
// in `seen` are passed over, and those looked at are added to it: whether
// an edge is one of these depends only on its ends.
std::vector<std::array<Index, 2>> edges_off_input_near_zero(const Tets& tets, const std::vector<Eigen::RowVector3d>& position,
                                                            const std::function<bool(Index)>& on_input,
                                                            const std::vector<double>& weights,
                                                            const EndDistances& distances, double shortest,
                                                            std::unordered_set<std::uint64_t>& seen) {
  std::vector<std::array<Index, 2>> out;
  for (const auto& tet : tets.live())
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Index u = tet[a], v = tet[b];
        if (on_input(u) == on_input(v) || !seen.insert(edge_key(u, v)).second) continue;
        const double length = (position[u] - position[v]).norm();
        if (length < shortest) continue;
        for (const double w : weights) {
          const double pu = distances.blend(u, w), pv = distances.blend(v, w);
          if ((pu < 0) != (pv < 0) || (std::abs(pu) < 0.5 * length && std::abs(pv) < 0.5 * length)) {
            out.push_back({u, v});
            break;
          }
        }
      }
  return out;
}

}  // namespace

Index split_curved_edges(RefinedCells& refined, const PointMatrix& points, const std::vector<bool>& on_surface,
                         const std::vector<double>& weights, const std::vector<double>& slaved,
                         const SignedDistance& dS, const SignedDistance& dT, EndDistances& distances, double tolerance,
                         double shortest, int rounds) {
  const Index n = static_cast<Index>(points.rows());
  const Index before = n + refined.new_points.rows();
  if (distances.s.size() != before || distances.t.size() != before)
    fail<InputError>("split_curved_edges needs the distances at all ", before, " points, got ", distances.s.size());
  std::vector<Tets::Simplex> simplices(static_cast<size_t>(refined.cells.rows()));
  for (Index c = 0; c < refined.cells.rows(); ++c)
    simplices[c] = {refined.cells(c, 0), refined.cells(c, 1), refined.cells(c, 2), refined.cells(c, 3)};
  Tets tets(std::move(simplices), before);
  std::vector<Eigen::RowVector3d> position;
  for (Index v = 0; v < n; ++v) position.push_back(points.row(v));
  for (Index j = 0; j < refined.new_points.rows(); ++j) position.push_back(refined.new_points.row(j));
  const std::function<bool(Index)> on_input = [&](Index v) { return v < n && on_surface[v]; };
  // The two diagonals of a parallelogram (a flat cell) share their middle:
  // a middle is not added where a point is already (but for rounding).
  double extent = 0;
  for (Index v = 0; v < n; ++v) extent = std::max(extent, points.row(v).cwiseAbs().maxCoeff());
  PointGrid taken(kCoincidentMiddle * std::max(extent, 1e-300));
  for (size_t v = 0; v < position.size(); ++v) taken.add(position[v].transpose(), static_cast<Index>(v));
  Index count = before;
  // An edge's judgement (near the zero set, curved, keeping its sign, its
  // middle free) depends only on its ends and the points taken, which only
  // grow: an edge left whole in one round stays whole, and each round looks
  // only at the edges the splits before it made.
  std::unordered_set<std::uint64_t> judged;
  for (int round = 0; round < rounds; ++round) {
    const auto edges = edges_off_input_near_zero(tets, position, on_input, weights, distances, shortest, judged);
    PointMatrix middles(static_cast<Index>(edges.size()), 3);
    for (size_t e = 0; e < edges.size(); ++e)
      middles.row(static_cast<Index>(e)) = 0.5 * (position[edges[e][0]] + position[edges[e][1]]);
    const Eigen::VectorXd ms = dS.distances(middles), mt = dT.distances(middles);
    const Index split_before = count;
    for (size_t e = 0; e < edges.size(); ++e) {
      const auto [u, v] = edges[e];
      const Index r = static_cast<Index>(e);
      auto mean = [&](double w) {
        return 0.5 * (distances.blend(u, w) + distances.blend(v, w));
      };
      bool curved = false, keeps_sign = true;
      for (const double w : weights) curved = curved || std::abs(distances.blend(ms(r), mt(r), w) - mean(w)) > tolerance;
      for (const auto* layers : {&weights, &slaved})
        for (const double w : *layers) keeps_sign = keeps_sign && (distances.blend(ms(r), mt(r), w) < 0) == (mean(w) < 0);
      if (!curved || !keeps_sign) continue;
      bool coincides = false;
      taken.near(middles.row(r).transpose(), [&](Index, double) { coincides = true; });
      if (coincides) continue;
      taken.add(middles.row(r).transpose(), count);
      const Index edge[2] = {u, v};
      tets.split(edge, 2, count++);
      position.push_back(middles.row(r));
      distances.s.conservativeResize(count), distances.t.conservativeResize(count);
      distances.s(count - 1) = ms(r), distances.t(count - 1) = mt(r);
      refined.splits.push_back({u, v});
      refined.shares.push_back({0.5, 0.5});
    }
    if (count == split_before) break;
  }
  refined.new_points.conservativeResize(count - n, 3);
  for (Index v = before; v < count; ++v) refined.new_points.row(v - n) = position[v];
  const auto live = tets.live();
  refined.cells.resize(static_cast<Index>(live.size()), 4);
  for (size_t c = 0; c < live.size(); ++c)
    for (int k = 0; k < 4; ++k) refined.cells(static_cast<Index>(c), k) = live[c][k];
  return count - before;
}

PointMatrix undersampled_chords(const SimplexMatrix& cells, const PointMatrix& points,
                                const std::vector<bool>& on_surface, const SimplexMatrix& constraints,
                                const SignedDistance& own, const SignedDistance& dS, const SignedDistance& dT,
                                const EndDistances& at_points, const std::vector<double>& weights, double spacing) {
  const RefinedCells refined = split_chords(cells, points, on_surface, constraints, own);
  const Index count = refined.new_points.rows();
  if (count == 0) return PointMatrix(0, 3);
  const Eigen::VectorXd ms = dS.distances(refined.new_points), mt = dT.distances(refined.new_points);
  const Eigen::VectorXd depth = own.distances(refined.new_points).cwiseAbs();
  std::vector<double> xyz;
  for (Index j = 0; j < count; ++j) {
    const std::vector<Index>& corners = refined.splits[j];
    bool undersampled = false;
    for (const double w : weights) {
      double interpolated = 0;  // the unsplit cells' field at the chord's middle: the mean of its corners'
      for (const Index v : corners) interpolated += at_points.blend(v, w);
      interpolated /= static_cast<double>(corners.size());
      undersampled = undersampled || (interpolated < 0) != (at_points.blend(ms(j), mt(j), w) < 0);
    }
    if (!undersampled) continue;
    // Off the middle by a little, within its depth in the input: middles
    // of chords in one plane are coplanar with their corners.
    const double reach = kMiddleJitter * std::min(spacing, depth(j));
    for (int a = 0; a < 3; ++a) xyz.push_back(refined.new_points(j, a) + reach * jitter(j, a, 0x3d1e, 0));
  }
  return Eigen::Map<const PointMatrix>(xyz.data(), static_cast<Index>(xyz.size() / 3), 3);
}

std::vector<Simplex4> transition_slab(const SimplexMatrix& cells, const std::vector<std::vector<Index>>& splits,
                                      Index n, Index refined_count, bool refined_at_bottom, const double* rank) {
  // Local ids: the refined layer's points are 0..refined_count-1 (the first
  // n are the unrefined layer's too), the unrefined layer's are
  // refined_count + v.
  const Index refined = 0, plain = refined_count;
  std::vector<Simplex4> prisms(4 * static_cast<size_t>(cells.rows()));
  for (Index c = 0; c < cells.rows(); ++c)
    prism_simplices(cells.row(c).data(), refined_at_bottom ? refined : plain, refined_at_bottom ? plain : refined,
                    &prisms[4 * static_cast<size_t>(c)], rank);
  StellarComplex<5> slab(std::move(prisms), refined_count + n);
  for (size_t j = 0; j < splits.size(); ++j)
    slab.split(splits[j].data(), static_cast<int>(splits[j].size()), n + static_cast<Index>(j));
  return slab.live();
}

}  // namespace animanifold::morph_field
