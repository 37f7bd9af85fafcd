// Small shapes shared by the C++ tests.
#pragma once

#include "animanifold/stitch.hpp"

namespace animanifold::fixtures {

// A closed octahedron (vertices on the axes, outward faces): #V 6 by 3, #F 8 by 3.
inline void octahedron(PointMatrix& V, SimplexMatrix& F) {
  V.resize(6, 3);
  V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  F.resize(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
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

}  // namespace animanifold::fixtures
