#include "animanifold/slice.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/threads.hpp"
#include "slice_cut.hpp"
#include "slice_points.hpp"
#include "slice_stages.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace animanifold {

namespace {

// Items (points, faces) from which a loop over them runs on OpenMP's threads;
// each item writes only its own output, so threads do not change results.
constexpr Index kParallelItems = 16384;

void check_slice_request(const Complex& m, int axis, double value, const IntervalIndex* index) {
  const int D = m.ambient_dimension();
  const int k = m.vertices_per_simplex();
  if (k != D || (D != 3 && D != 4))
    fail<InputError>("slicing needs tets in R^4 or triangles in R^3; got ", k, "-vertex simplices in R^", D);
  if (axis < 0 || axis >= D) fail<InputError>("slicing axis ", axis, " is outside 0..", D - 1);
  if (!std::isfinite(value)) fail<InputError>("slicing value is not finite");
  if (index && (index->axis() != axis))
    fail<InputError>("interval index was built for axis ", index->axis(), ", not ", axis);
}

// The simplices a hyperplane may cut, found through the index or by a scan.
class Stabber {
 public:
  Stabber(const Complex& m, int axis, const IntervalIndex* index) : m_(m), axis_(axis), index_(index) {
    if (index) {
      lowest = index->lowest(), highest = index->highest();
    } else {
      lowest = m.V.rows() ? m.V.col(axis).minCoeff() : 0.0;
      highest = m.V.rows() ? m.V.col(axis).maxCoeff() : 0.0;
    }
  }

  // The simplices whose extent along the axis holds `at`, into `candidates`,
  // in the index's order; through the index, with some that miss it by a
  // float's rounding (exact() removes them; cutting skips them).
  void stab(double at, std::vector<Index>& candidates) const {
    candidates.clear();
    if (index_) {
      index_->stab_candidates(at, candidates);
      return;
    }
    const int k = m_.vertices_per_simplex();
    candidates.reserve(1024);
    for (Index s = 0; s < m_.S.rows(); ++s) {
      double low = m_.V(m_.S(s, 0), axis_), high = low;
      for (int c = 1; c < k; ++c) {
        const double x = m_.V(m_.S(s, c), axis_);
        low = std::min(low, x), high = std::max(high, x);
      }
      if (low <= at && at <= high) candidates.push_back(s);
    }
  }

  // Removes the candidates whose extent does not hold `at`.
  void exact(double at, std::vector<Index>& candidates) const {
    if (!index_) return;  // the scan is exact
    const int k = m_.vertices_per_simplex();
    std::erase_if(candidates, [&](Index s) {
      double low = m_.V(m_.S(s, 0), axis_), high = low;
      for (int c = 1; c < k; ++c) {
        const double x = m_.V(m_.S(s, c), axis_);
        low = std::min(low, x), high = std::max(high, x);
      }
      return !(low <= at && at <= high);
    });
  }

  // Whether a vertex may lie within `tolerance` of `at` (false only when none does).
  bool may_snap(double at, double tolerance) const {
    return !index_ || index_->has_vertex_value_near(at, tolerance);
  }

  double lowest, highest;

 private:
  const Complex& m_;
  int axis_;
  const IntervalIndex* index_;
};

// A value a rounding away from vertices (a frame's time computed as
// t0 + k·dt next to a keyframe, or a layer of a morph) is taken as theirs:
// cut a hair off them, edges from each vertex would give slice vertices
// of their own within an ulp of it, and faces between them that fold.
// Just outside the manifold's ends, the ends' own. Returns the value cut at,
// with `candidates` the simplices that may cut there.
double snapped_value(const Complex& m, int axis, double value, const Stabber& stabber,
                     std::vector<Index>& candidates) {
  const int k = m.vertices_per_simplex();
  const double snap = slice_points::snap_tolerance(stabber.lowest, stabber.highest);
  if (value < stabber.lowest && stabber.lowest - value <= snap) value = stabber.lowest;
  if (value > stabber.highest && value - stabber.highest <= snap) value = stabber.highest;
  stabber.stab(value, candidates);
  if (!stabber.may_snap(value, snap)) return value;  // the scan below would find nothing
  stabber.exact(value, candidates);
  double nearest = value, distance = std::numeric_limits<double>::infinity();
  for (const Index s : candidates)
    for (int c = 0; c < k; ++c) {
      const double x = m.V(m.S(s, c), axis), d = std::abs(x - value);
      if (d <= snap && d < distance) nearest = x, distance = d;
    }
  if (nearest != value) value = nearest, stabber.stab(value, candidates);
  return value;
}

// Inputs: m, axis; cut, the welded faces of a slice; with_attributes
// Outputs: the Slice without normals: the points the faces use, their edges,
//   coordinates and (with_attributes) interpolated attributes; the faces and
//   (with_attributes) their simplices' attributes
Slice frame_of_cuts(const Complex& m, int axis, slice_cut::CutFaces& cut, bool with_attributes) {
  // Only the cut points that corners of the frame use: on a vertex plane,
  // a simplex whose faces there are degenerate (or cancelled) registers its
  // corners too, and where the manifold holds copies of a vertex (split at a
  // UV seam) those copies would be left loose in the frame.
  std::vector<Index> kept;
  if (cut.on_vertices) kept = slice_cut::used_points(cut.corners, static_cast<Index>(cut.points.size()));
  const Index P = static_cast<Index>(cut.on_vertices ? kept.size() : cut.points.size());
  Slice out;
  out.vertex_edges.resize(P, 2);
  out.edge_parameter.resize(P);
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (P > kParallelItems)
  for (Index p = 0; p < P; ++p) {
    const slice_cut::Point& c = cut.points[cut.on_vertices ? kept[p] : p];
    out.vertex_edges(p, 0) = c.a, out.vertex_edges(p, 1) = c.b;
    out.edge_parameter(p) = c.s;
  }
  slice_points::interpolate_points(m, axis, out, with_attributes);

  const Index F = static_cast<Index>(cut.simplex.size());
  out.faces = Eigen::Map<const SimplexMatrix>(cut.corners.data(), F, cut.n);
  out.face_simplex = Eigen::Map<const IndexVector>(cut.simplex.data(), F);
  if (!with_attributes) return out;
  for (const auto& [name, table] : m.simplex_attributes) {
    SimplexMatrix values(F, table.cols());
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (F > kParallelItems)
    for (Index f = 0; f < F; ++f) values.row(f) = table.row(out.face_simplex(f));
    out.face_attributes[name] = std::move(values);
  }
  return out;
}

}  // namespace

namespace slice_points {

void interpolate_points(const Complex& m, int axis, Slice& out, bool with_attributes) {
  const int D = m.ambient_dimension();
  const Index P = out.vertex_edges.rows();
  const auto& edges = out.vertex_edges;
  const auto& s = out.edge_parameter;
  out.vertices.resize(P, D - 1);
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (P > kParallelItems)
  for (Index p = 0; p < P; ++p) {
    const Index a = edges(p, 0), b = edges(p, 1);
    for (int d = 0, o = 0; d < D; ++d) {
      if (d == axis) continue;
      // A vertex on the plane is copied, never interpolated: keyframes come back exactly.
      out.vertices(p, o++) = a == b ? m.V(a, d) : (1.0 - s(p)) * m.V(a, d) + s(p) * m.V(b, d);
    }
  }
  if (!with_attributes) return;
  for (const auto& [name, table] : m.vertex_attributes) {
    PointMatrix values(P, table.cols());
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (P > kParallelItems)
    for (Index p = 0; p < P; ++p) {
      const Index a = edges(p, 0), b = edges(p, 1);
      values.row(p) = a == b ? table.row(a) : ((1.0 - s(p)) * table.row(a) + s(p) * table.row(b)).eval();
    }
    out.vertex_attributes[name] = std::move(values);
  }
}

}  // namespace slice_points

namespace {

// slice() without the normals; the attributes only when with_attributes.
Slice slice_without_normals(const Complex& m, int axis, double value, const IntervalIndex* index, SliceStages* stages,
                            bool with_attributes) {
  check_slice_request(m, axis, value, index);
  const int D = m.ambient_dimension();
  StageClock clock(stages);
  const Stabber stabber(m, axis, index);
  std::vector<Index> candidates;
  value = snapped_value(m, axis, value, stabber, candidates);
  clock.lap(&SliceStages::stab);
  slice_cut::CutFaces cut = slice_cut::cut_and_weld(m, axis, value, value >= stabber.highest, candidates, stages);
  clock.restart();
  slice_cut::cancel_opposite_pairs(cut);
  Slice out = frame_of_cuts(m, axis, cut, with_attributes);

  // Dropping coordinate `axis` instead of the last one permutes the remaining
  // coordinates' orientation by (-1)^(D-1-axis): the table's faces would then
  // face inward, so they are turned over. Slices along time are never
  // turned, so keyframes keep their orientation.
  if ((D - 1 - axis) % 2 == 1) out.faces.col(0).swap(out.faces.col(1));
  clock.lap(&SliceStages::output);
  return out;
}

}  // namespace

Slice slice(const Complex& m, int axis, double value, const IntervalIndex* index, SliceStages* stages) {
  Slice out = slice_without_normals(m, axis, value, index, stages, true);
  StageClock clock(stages);
  out.normals = frame_vertex_normals_unchecked(out.vertices, out.faces);
  clock.lap(&SliceStages::normals);
  return out;
}

Slice slice_shape(const Complex& m, int axis, double value, const IntervalIndex* index) {
  return slice_without_normals(m, axis, value, index, nullptr, false);
}

}  // namespace animanifold

namespace animanifold {

Slicer::Slicer(std::shared_ptr<const Complex> manifold) : manifold_(std::move(manifold)) {
  if (!manifold_) fail<InputError>("Slicer needs a manifold");
  indices_.resize(manifold_->ambient_dimension());
  index_built_ = std::make_unique<std::once_flag[]>(indices_.size());
}

const IntervalIndex& Slicer::index(int axis) {
  if (axis < 0 || axis >= static_cast<int>(indices_.size()))
    fail<InputError>("slicing axis ", axis, " is outside 0..", indices_.size() - 1);
  // Threads slicing a fresh manifold at once (the bindings release the GIL)
  // would otherwise each build the index and replace one another's while in use.
  std::call_once(index_built_[axis], [&] {
    indices_[axis] = std::make_unique<IntervalIndex>(manifold_->V, manifold_->S, axis);
  });
  return *indices_[axis];
}

Slice Slicer::slice(int axis, double value, bool use_index, SliceStages* stages) {
  return animanifold::slice(*manifold_, axis, value, use_index ? &index(axis) : nullptr, stages);
}

Slice Slicer::slice_shape(int axis, double value) {
  return animanifold::slice_shape(*manifold_, axis, value, &index(axis));
}

}  // namespace animanifold
