// Shared between hole_space.cpp (checks, dispatch, fast paths) and the CGAL
// halves hole_space_3d.cpp and hole_space_2d.cpp (each CGAL package is slow
// to compile, so each lives in its own translation unit).
#pragma once

#include "animanifold/errors.hpp"
#include "animanifold/hole_space.hpp"
#include "cgal_failures.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

namespace animanifold::holes {

// The CGAL halves construct exactly (Epeck) and round to doubles at the end.
using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;

// A lazy exact number rounds to the midpoint of its interval until its exact
// value has been needed, and to the exact value's rounding after: the same
// point could come out one ulp apart from one call to the next. Always
// round the exact value.
template <class Number>
double rounded(const Number& x) {
  return CGAL::to_double(CGAL::exact(x));
}

// One operand of a Boolean operation and how messages call it ("the frame").
struct Operand {
  const PointMatrix& V;
  const SimplexMatrix& F;
  const char* name;
};

enum class Operation { Intersection, Difference };

// The hole space is computed exactly, after quads of C that are planar up
// to rounding have been made to follow the hull's facets (hole_space_3d.cpp).
// When slivers of C's own concave triangulation touch one another along
// edges, so that the exact difference is not a manifold, it is computed again
// with every dent of C's triangulation between four hull vertices flipped
// away, and if it is still not a manifold, with the hull shrunk by this
// fraction about the centroid of its vertices: every sliver thinner than
// 2^-24 (6e-8) of the hull's size disappears, and real holes lose a layer
// about that thick under the hull.
inline constexpr double HULL_SHRINK = 1.0 / (1ull << 24);

// H_C = CH(C) \ C; both arrays already checked for shape and indices.
Solid hole_space_3d(const Operand& shape);
Solid hole_space_2d(const Operand& shape);

bool intersects_itself_3d(const Operand& shape);

// a ∩ b or a \ b into `out`. Returns false, leaving `out` untouched, when
// the two boundaries do not meet and neither solid contains the other (the
// intersection is then empty and the difference is `a`).
bool boolean_3d(Operation operation, const Operand& a, const Operand& b, Solid& out);
bool boolean_2d(Operation operation, const Operand& a, const Operand& b, Solid& out);

}  // namespace animanifold::holes
