#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/validation.hpp"
#include "slice_points.hpp"

#include <cmath>

namespace animanifold {

namespace {

// Per slice vertex p on edge (a, b): (table(b) - table(a)) * inverse_span(p),
// the rate at which a quantity interpolated along the edge changes with the value.
PointMatrix edge_rates(const PointMatrix& table, const SimplexMatrix& edges, const Eigen::VectorXd& inverse_span) {
  PointMatrix rates(edges.rows(), table.cols());
  for (Index p = 0; p < edges.rows(); ++p)
    rates.row(p) = (table.row(edges(p, 1)) - table.row(edges(p, 0))) * inverse_span(p);
  return rates;
}

}  // namespace

IntervalFrame Slicer::interval_frame(int axis, double value) {
  if (!std::isfinite(value)) fail<InputError>("slicing value is not finite");
  const IntervalIndex& idx = index(axis);
  const auto interval = idx.topology_interval(value);
  if (!interval)
    fail<InputError>("the slice at ", value, " along axis ", axis,
                     " has no topology interval: it lies on a vertex coordinate or outside the manifold, "
                     "where the faces change");
  const Complex& m = *manifold_;
  IntervalFrame out{axis, value, animanifold::slice(m, axis, value, &idx), interval->first, interval->second, {}, {}, {}};
  const SimplexMatrix& edges = out.slice.vertex_edges;
  const Index P = edges.rows();
  // Inside the interval no vertex lies on the plane (topology_interval keeps
  // values clear of slice()'s snap), so every slice vertex is on an edge whose
  // ends lie on either side: the span is never zero.
  out.parameter_rate.resize(P);
  for (Index p = 0; p < P; ++p) out.parameter_rate(p) = 1.0 / (m.V(edges(p, 1), axis) - m.V(edges(p, 0), axis));

  out.rate.resize(P, m.V.cols() - 1);
  for (Index p = 0; p < P; ++p)
    for (int d = 0, o = 0; d < m.V.cols(); ++d)
      if (d != axis) out.rate(p, o++) = (m.V(edges(p, 1), d) - m.V(edges(p, 0), d)) * out.parameter_rate(p);
  for (const auto& [name, table] : m.vertex_attributes)
    out.attribute_rates[name] = edge_rates(table, edges, out.parameter_rate);
  return out;
}

Slice Slicer::slice_in_interval(const IntervalFrame& frame, double value) {
  if (!std::isfinite(value)) fail<InputError>("slicing value is not finite");
  const auto interval = index(frame.axis).topology_interval(value);
  if (!interval || interval->first != frame.lo || interval->second != frame.hi)
    fail<InputError>("the slice at ", value, " along axis ", frame.axis, " is not in the topology interval (",
                     frame.lo, ", ", frame.hi, ") of the frame at ", frame.value, ": slice it afresh");
  const Complex& m = *manifold_;
  const Slice& cut = frame.slice;
  check_indices(cut.vertex_edges, m.V.rows(), "the frame's vertex edge");
  Slice out;
  out.vertex_edges = cut.vertex_edges;
  const Index P = out.vertex_edges.rows();
  out.edge_parameter.resize(P);
  for (Index p = 0; p < P; ++p) {
    const Index a = cut.vertex_edges(p, 0), b = cut.vertex_edges(p, 1);
    if (a >= b) fail<InputError>("vertex ", p, " of the frame at ", frame.value, " is not on an edge (", a, ", ", b,
                                 ") with a < b: not a frame inside a topology interval");
    // slice() computes its points' parameters so: the same arithmetic, the same bits.
    out.edge_parameter(p) = slice_points::edge_parameter(m.V, frame.axis, value, a, b);
  }
  slice_points::interpolate_points(m, frame.axis, out);
  out.faces = cut.faces;
  out.face_simplex = cut.face_simplex;
  out.face_attributes = cut.face_attributes;
  out.normals = frame_vertex_normals(out.vertices, out.faces);
  return out;
}

}  // namespace animanifold
