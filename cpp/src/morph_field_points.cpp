// Free points and the conforming ends of the field method (morph_field_internal.hpp).
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/isolated.hpp"
#include "animanifold/threads.hpp"
#include "morph_field_internal.hpp"
#include "point_grid.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <system_error>

namespace animanifold::morph_field {

namespace {

// The box around both inputs, as a share of their size on each side: the
// field is positive well inside it, so the zero set never meets its sides.
constexpr double kBoxPad = 0.15;
// Free points keep this many circumradii of the nearest input faces from
// the input (a point inside a face's diametral sphere would make the
// conforming mesher split that face).
constexpr double kClearance = 1.1;
// The lattice's points keep only this many lattice spacings from faces whose
// clearance would be more than kCapBeyond spacings: beside faces that much
// larger than the lattice (a cylinder's sides, a cube's) the clearance would
// leave a void as wide as the face, where the field is sampled only by the
// face's corners and points far off it, and the frames leaving the face come
// apart in shreds (Blender's cylinder into its torus). The mesher splits such
// faces instead (Steiner points on them, reported; the end frame is still the
// input). Faces up to a few spacings keep their clearance, and the end frame
// its triangles.
constexpr double kClearanceCap = 1.25;
constexpr double kCapBeyond = 4.0;
// The surface shell's points sit this many circumradii off the input,
// jittered by this share of one.
constexpr double kShell = 1.3;
constexpr double kShellJitter = 0.2;
// Outside the band the surface sweeps, one lattice point in kCoarse^3 is kept
// (space is filled, not resolved, there).
constexpr int kCoarse = 3;
// Points of the two ends this share of the size apart are one point rounded
// two ways (share_coincident_points).
constexpr double kCoincidentShare = 1e-12;

// Whether `p` (the query's row in `projection`) is clear of the surface's
// faces nearest to it: kClearance circumradii, or `cap` where that is more
// than `cap_beyond`.
bool clear_of(const SurfaceProjection& projection, Index row, const SimplexMatrix& F, const Eigen::VectorXd& radius,
              double cap = std::numeric_limits<double>::infinity(), double cap_beyond = 0.0) {
  const Index f = projection.face(row);
  const double clearance = kClearance * std::max({radius(F(f, 0)), radius(F(f, 1)), radius(F(f, 2))});
  return std::abs(projection.distance(row)) >= (clearance > cap_beyond ? std::min(cap, clearance) : clearance);
}

}  // namespace

std::vector<bool> clear_of_surface(const PointMatrix& points, const PointMatrix& V, const SimplexMatrix& F,
                                   const SignedDistance& d) {
  const Eigen::VectorXd radius = vertex_circumradius(V, F);
  const SurfaceProjection p = d(points);
  std::vector<bool> clear(points.rows());
  for (Index r = 0; r < points.rows(); ++r) clear[r] = clear_of(p, r, F, radius);
  return clear;
}


double jitter(std::int64_t i, std::int64_t j, std::int64_t k, int axis) {
  std::uint64_t h = 1469598103934665603ull;
  for (const std::int64_t x : {i, j, k, static_cast<std::int64_t>(axis)})
    h = (h ^ static_cast<std::uint64_t>(x)) * 1099511628211ull;
  h ^= h >> 29, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 32;
  return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53) - 0.5;
}

Eigen::VectorXd vertex_circumradius(const PointMatrix& V, const SimplexMatrix& F) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(V.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double area2 = (b - a).cross(c - a).norm();
    const double R = area2 > 0 ? (a - b).norm() * (b - c).norm() * (c - a).norm() / (2 * area2) : (b - a).norm();
    for (int k = 0; k < 3; ++k) r(F(f, k)) = std::max(r(F(f, k)), R);
  }
  return r;
}


double middle_widening(const Eigen::VectorXd& s, const Eigen::VectorXd& t) {
  const Index inside_S = (s.array() < 0).count(), inside_T = (t.array() < 0).count();
  if (std::min(inside_S, inside_T) == 0) return 0;
  std::vector<double> middle(static_cast<size_t>(s.size()));
  for (Index r = 0; r < s.size(); ++r) middle[static_cast<size_t>(r)] = 0.5 * (s(r) + t(r));
  std::sort(middle.begin(), middle.end());
  const double thinner = std::min(-s.minCoeff(), -t.minCoeff());
  // The valley's floor: half the gap between inputs apart.
  const double valley_floor = middle.front();
  if (valley_floor > kMiddleReach * thinner) return 0;
  // The widening that takes as many points inside the middle as the larger input holds.
  const double larger = middle[static_cast<size_t>(std::max(inside_S, inside_T) - 1)];
  return std::max(0.0, std::min(kMiddleDepth * thinner + valley_floor, larger));
}

Lattice lattice_points(const PointMatrix& VS, const SimplexMatrix& FS, const SignedDistance& dS, const PointMatrix& VT,
                       const SimplexMatrix& FT, const SignedDistance& dT, double spacing, double size) {
  Eigen::RowVector3d lo = VS.colwise().minCoeff().cwiseMin(VT.colwise().minCoeff());
  Eigen::RowVector3d hi = VS.colwise().maxCoeff().cwiseMax(VT.colwise().maxCoeff());
  lo.array() -= kBoxPad * size, hi.array() += kBoxPad * size;
  Lattice out;
  out.spacing = spacing;
  out.corners.resize(8, 3);
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a) out.corners(c, a) = (c >> a) & 1 ? hi(a) : lo(a);
  const Eigen::Array3i cells = ((hi - lo) / spacing).array().ceil().cast<int>().max(1);
  std::vector<double> xyz;
  std::vector<bool> coarse;
  for (int centre = 0; centre < 2; ++centre)
    for (int i = 0; i <= cells(0); ++i)
      for (int j = 0; j <= cells(1); ++j)
        for (int k = 0; k <= cells(2); ++k) {
          Eigen::RowVector3d p(i + 0.5 * centre, j + 0.5 * centre, k + 0.5 * centre);
          for (int a = 0; a < 3; ++a) p(a) += 0.1 * jitter(i, j, k, a + 3 * centre);
          p = lo + spacing * p;
          // Clear of the box's sides by half a cell: the corners are the hull.
          if (((p - lo).array() < 0.5 * spacing).any() || ((hi - p).array() < 0.5 * spacing).any()) continue;
          xyz.insert(xyz.end(), {p(0), p(1), p(2)});
          coarse.push_back(centre == 0 && i % kCoarse == 0 && j % kCoarse == 0 && k % kCoarse == 0);
        }
  const PointMatrix candidates = Eigen::Map<const PointMatrix>(xyz.data(), static_cast<Index>(coarse.size()), 3);
  const SurfaceProjection ps = dS(candidates), pt = dT(candidates);
  out.widening = middle_widening(ps.distance, pt.distance);
  const Eigen::VectorXd rS = vertex_circumradius(VS, FS), rT = vertex_circumradius(VT, FT);
  std::vector<Index> keep_source, keep_target;
  for (Index r = 0; r < candidates.rows(); ++r) {
    const double s = ps.distance(r), t = pt.distance(r);
    // Outside both, the widened blend reaches below zero only within the
    // widening of one input (middle_widening): the zero set sweeps there.
    const bool widened = out.widening > 0 && std::min(s, t) <= out.widening + 2 * spacing;
    const bool band = s * t <= 0 || std::min(std::abs(s), std::abs(t)) <= 2 * spacing || widened;
    if (!band && !coarse[r]) continue;
    const double cap = kClearanceCap * spacing, cap_beyond = kCapBeyond * spacing;
    if (clear_of(ps, r, FS, rS, cap, cap_beyond)) keep_source.push_back(r);
    if (clear_of(pt, r, FT, rT, cap, cap_beyond)) keep_target.push_back(r);
  }
  out.source = candidates(keep_source, Eigen::all);
  out.target = candidates(keep_target, Eigen::all);
  out.source_s = ps.distance(keep_source), out.source_t = pt.distance(keep_source);
  out.target_s = ps.distance(keep_target), out.target_t = pt.distance(keep_target);
  return out;
}

// ---------------------------------------------------------------- the ends


PointMatrix surface_shell(const PointMatrix& V, const SimplexMatrix& F, const SignedDistance& d) {
  const Eigen::VectorXd radius = vertex_circumradius(V, F);
  PointMatrix normal = PointMatrix::Zero(V.rows(), 3);
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);  // area-weighted
    for (int k = 0; k < 3; ++k) normal.row(F(f, k)) += n;
  }
  PointMatrix candidates(2 * V.rows(), 3);
  for (Index v = 0; v < V.rows(); ++v) {
    const double length = normal.row(v).norm();
    const Eigen::RowVector3d n = length > 0 ? Eigen::RowVector3d(normal.row(v) / length) : Eigen::RowVector3d::Zero();
    // Jittered along and across the normal: on a sphere the normals are radial
    // and two neighbours with their offsets would be four coplanar points, a
    // flat tet of the triangulation.
    for (int side = 0; side < 2; ++side) {
      Eigen::RowVector3d offset;
      for (int a = 0; a < 3; ++a) offset(a) = kShellJitter * jitter(v, side, a, 0x5e11);
      const double along = kShell * radius(v) * (1.0 + kShellJitter * jitter(v, side, 3, 0x5e11));
      candidates.row(2 * v + side) = V.row(v) + (side == 0 ? along : -along) * n + radius(v) * offset;
    }
  }
  const SurfaceProjection p = d(candidates);
  std::vector<Index> keep;
  for (Index r = 0; r < candidates.rows(); ++r) {
    const bool outside_wanted = r % 2 == 0;
    if ((p.distance(r) > 0) == outside_wanted && clear_of(p, r, F, radius)) keep.push_back(r);
  }
  return candidates(keep, Eigen::all);
}

EndMesh conform_end(const PointMatrix& V, const SimplexMatrix& F, const PointMatrix& free, const PointMatrix& corners,
                    const char* name, const std::function<void()>& while_meshing, double mesher_time_limit) {
  PointMatrix points(V.rows() + free.rows() + corners.rows(), 3);
  points << V, free, corners;
  ConformingDelaunay c;
  try {
    c = conforming_delaunay_3d(points, F, while_meshing, mesher_time_limit, /*mend_flat_cells=*/true);
  } catch (const Cancelled&) {
    throw;
  } catch (const TimeLimitError& e) {
    fail<TimeLimitError>("the ", name, " cannot be meshed: ", e.what());  // keeps its type: nothing retries it
  } catch (const std::exception& e) {
    fail<MeshingError>("the ", name, " cannot be meshed: ", e.what());
  }
  if (!c.is_delaunay)
    fail<MeshingError>("the ", name, "'s conforming tetrahedralization leaves ", c.non_delaunay_faces,
                             " of its faces non-Delaunay (TetGen could not conform)");
  EndMesh end;
  end.on_surface.assign(c.points.rows(), false);
  for (Index v = 0; v < V.rows(); ++v) end.on_surface[v] = true;
  for (Index f = 0; f < c.constraints.rows(); ++f)
    for (int k = 0; k < 3; ++k) end.on_surface[c.constraints(f, k)] = true;
  end.points = std::move(c.points);
  end.constraints = std::move(c.constraints);
  end.constraint_parent = std::move(c.constraint_parent);
  end.input_points = static_cast<Index>(V.rows());
  end.free_points = static_cast<Index>(free.rows());
  end.steiner_points = static_cast<Index>(end.points.rows() - points.rows());
  end.flat_cell_points = c.flat_cell_points, end.flat_cells = c.flat_cells;
  return end;
}

void side_by_side(const std::function<void(const std::function<void()>&)>& beside, const std::function<void()>& here,
                  const std::function<void()>& poll) {
  auto in_turn = [&] {
    beside(poll);
    here();
  };
  if (thread_count() < 2) return in_turn();
  std::atomic<bool> stop{false}, stopped{false};
  const std::function<void()> stop_poll = [&] {
    if (stop) stopped = true, throw Cancelled();
  };
  std::future<void> other;
  try {
    other = std::async(std::launch::async, [&] { beside(stop_poll); });
  } catch (const std::system_error&) {
    return in_turn();  // no thread to be had: the same work, in turn
  }
  std::exception_ptr failure;
  auto keep = [&](std::exception_ptr e) {  // the first failure here; a cancel stops beside()
    if (!failure) failure = e;
    try {
      std::rethrow_exception(e);
    } catch (const Cancelled&) {
      stop = true;
    } catch (...) {
    }
  };
  try {
    here();
  } catch (...) {
    keep(std::current_exception());
  }
  try {
    while (!stop && other.wait_for(std::chrono::duration<double>(kWaitTick)) != std::future_status::ready)
      if (poll) poll();
  } catch (...) {
    keep(std::current_exception());
  }
  try {
    other.get();
  } catch (...) {
    if (!stopped) throw;  // beside's own failure comes first
  }
  if (failure) std::rethrow_exception(failure);
}

namespace {

double size_of_points(const PointMatrix& P) {
  return P.rows() ? (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm() : 0.0;
}

// Pairs (row of A, row of B) of distinct points at most `tolerance` apart.
std::vector<std::array<Index, 2>> nearly_coincident(const PointMatrix& A, const PointMatrix& B, double tolerance) {
  PointGrid grid(tolerance);
  for (Index r = 0; r < A.rows(); ++r) grid.add(A.row(r).transpose(), r);
  std::vector<std::array<Index, 2>> pairs;
  for (Index r = 0; r < B.rows(); ++r)
    grid.near(B.row(r).transpose(), [&](Index a, double distance) {
      if (distance > 0) pairs.push_back({a, r});
    });
  return pairs;
}

// Whether `end` still conforms to its input with its points moved as `moves`
// says (row, position), Theorem 5.2.1's check on the Delaunay triangulation
// the fill's end facet will be.
bool conforms_with(const EndMesh& end, const std::vector<std::pair<Index, Eigen::RowVector3d>>& moves) {
  if (moves.empty()) return true;
  PointMatrix points = end.points;
  for (const auto& [row, to] : moves) points.row(row) = to;
  return missing_facets(delaunay_exact(points).simplices, end.constraints).size() == 0;
}

}  // namespace

Index share_coincident_points(EndMesh& source, EndMesh& target) {
  const double size = std::max(size_of_points(source.points), size_of_points(target.points));
  const auto pairs = nearly_coincident(source.points, target.points, kCoincidentShare * size);
  // Per direction, each end's moves: one end's point onto the other's, or
  // the other way where it is an input vertex (two input vertices stay).
  for (const bool onto_source : {true, false}) {
    std::vector<std::pair<Index, Eigen::RowVector3d>> source_moves, target_moves;
    Index moved = 0;
    for (const auto& [s, t] : pairs) {
      const bool s_fixed = s < source.input_points, t_fixed = t < target.input_points;
      if (s_fixed && t_fixed) continue;
      ++moved;
      if (onto_source ? !t_fixed : s_fixed) target_moves.emplace_back(t, source.points.row(s));
      else source_moves.emplace_back(s, target.points.row(t));
    }
    if (!conforms_with(source, source_moves) || !conforms_with(target, target_moves)) continue;
    for (const auto& [row, to] : source_moves) source.points.row(row) = to;
    for (const auto& [row, to] : target_moves) target.points.row(row) = to;
    return moved;
  }
  return 0;
}

std::array<EndMesh, 2> conform_ends(const EndInput& source, const EndInput& target, const PointMatrix& corners,
                                    const std::function<void()>& while_meshing, double mesher_time_limit) {
  std::array<EndMesh, 2> ends;
  side_by_side(
      [&](const std::function<void()>& poll) {
        ends[0] = conform_end(source.V, source.F, source.free, corners, "source", poll, mesher_time_limit);
      },
      [&] { ends[1] = conform_end(target.V, target.F, target.free, corners, "target", while_meshing, mesher_time_limit); },
      while_meshing);
  return ends;
}

}  // namespace animanifold::morph_field
