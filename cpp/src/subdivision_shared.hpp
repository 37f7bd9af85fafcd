// Steps shared by the subdivision of frames (frame_subdivision.cpp) and of
// manifolds (subdivide.cpp): attributes carried through the stencils with
// the points, attributes inherited by children from their parents, and the
// input checks all of them make (not a public header).
#pragma once

#include "animanifold/types.hpp"
#include "animanifold/validation.hpp"

#include <string>

namespace animanifold::subdivision_detail {

// The points' columns, then every attribute's in the map's order: one matrix
// the stencils average at once, so attributes are refined exactly like the points.
PointMatrix pack_columns(const PointMatrix& points, const VertexAttributes& attributes);

// The attributes of `attributes`' names and widths, read back out of a
// matrix packed by pack_columns with `dims` point columns.
VertexAttributes unpack_columns(const PointMatrix& packed, Eigen::Index dims, const VertexAttributes& attributes);

// Per child simplex, the row of its parent (parent[child]) in every table.
SimplexAttributes inherit_rows(const SimplexAttributes& attributes, const IndexVector& parent);

// 0, 1, ..., count - 1: every element its own parent.
IndexVector identity_parent(Index count);

// Throws InputError unless every table has `count` rows; `kind` and `element`
// name them in the message ("vertex", "vertices").
template <class Attributes>
void check_attribute_rows(const Attributes& attributes, Index count, const char* kind, const char* element);

// Throws InputError naming the first point (`what` and its row) with a non-finite coordinate.
void check_finite(const PointMatrix& points, const char* what);

// Scales every non-zero row to unit length.
void normalize_rows(PointMatrix& rows);

// Whether the crease angle (degrees) makes any turn sharp, and the cosine
// below which the angle between two directions counts as a crease.
bool creases_by_angle(double crease_angle_degrees);
double crease_cosine(double crease_angle_degrees);

}  // namespace animanifold::subdivision_detail
