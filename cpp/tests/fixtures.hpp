// Small shapes and helpers shared by the C++ tests (cpp/tests and cpp/tests/internal).
#pragma once

#include "animanifold/errors.hpp"
#include "animanifold/stitch.hpp"

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace animanifold::fixtures {

// The message of the InputError that `call()` throws, or "(no InputError)":
// tests compare what a refusal names.
template <class Call>
std::string input_error_message(Call&& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

// Whether two compressed sparse matrices have the same size, pattern and
// values, bit for bit (thread-count tests).
template <class Sparse>
bool same_sparse_bits(const Sparse& a, const Sparse& b) {
  if (a.nonZeros() != b.nonZeros() || a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index o = 0; o <= a.outerSize(); ++o)
    if (a.outerIndexPtr()[o] != b.outerIndexPtr()[o]) return false;
  for (Eigen::Index e = 0; e < a.nonZeros(); ++e)
    if (a.innerIndexPtr()[e] != b.innerIndexPtr()[e] || a.valuePtr()[e] != b.valuePtr()[e]) return false;
  return true;
}

// A closed octahedron (vertices on the axes, outward faces): #V 6 by 3, #F 8 by 3.
inline void octahedron(PointMatrix& V, SimplexMatrix& F) {
  V.resize(6, 3);
  V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  F.resize(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
}

// Each face of (V, F) split into four at its edges' middles, `levels` times
// (the shape stays the same).
inline void subdivide(PointMatrix& V, SimplexMatrix& F, int levels) {
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<Index, Index>, Index> middle;
    std::vector<Eigen::RowVector3d> points;
    for (Index v = 0; v < V.rows(); ++v) points.push_back(V.row(v));
    auto at = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto [it, added] = middle.emplace(key, static_cast<Index>(points.size()));
      if (added) points.push_back(0.5 * (points[a] + points[b]));
      return it->second;
    };
    SimplexMatrix finer(4 * F.rows(), 3);
    for (Index f = 0; f < F.rows(); ++f) {
      const Index a = F(f, 0), b = F(f, 1), c = F(f, 2), ab = at(a, b), bc = at(b, c), ca = at(c, a);
      finer.middleRows(4 * f, 4) << a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca;
    }
    V.resize(static_cast<Index>(points.size()), 3);
    for (size_t r = 0; r < points.size(); ++r) V.row(static_cast<Index>(r)) = points[r];
    F = finer;
  }
}

// The octahedron through three keyframes: keyframe i is `scale[i]` times the
// octahedron moved by `offset[i]`, at `times`.
inline StitchInput octahedron_keyframes(const Eigen::Vector3d& times, const Eigen::Vector3d& scale,
                                        const Eigen::Matrix3d& offset) {
  PointMatrix base;
  StitchInput in;
  octahedron(base, in.faces);
  in.times = times;
  in.frames.resize(18, 3);
  for (int i = 0; i < 3; ++i)
    in.frames.middleRows(6 * i, 6) = (scale(i) * base).rowwise() + offset.row(i);
  return in;
}

// The octahedron through keyframes at 0, 0.4 and 1.5: growing by half, then
// back to its size moved by (1, 1, 0).
inline StitchInput octahedron_animation() {
  Eigen::Matrix3d offset;
  offset << 0, 0, 0, 0, 0, 0, 1, 1, 0;
  return octahedron_keyframes({0.0, 0.4, 1.5}, {1.0, 1.5, 1.0}, offset);
}

// Random points in R^4 on two planes t = 0 and t = 1, like a morph's fill.
inline PointMatrix two_planes(int per_plane, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  PointMatrix P(2 * per_plane, 4);
  for (int r = 0; r < 2 * per_plane; ++r) P.row(r) << g(rng), g(rng), g(rng), r < per_plane ? 0.0 : 1.0;
  return P;
}

// Point i of a #P by 3 matrix as a vector.
inline Eigen::Vector3d at(const PointMatrix& P, Index i) { return P.row(i).transpose(); }

// The normal of triangle t of P, as long as twice its area (not normalised).
inline Eigen::Vector3d normal(const PointMatrix& P, const std::array<Index, 3>& t) {
  return (at(P, t[1]) - at(P, t[0])).cross(at(P, t[2]) - at(P, t[0]));
}

}  // namespace animanifold::fixtures
