// OpenSubdiv refinement of frames (Loop / Catmull-Clark) with creases at
// sharp edges. See subdivide.hpp.
#include "animanifold/errors.hpp"
#include "animanifold/memory_estimates.hpp"
#include "animanifold/subdivide.hpp"
#include "animanifold/threads.hpp"
#include "subdivision_shared.hpp"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/sdc/crease.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>

namespace animanifold {

FrameScheme parse_frame_scheme(const std::string& name) {
  return parse_name(name, kFrameSchemeNames, "frame subdivision scheme");
}

namespace {

using namespace OpenSubdiv;
using namespace subdivision_detail;

// OpenSubdiv reports topology problems through a global callback; keep the
// last message of this thread so the exception can quote it.
thread_local std::string osd_last_error;
void record_error(Far::ErrorType, const char* message) { osd_last_error = message ? message : ""; }
void install_error_callback() {
  static std::once_flag once;
  std::call_once(once, [] { Far::SetErrorCallback(record_error); });
}

struct Point3 {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point3& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
};

struct Scalar {
  double v;
  void Clear() { v = 0; }
  void AddWithWeight(const Scalar& s, double w) { v += w * s.v; }
};

Eigen::Vector3d face_normal(const PointMatrix& V, const Index* f, int n);

// Every face's Newell normal, each into its own entry (the same for any thread count).
std::vector<Eigen::Vector3d> face_normals(const PointMatrix& vertices, const SimplexMatrix& faces) {
  const int n = static_cast<int>(faces.cols());
  std::vector<Eigen::Vector3d> normals(faces.rows());
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index f = 0; f < faces.rows(); ++f) normals[f] = face_normal(vertices, faces.row(f).data(), n);
  return normals;
}

Eigen::Vector3d face_normal(const PointMatrix& V, const Index* f, int n) {
  // Newell's normal: exact for planar polygons, a fair average otherwise.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d a = V.row(f[i]).transpose(), b = V.row(f[(i + 1) % n]).transpose();
    normal += (a - b).cross(a + b) * 0.5;
  }
  return normal;
}

void check_frame_input(const PointMatrix& vertices, const SimplexMatrix& faces, const FrameSubdivisionOptions& options,
                       const VertexAttributes& vertex_attributes, const SimplexAttributes& face_attributes) {
  const Index nV = static_cast<Index>(vertices.rows());
  const Index nF = static_cast<Index>(faces.rows());
  const int n = static_cast<int>(faces.cols());
  if (vertices.cols() != 3) fail<InputError>("frame vertices must be #V by 3, got ", vertices.cols(), " columns");
  if (n != 3 && n != 4) fail<InputError>("frame faces must be triangles or quads, got ", n, " vertices per face");
  if (options.scheme == FrameScheme::Loop && n != 3)
    fail<InputError>("Loop subdivision needs triangles; use Catmull-Clark for quads");
  if (options.scheme == FrameScheme::BSpline)
    fail<InputError>("the bspline scheme subdivides polylines (subdivide_polyline), not surfaces");
  if (options.levels < 0 || options.levels > 8)
    fail<InputError>("frame subdivision levels must be in 0..8, got ", options.levels);
  check_finite(vertices, "frame vertex");
  for (Index f = 0; f < nF; ++f)
    for (int a = 0; a < n; ++a) {
      const Index v = faces(f, a);
      if (v < 0 || v >= nV) fail<InputError>("face ", f, " refers to vertex ", v, ", outside 0..", nV - 1);
      for (int b = a + 1; b < n; ++b)
        if (faces(f, b) == v) fail<InputError>("face ", f, " repeats vertex ", v);
    }
  check_attribute_rows(vertex_attributes, nV, "vertex", "vertices");
  check_attribute_rows(face_attributes, nF, "face", "faces");
}

// An edge (smaller vertex first) of a face.
struct EdgeRecord {
  std::array<Index, 2> key;
  Index face;
};
bool edge_order(const EdgeRecord& x, const EdgeRecord& y) { return x.key != y.key ? x.key < y.key : x.face < y.face; }

// Every face's edges, sorted: an edge's faces are consecutive.
std::vector<EdgeRecord> sorted_edges(const SimplexMatrix& faces) {
  const int n = static_cast<int>(faces.cols());
  std::vector<EdgeRecord> records;
  records.reserve(static_cast<size_t>(faces.rows()) * n);
  for (Index f = 0; f < faces.rows(); ++f)
    for (int i = 0; i < n; ++i) {
      const Index a = faces(f, i), b = faces(f, (i + 1) % n);
      records.push_back({{std::min(a, b), std::max(a, b)}, f});
    }
  std::sort(records.begin(), records.end(), edge_order);
  return records;
}

// Edges between two faces whose normals turn by more than the crease angle.
void add_angle_creases(const PointMatrix& vertices, const SimplexMatrix& faces, const std::vector<EdgeRecord>& records,
                       double crease_angle_degrees, std::vector<std::array<Index, 2>>& creases) {
  const double cos_limit = crease_cosine(crease_angle_degrees);
  const std::vector<Eigen::Vector3d> normals = face_normals(vertices, faces);
  for (size_t begin = 0; begin < records.size();) {
    size_t end = begin + 1;
    while (end < records.size() && records[end].key == records[begin].key) ++end;
    if (end - begin == 2) {
      const Eigen::Vector3d& a = normals[records[begin].face];
      const Eigen::Vector3d& b = normals[records[begin + 1].face];
      const double la = a.norm(), lb = b.norm();
      if (la > 0 && lb > 0 && a.dot(b) / (la * lb) < cos_limit) creases.push_back(records[begin].key);
    }
    begin = end;
  }
}

// The given crease edges, each checked to be an edge of the frame.
void add_given_creases(const SimplexMatrix& crease_edges, const std::vector<EdgeRecord>& records,
                       std::vector<std::array<Index, 2>>& creases) {
  for (Eigen::Index c = 0; c < crease_edges.rows(); ++c) {
    if (crease_edges.cols() != 2) fail<InputError>("crease edges must be #C by 2 vertex pairs");
    const Index a = std::min(crease_edges(c, 0), crease_edges(c, 1));
    const Index b = std::max(crease_edges(c, 0), crease_edges(c, 1));
    const EdgeRecord probe{{a, b}, -1};
    const auto it = std::lower_bound(records.begin(), records.end(), probe, edge_order);
    if (it == records.end() || it->key != probe.key)
      fail<InputError>("crease edge ", c, " (", crease_edges(c, 0), ", ", crease_edges(c, 1),
                       ") is not an edge of the frame");
    creases.push_back({a, b});
  }
}

// The sharp edges as flat vertex pairs, sorted and each once (an edge found
// by angle may also be given).
std::vector<Index> crease_pairs(const PointMatrix& vertices, const SimplexMatrix& faces,
                                const FrameSubdivisionOptions& options) {
  const std::vector<EdgeRecord> records = sorted_edges(faces);
  std::vector<std::array<Index, 2>> creases;
  if (creases_by_angle(options.crease_angle_degrees) && options.levels > 0)
    add_angle_creases(vertices, faces, records, options.crease_angle_degrees, creases);
  add_given_creases(options.crease_edges, records, creases);
  std::sort(creases.begin(), creases.end());
  creases.erase(std::unique(creases.begin(), creases.end()), creases.end());
  std::vector<Index> pairs;
  for (const auto& p : creases) pairs.insert(pairs.end(), {p[0], p[1]});
  return pairs;
}

std::unique_ptr<Far::TopologyRefiner> refine_topology(const SimplexMatrix& faces, Index vertex_count,
                                                      const std::vector<Index>& creases,
                                                      const FrameSubdivisionOptions& options) {
  install_error_callback();
  osd_last_error.clear();
  const Index nF = static_cast<Index>(faces.rows());
  std::vector<int> verts_per_face(nF, static_cast<int>(faces.cols()));
  std::vector<float> crease_weights(creases.size() / 2, Sdc::Crease::SHARPNESS_INFINITE);
  Far::TopologyDescriptor desc;
  desc.numVertices = vertex_count;
  desc.numFaces = nF;
  desc.numVertsPerFace = verts_per_face.data();
  desc.vertIndicesPerFace = faces.data();
  desc.numCreases = static_cast<int>(crease_weights.size());
  desc.creaseVertexIndexPairs = creases.data();
  desc.creaseWeights = crease_weights.data();

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  const Sdc::SchemeType type = options.scheme == FrameScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(type, sdc)));
  if (!refiner)
    fail<InputError>("OpenSubdiv rejected the frame's topology", osd_last_error.empty() ? "" : ": ", osd_last_error);
  Far::TopologyRefiner::UniformOptions uniform(options.levels);
  uniform.fullTopologyInLastLevel = true;  // PrimvarRefiner::Limit needs it
  refiner->RefineUniform(uniform);
  return refiner;
}

// A vertex primvar through all levels, then to the limit when asked.
template <class Value>
void refine_vertex_values(const Far::TopologyRefiner& refiner, const Far::PrimvarRefinerReal<double>& primvar,
                          bool limit, std::vector<Value>& values) {
  const int L = refiner.GetMaxLevel();
  std::vector<Value> next;
  for (int level = 1; level <= L; ++level) {
    next.assign(refiner.GetLevel(level).GetNumVertices(), Value{});
    primvar.Interpolate(level, values, next);
    values.swap(next);
  }
  if (limit) {
    next.assign(refiner.GetLevel(L).GetNumVertices(), Value{});
    primvar.Limit(values, next);
    values.swap(next);
  }
}

PointMatrix refined_points(const Far::TopologyRefiner& refiner, const Far::PrimvarRefinerReal<double>& primvar,
                           const PointMatrix& vertices, bool limit) {
  std::vector<Point3> values(vertices.rows());
  for (Index v = 0; v < vertices.rows(); ++v)
    for (int c = 0; c < 3; ++c) values[v].p[c] = vertices(v, c);
  refine_vertex_values(refiner, primvar, limit, values);
  if (!osd_last_error.empty()) fail<InputError>("OpenSubdiv failed: ", osd_last_error);
  PointMatrix out(static_cast<Eigen::Index>(values.size()), 3);
  for (size_t v = 0; v < values.size(); ++v)
    for (int c = 0; c < 3; ++c) out(v, c) = values[v].p[c];
  return out;
}

VertexAttributes refined_attributes(const Far::TopologyRefiner& refiner, const Far::PrimvarRefinerReal<double>& primvar,
                                    const VertexAttributes& attributes, bool limit) {
  const int outV = refiner.GetLevel(refiner.GetMaxLevel()).GetNumVertices();
  VertexAttributes out;
  for (const auto& [name, table] : attributes) {
    PointMatrix refined(outV, table.cols());
    for (Eigen::Index c = 0; c < table.cols(); ++c) {
      std::vector<Scalar> values(table.rows());
      for (Index v = 0; v < table.rows(); ++v) values[v].v = table(v, c);
      refine_vertex_values(refiner, primvar, limit, values);
      for (int v = 0; v < outV; ++v) refined(v, c) = values[v].v;
    }
    out[name] = std::move(refined);
  }
  return out;
}

// Faces of the last level: Loop keeps triangles, Catmull-Clark makes quads.
SimplexMatrix refined_faces(const Far::TopologyRefiner& refiner, FrameScheme scheme) {
  const Far::TopologyLevel& last = refiner.GetLevel(refiner.GetMaxLevel());
  const int outF = last.GetNumFaces();
  const int outN = scheme == FrameScheme::Loop ? 3 : 4;
  SimplexMatrix faces(outF, outN);
  for (int f = 0; f < outF; ++f)
    if (last.GetFaceVertices(f).size() != outN)
      fail<InputError>("OpenSubdiv produced face ", f, " of ", last.GetFaceVertices(f).size(), " vertices");
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (int f = 0; f < outF; ++f) {
    const Far::ConstIndexArray fv = last.GetFaceVertices(f);
    for (int i = 0; i < outN; ++i) faces(f, i) = fv[i];
  }
  return faces;
}

IndexVector refined_face_parents(const Far::TopologyRefiner& refiner, const Far::PrimvarRefinerReal<double>& primvar,
                                 Index face_count) {
  std::vector<Index> src(face_count), dst;
  for (Index f = 0; f < face_count; ++f) src[f] = f;
  for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
    dst.assign(refiner.GetLevel(level).GetNumFaces(), 0);
    primvar.InterpolateFaceUniform(level, src, dst);
    src.swap(dst);
  }
  return Eigen::Map<const IndexVector>(src.data(), static_cast<Eigen::Index>(src.size()));
}

// Area-weighted unit normals.
PointMatrix vertex_normals(const PointMatrix& vertices, const SimplexMatrix& faces) {
  PointMatrix normals = PointMatrix::Zero(vertices.rows(), 3);
  const int n = static_cast<int>(faces.cols());
  // Face normals on all threads; their sums at the vertices in face order, so the bits never depend on the threads.
  const std::vector<Eigen::Vector3d> by_face = face_normals(vertices, faces);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int i = 0; i < n; ++i) normals.row(faces(f, i)) += by_face[f].transpose();
  normalize_rows(normals);
  return normals;
}

// Polyline vertex neighbours along the curve; -1 where the curve ends or branches.
void curve_neighbours(Index n, const SimplexMatrix& S, std::vector<Index>& prev, std::vector<Index>& next) {
  prev.assign(n, -1);
  next.assign(n, -1);
  std::vector<int> in(n, 0), out(n, 0);
  for (Eigen::Index e = 0; e < S.rows(); ++e) {
    next[S(e, 0)] = S(e, 1);
    prev[S(e, 1)] = S(e, 0);
    ++out[S(e, 0)];
    ++in[S(e, 1)];
  }
  for (Index v = 0; v < n; ++v)
    if (in[v] != 1 || out[v] != 1) prev[v] = next[v] = -1;
}

void check_polyline_input(const PointMatrix& vertices, const SimplexMatrix& segments,
                          const FrameSubdivisionOptions& options, const VertexAttributes& vertex_attributes,
                          const SimplexAttributes& segment_attributes) {
  const int D = static_cast<int>(vertices.cols());
  if (segments.cols() != 2) fail<InputError>("polyline segments must be #E by 2, got ", segments.cols(), " columns");
  if (D < 2) fail<InputError>("polyline points need at least 2 coordinates, got ", D);
  if (options.levels < 0 || options.levels > 16)
    fail<InputError>("polyline subdivision levels must be in 0..16, got ", options.levels);
  check_indices(segments, vertices.rows(), "segment");
  check_finite(vertices, "polyline vertex");
  check_attribute_rows(vertex_attributes, vertices.rows(), "vertex", "vertices");
  check_attribute_rows(segment_attributes, segments.rows(), "segment", "segments");
}

// Corners of the curve, kept fixed: ends, branches, and turns sharper than the crease angle.
std::vector<char> curve_corners(const PointMatrix& vertices, const std::vector<Index>& prev,
                                const std::vector<Index>& next, double crease_angle_degrees) {
  const Index nV = static_cast<Index>(vertices.rows());
  std::vector<char> fixed(nV, 0);
  const bool by_angle = creases_by_angle(crease_angle_degrees);
  const double cos_limit = crease_cosine(crease_angle_degrees);
  for (Index v = 0; v < nV; ++v) {
    if (prev[v] < 0) {
      fixed[v] = 1;
    } else if (by_angle) {
      const Eigen::VectorXd a = (vertices.row(v) - vertices.row(prev[v])).transpose();
      const Eigen::VectorXd b = (vertices.row(next[v]) - vertices.row(v)).transpose();
      const double la = a.norm(), lb = b.norm();
      if (la > 0 && lb > 0 && a.dot(b) / (la * lb) < cos_limit) fixed[v] = 1;
    }
  }
  return fixed;
}

// A polyline with its points (and attributes, packed) during refinement.
struct Curve {
  PointMatrix X;
  SimplexMatrix E;
  IndexVector parent;
  std::vector<char> fixed;
  std::vector<Index> prev, next;
};

// One level of cubic B-spline subdivision: midpoints on segments,
// 1/8 (prev) + 3/4 (self) + 1/8 (next) at old points.
void refine_curve(Curve& curve) {
  const PointMatrix& X = curve.X;
  const SimplexMatrix& E = curve.E;
  const Index V = static_cast<Index>(X.rows());
  const Index S = static_cast<Index>(E.rows());
  PointMatrix Y(static_cast<Eigen::Index>(V) + S, X.cols());
  for (Index v = 0; v < V; ++v)
    Y.row(v) = curve.fixed[v] ? Eigen::RowVectorXd(X.row(v))
                              : Eigen::RowVectorXd(0.75 * X.row(v) +
                                                   0.125 * (X.row(curve.prev[v]) + X.row(curve.next[v])));
  SimplexMatrix F(2 * static_cast<Eigen::Index>(S), 2);
  IndexVector P(2 * static_cast<Eigen::Index>(S));
  for (Index e = 0; e < S; ++e) {
    const Index m = V + e;
    Y.row(m) = 0.5 * (X.row(E(e, 0)) + X.row(E(e, 1)));
    F.row(2 * e) << E(e, 0), m;
    F.row(2 * e + 1) << m, E(e, 1);
    P(2 * e) = P(2 * e + 1) = curve.parent(e);
  }
  curve.X = std::move(Y);
  curve.E = std::move(F);
  curve.parent = std::move(P);
  curve.fixed.resize(curve.X.rows(), 0);
  curve_neighbours(static_cast<Index>(curve.X.rows()), curve.E, curve.prev, curve.next);
}

// The points of the cubic B-spline's limit curve.
void move_curve_to_limit(Curve& curve) {
  const PointMatrix& X = curve.X;
  PointMatrix Y = X;
  for (Index v = 0; v < static_cast<Index>(X.rows()); ++v)
    if (!curve.fixed[v] && curve.prev[v] >= 0)
      Y.row(v) = (2.0 / 3.0) * X.row(v) + (1.0 / 6.0) * (X.row(curve.prev[v]) + X.row(curve.next[v]));
  curve.X = std::move(Y);
}

// Normals of planar curves: the segment a -> b has normal (dy, -dx), which
// points out of a counter-clockwise loop; length-weighted at the points.
// Zero for curves in more than two dimensions.
PointMatrix curve_normals(const PointMatrix& vertices, const SimplexMatrix& segments) {
  PointMatrix normals = PointMatrix::Zero(vertices.rows(), vertices.cols());
  if (vertices.cols() != 2) return normals;
  for (Eigen::Index f = 0; f < segments.rows(); ++f) {
    const Eigen::RowVector2d d = vertices.row(segments(f, 1)) - vertices.row(segments(f, 0));
    const Eigen::RowVector2d n(d.y(), -d.x());
    normals.row(segments(f, 0)) += n;
    normals.row(segments(f, 1)) += n;
  }
  normalize_rows(normals);
  return normals;
}

}  // namespace

FrameSubdivision subdivide_frame(const PointMatrix& vertices, const SimplexMatrix& faces,
                                 const FrameSubdivisionOptions& options, const VertexAttributes& vertex_attributes,
                                 const SimplexAttributes& face_attributes, const Interrupter& interrupter) {
  check_memory(frame_subdivision_memory(vertices, faces, vertex_attributes, options.levels));
  check_frame_input(vertices, faces, options, vertex_attributes, face_attributes);
  const Index nF = static_cast<Index>(faces.rows());
  interrupter.step("creases", 0.0);
  const std::vector<Index> creases = crease_pairs(vertices, faces, options);
  FrameSubdivision out;
  out.crease_count = static_cast<Index>(creases.size() / 2);
  if (options.levels == 0 || nF == 0) {
    out.vertices = vertices;
    out.faces = faces;
    out.vertex_attributes = vertex_attributes;
    out.face_attributes = face_attributes;
    out.face_parent = identity_parent(nF);
  } else {
    interrupter.step("topology", 0.1);
    const auto refiner = refine_topology(faces, static_cast<Index>(vertices.rows()), creases, options);
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    interrupter.step("points", 0.3);
    out.vertices = refined_points(*refiner, primvar, vertices, options.limit);
    interrupter.step("attributes", 0.5);
    out.vertex_attributes = refined_attributes(*refiner, primvar, vertex_attributes, options.limit);
    interrupter.step("faces", 0.7);
    out.faces = refined_faces(*refiner, options.scheme);
    out.face_parent = refined_face_parents(*refiner, primvar, nF);
    out.face_attributes = inherit_rows(face_attributes, out.face_parent);
  }
  interrupter.step("normals", 0.9);
  out.normals = vertex_normals(out.vertices, out.faces);
  return out;
}

FrameSubdivision subdivide_polyline(const PointMatrix& vertices, const SimplexMatrix& segments,
                                    const FrameSubdivisionOptions& options, const VertexAttributes& vertex_attributes,
                                    const SimplexAttributes& segment_attributes, const Interrupter& interrupter) {
  check_memory(frame_subdivision_memory(vertices, segments, vertex_attributes, options.levels));
  check_polyline_input(vertices, segments, options, vertex_attributes, segment_attributes);
  const Eigen::Index D = vertices.cols();
  Curve curve{pack_columns(vertices, vertex_attributes), segments, identity_parent(segments.rows()), {}, {}, {}};
  curve_neighbours(static_cast<Index>(vertices.rows()), curve.E, curve.prev, curve.next);
  curve.fixed = curve_corners(vertices, curve.prev, curve.next, options.crease_angle_degrees);
  const Index corners = static_cast<Index>(std::count(curve.fixed.begin(), curve.fixed.end(), 1));
  for (int level = 0; level < options.levels; ++level) {
    std::string step = "level ";  // appended, not operator+: GCC 12 warns falsely (-Wrestrict) on that
    step += std::to_string(level + 1);
    interrupter.step(step, loop_fraction(0.0, 0.9, level, options.levels));
    refine_curve(curve);
  }
  interrupter.step("limit", 0.9);
  if (options.limit && options.levels > 0) move_curve_to_limit(curve);

  FrameSubdivision out;
  out.vertices = curve.X.leftCols(D);
  out.vertex_attributes = unpack_columns(curve.X, D, vertex_attributes);
  out.faces = std::move(curve.E);
  out.face_parent = std::move(curve.parent);
  out.face_attributes = inherit_rows(segment_attributes, out.face_parent);
  out.crease_count = corners;
  out.normals = curve_normals(out.vertices, out.faces);
  return out;
}

Slice smooth_slice(const Slice& frame, const FrameSubdivisionOptions& options) {
  const bool surface = frame.vertices.cols() == 3 && frame.faces.cols() == 3;
  const bool curve = frame.vertices.cols() == 2 && frame.faces.cols() == 2;
  if (!surface && !curve)
    fail<InputError>("only surface frames (triangles in 3D) and curve frames (segments in 2D) can be smoothed; this "
                     "frame has ", frame.faces.cols(), "-vertex faces in ", frame.vertices.cols(), "D");
  FrameSubdivision refined =
      surface ? subdivide_frame(frame.vertices, frame.faces, options, frame.vertex_attributes, frame.face_attributes)
              : subdivide_polyline(frame.vertices, frame.faces, options, frame.vertex_attributes,
                                   frame.face_attributes);
  Slice out;
  out.vertices = std::move(refined.vertices);
  out.faces = std::move(refined.faces);
  out.normals = std::move(refined.normals);
  out.vertex_attributes = std::move(refined.vertex_attributes);
  out.face_attributes = std::move(refined.face_attributes);
  out.vertex_edges.resize(0, 2);
  out.edge_parameter.resize(0);
  out.face_simplex.resize(refined.face_parent.size());
  for (Eigen::Index f = 0; f < refined.face_parent.size(); ++f)
    out.face_simplex(f) = frame.face_simplex.size() ? frame.face_simplex(refined.face_parent(f)) : -1;
  return out;
}

}  // namespace animanifold
