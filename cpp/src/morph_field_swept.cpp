// The field method where both inputs are the same surface (morph_field.hpp).
#include "morph_field.hpp"

#include "animanifold/stitch.hpp"

#include <algorithm>
#include <array>
#include <map>

namespace animanifold {

namespace {

using Face = std::array<Index, 3>;

// The face from its least corner, its orientation kept.
Face from_least_corner(Face f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}

// Each of S's points' row in T where every one of them is a point of T (T's
// points distinct); empty otherwise.
IndexVector matching_points(const PointMatrix& VS, const PointMatrix& VT) {
  std::map<std::array<double, 3>, Index> in_target;
  for (Index v = 0; v < VT.rows(); ++v) in_target.emplace(std::array{VT(v, 0), VT(v, 1), VT(v, 2)}, v);
  if (static_cast<Index>(in_target.size()) != VT.rows()) return {};
  IndexVector to_target(VS.rows());
  for (Index v = 0; v < VS.rows(); ++v) {
    const auto found = in_target.find(std::array{VS(v, 0), VS(v, 1), VS(v, 2)});
    if (found == in_target.end()) return {};
    to_target[v] = found->second;
  }
  return to_target;
}

}  // namespace

std::optional<Complex> swept_when_same(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                                       const SimplexMatrix& FT, double t0, double t1) {
  if (VS.cols() != 3 || VS.rows() != VT.rows() || FS.rows() != FT.rows() || VS.rows() == 0) return std::nullopt;
  const IndexVector to_target = matching_points(VS, VT);
  if (to_target.size() == 0) return std::nullopt;
  std::vector<Face> source_faces, target_faces;
  for (Index f = 0; f < FS.rows(); ++f) {
    source_faces.push_back(from_least_corner({to_target[FS(f, 0)], to_target[FS(f, 1)], to_target[FS(f, 2)]}));
    target_faces.push_back(from_least_corner({FT(f, 0), FT(f, 1), FT(f, 2)}));
  }
  std::sort(source_faces.begin(), source_faces.end());
  std::sort(target_faces.begin(), target_faces.end());
  if (source_faces != target_faces) return std::nullopt;
  StitchInput sweep;
  sweep.frames.resize(2 * VS.rows(), 3);
  sweep.frames << VS, VS;
  sweep.faces = FS;
  sweep.times.resize(2);
  sweep.times << t0, t1;
  return stitch(sweep);
}

}  // namespace animanifold
