// The Steiner points of a conforming fill nudged off their edges and faces,
// where that costs the fill no refined face (see morph_skeleton.hpp).
#include "animanifold/delaunay.hpp"
#include "morph_skeleton.hpp"
#include "animanifold/perturbation.hpp"

#include <vector>

namespace animanifold {

PointMatrix nudged_steiner_points(const ConformingDelaunay& c, Index first, double amount, Index& unnudged,
                                  const std::vector<bool>& stay) {
  const int d = static_cast<int>(c.points.cols());
  PointMatrix P = c.points;
  std::vector<bool> nudged(P.rows(), false);
  for (Index v = first; v < P.rows(); ++v) {
    if (static_cast<size_t>(v) < stay.size() && stay[v]) continue;
    // One coordinate after the other, each offset keyed by the point as far
    // as it has moved (as the morph always did: the same points, the same nudge).
    for (int k = 0; k < d; ++k) P(v, k) += amount * position_hash_offset(P.row(v).data(), d, k, 777);
    nudged[v] = true;
  }
  // The exact predicates in 3D (Qhull's roundoff would blame faces that are
  // there); in 2D Qhull, whose false alarms only keep more points in place.
  auto lost_faces = [&] {
    const DelaunayTriangulation dt = d == 3 ? delaunay_exact(P) : delaunay(P);
    return missing_facets(dt.simplices, c.constraints);
  };
  // Each pass puts back the nudged corners of the faces lost; the points as
  // the mesher left them lose none (the fill conforms), so it ends.
  for (IndexVector lost = lost_faces(); lost.size() > 0; lost = lost_faces()) {
    bool changed = false;
    for (const Index f : lost)
      for (int k = 0; k < c.constraints.cols(); ++k) {
        const Index v = c.constraints(f, k);
        if (!nudged[v]) continue;
        P.row(v) = c.points.row(v);
        nudged[v] = false;
        changed = true;
        ++unnudged;
      }
    if (!changed) break;  // lost with nothing nudged: the fill itself did not conform
  }
  return P;
}

}  // namespace animanifold
