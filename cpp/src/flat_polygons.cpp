#include "animanifold/flat_polygons.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace animanifold {

namespace {

using Vec3 = Eigen::Vector3d;

// How far from a face's plane the corners of a polygon may lie, relative to
// the size: far below the 1e-9 within which the morph's ends must reproduce
// the input (a fan's centre lies as far off as its corners do), far above
// the rounding of float32 coordinates rotated in doubles (1e-16).
constexpr double kFlat = 1e-10;

Vec3 corner(const PointMatrix& V, Index v) { return V.row(v).transpose(); }

std::uint64_t edge_key(Index a, Index b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The boundary of the faces `region` (ids into F) as one loop of vertices in
// the faces' direction, or empty where it is not one simple loop around a
// disc with no vertex inside.
std::vector<Index> boundary_loop(const SimplexMatrix& F, const std::vector<Index>& region,
                                 const std::vector<bool>& in_region,
                                 const std::unordered_map<std::uint64_t, Index>& face_of_edge) {
  std::unordered_map<Index, Index> next;
  std::vector<Index> vertices;
  for (const Index f : region)
    for (int c = 0; c < 3; ++c) {
      const Index a = F(f, c), b = F(f, (c + 1) % 3);
      vertices.push_back(a);
      const auto twin = face_of_edge.find(edge_key(b, a));
      if (twin != face_of_edge.end() && in_region[twin->second]) continue;
      if (!next.emplace(a, b).second) return {};  // the boundary touches itself at a
    }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  // A triangulated disc with b boundary vertices and none inside has b - 2 faces.
  if (next.size() != vertices.size() || region.size() + 2 != next.size()) return {};
  std::vector<Index> loop{next.begin()->first};
  while (loop.size() <= next.size()) {
    const Index after = next.at(loop.back());
    if (after == loop.front()) break;
    loop.push_back(after);
  }
  return loop.size() == next.size() ? loop : std::vector<Index>{};
}

// The mean of the corners of `loop` if the polygon is strictly convex about
// its own normal (no straight corner: a voxel model's row of squares is a
// flat polygon too, which a fan from its centre would only cut into slivers)
// and every triangle of the fan from the mean has a clear area; nothing
// otherwise.
bool fan_centre(const PointMatrix& V, const std::vector<Index>& loop, Vec3& centre) {
  const size_t n = loop.size();
  Vec3 normal = Vec3::Zero();  // Newell's: twice the polygon's area along its normal
  centre.setZero();
  for (size_t i = 0; i < n; ++i) {
    normal += corner(V, loop[i]).cross(corner(V, loop[(i + 1) % n]));
    centre += corner(V, loop[i]);
  }
  centre /= static_cast<double>(n);
  if (!(normal.norm() > 0)) return false;
  normal.normalize();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 before = corner(V, loop[(i + n - 1) % n]), at = corner(V, loop[i]), after = corner(V, loop[(i + 1) % n]);
    const Vec3 in = at - before, out = after - at;
    if (!(in.cross(out).dot(normal) > 1e-9 * in.norm() * out.norm())) return false;  // a reflex or straight corner
    const Vec3 a = at - centre, b = after - centre;
    if (!(a.cross(b).dot(normal) > 1e-9 * a.norm() * b.norm())) return false;  // a sliver of the fan
  }
  return true;
}

}  // namespace

FannedMesh fan_flat_polygons(const PointMatrix& V, const SimplexMatrix& F, Index min_corners) {
  FannedMesh out;
  out.V = V;
  out.F = F;
  if (V.cols() != 3 || F.cols() != 3 || F.rows() == 0) return out;
  const double tolerance = kFlat * (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  std::unordered_map<std::uint64_t, Index> face_of_edge;
  face_of_edge.reserve(3 * static_cast<size_t>(F.rows()));
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) face_of_edge.emplace(edge_key(F(f, c), F(f, (c + 1) % 3)), f);
  std::vector<Vec3> unit_normal(static_cast<size_t>(F.rows()));
  for (Index f = 0; f < F.rows(); ++f) {
    const Vec3 n = (corner(V, F(f, 1)) - corner(V, F(f, 0))).cross(corner(V, F(f, 2)) - corner(V, F(f, 0)));
    unit_normal[f] = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  }

  std::vector<bool> grouped(static_cast<size_t>(F.rows()), false), fanned(static_cast<size_t>(F.rows()), false);
  std::vector<bool> in_region(static_cast<size_t>(F.rows()), false);
  std::vector<Vec3> centres;
  std::vector<std::vector<Index>> loops;
  for (Index seed = 0; seed < F.rows(); ++seed) {
    if (grouped[seed] || unit_normal[seed].isZero()) continue;
    // The faces edge-connected to the seed that face its way in its plane
    // (measured against the seed's plane, so that a gently curved surface
    // does not pass for flat one small bend at a time).
    const Vec3 normal = unit_normal[seed], origin = corner(V, F(seed, 0));
    std::vector<Index> region{seed};
    grouped[seed] = in_region[seed] = true;
    for (size_t i = 0; i < region.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const auto twin = face_of_edge.find(edge_key(F(region[i], (c + 1) % 3), F(region[i], c)));
        if (twin == face_of_edge.end()) continue;
        const Index g = twin->second;
        if (grouped[g] || unit_normal[g].dot(normal) < 0.5) continue;
        bool flat = true;
        for (int k = 0; k < 3; ++k) flat = flat && std::abs(normal.dot(corner(V, F(g, k)) - origin)) <= tolerance;
        if (!flat) continue;
        grouped[g] = in_region[g] = true;
        region.push_back(g);
      }
    if (static_cast<Index>(region.size()) + 2 >= min_corners) {
      std::vector<Index> loop = boundary_loop(F, region, in_region, face_of_edge);
      Vec3 centre;
      if (!loop.empty() && fan_centre(V, loop, centre)) {
        for (const Index f : region) fanned[f] = true;
        centres.push_back(centre);
        loops.push_back(std::move(loop));
      }
    }
    for (const Index f : region) in_region[f] = false;
  }
  if (loops.empty()) return out;

  out.polygons = static_cast<Index>(loops.size());
  out.V.resize(V.rows() + out.polygons, 3);
  out.V.topRows(V.rows()) = V;
  Index fan_faces = 0;
  for (size_t p = 0; p < loops.size(); ++p) {
    out.V.row(V.rows() + static_cast<Index>(p)) = centres[p].transpose();
    fan_faces += static_cast<Index>(loops[p].size());
  }
  const Index kept = static_cast<Index>(std::count(fanned.begin(), fanned.end(), false));
  out.F.resize(kept + fan_faces, 3);
  Index row = 0;
  for (Index f = 0; f < F.rows(); ++f)
    if (!fanned[f]) out.F.row(row++) = F.row(f);
  for (size_t p = 0; p < loops.size(); ++p) {
    const std::vector<Index>& loop = loops[p];
    const Index centre = V.rows() + static_cast<Index>(p);
    for (size_t i = 0; i < loop.size(); ++i) out.F.row(row++) << loop[i], loop[(i + 1) % loop.size()], centre;
  }
  return out;
}

}  // namespace animanifold
