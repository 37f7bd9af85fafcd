// Steps shared by frame and manifold subdivision (see subdivision_shared.hpp).
#include "subdivision_shared.hpp"

#include "animanifold/errors.hpp"

#include <cmath>

namespace animanifold::subdivision_detail {

PointMatrix pack_columns(const PointMatrix& points, const VertexAttributes& attributes) {
  const Eigen::Index D = points.cols();
  Eigen::Index C = D;
  for (const auto& [name, table] : attributes) C += table.cols();
  PointMatrix X(points.rows(), C);
  X.leftCols(D) = points;
  Eigen::Index c = D;
  for (const auto& [name, table] : attributes) {
    X.middleCols(c, table.cols()) = table;
    c += table.cols();
  }
  return X;
}

VertexAttributes unpack_columns(const PointMatrix& packed, Eigen::Index dims, const VertexAttributes& attributes) {
  VertexAttributes out;
  Eigen::Index c = dims;
  for (const auto& [name, table] : attributes) {
    out[name] = packed.middleCols(c, table.cols());
    c += table.cols();
  }
  return out;
}

SimplexAttributes inherit_rows(const SimplexAttributes& attributes, const IndexVector& parent) {
  SimplexAttributes out;
  for (const auto& [name, table] : attributes) {
    SimplexMatrix inherited(parent.size(), table.cols());
    for (Eigen::Index s = 0; s < parent.size(); ++s) inherited.row(s) = table.row(parent(s));
    out[name] = std::move(inherited);
  }
  return out;
}

IndexVector identity_parent(Index count) {
  IndexVector parent(count);
  for (Index i = 0; i < count; ++i) parent(i) = i;
  return parent;
}

template <class Attributes>
void check_attribute_rows(const Attributes& attributes, Index count, const char* kind, const char* element) {
  for (const auto& [name, table] : attributes)
    if (table.rows() != count)
      fail<InputError>(kind, " attribute '", name, "' has ", table.rows(), " rows for ", count, " ", element);
}
template void check_attribute_rows(const VertexAttributes&, Index, const char*, const char*);
template void check_attribute_rows(const SimplexAttributes&, Index, const char*, const char*);

void check_finite(const PointMatrix& points, const char* what) {
  for (Index v = 0; v < points.rows(); ++v)
    for (Eigen::Index c = 0; c < points.cols(); ++c)
      if (!std::isfinite(points(v, c))) fail<InputError>(what, " ", v, " has a non-finite coordinate");
}

void normalize_rows(PointMatrix& rows) {
  for (Eigen::Index v = 0; v < rows.rows(); ++v) {
    const double length = rows.row(v).norm();
    if (length > 0) rows.row(v) /= length;
  }
}

bool creases_by_angle(double crease_angle_degrees) { return crease_angle_degrees > 0 && crease_angle_degrees < 180; }

double crease_cosine(double crease_angle_degrees) { return std::cos(crease_angle_degrees * M_PI / 180.0); }

}  // namespace animanifold::subdivision_detail
