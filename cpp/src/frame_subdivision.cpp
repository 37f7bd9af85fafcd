// OpenSubdiv refinement of frames (Loop / Catmull-Clark) with creases at
// sharp edges. See subdivide.hpp.
#include "animanifold/errors.hpp"
#include "animanifold/subdivide.hpp"

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
  if (name == "loop") return FrameScheme::Loop;
  if (name == "catmull-clark" || name == "catmull_clark" || name == "catmark") return FrameScheme::CatmullClark;
  fail<InputError>("unknown frame subdivision scheme '", name, "': use 'loop' or 'catmull-clark'");
}

namespace {

using namespace OpenSubdiv;

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

Eigen::Vector3d face_normal(const PointMatrix& V, const Index* f, int n) {
  // Newell's normal: exact for planar polygons, a fair average otherwise.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d a = V.row(f[i]).transpose(), b = V.row(f[(i + 1) % n]).transpose();
    normal += (a - b).cross(a + b) * 0.5;
  }
  return normal;
}

}  // namespace

FrameSubdivision subdivide_frame(const PointMatrix& vertices, const SimplexMatrix& faces,
                                 const FrameSubdivisionOptions& options, const VertexAttributes& vertex_attributes,
                                 const SimplexAttributes& face_attributes) {
  const Index nV = static_cast<Index>(vertices.rows());
  const Index nF = static_cast<Index>(faces.rows());
  const int n = static_cast<int>(faces.cols());
  if (vertices.cols() != 3) fail<InputError>("frame vertices must be #V by 3, got ", vertices.cols(), " columns");
  if (n != 3 && n != 4) fail<InputError>("frame faces must be triangles or quads, got ", n, " vertices per face");
  if (options.scheme == FrameScheme::Loop && n != 3)
    fail<InputError>("Loop subdivision needs triangles; use Catmull-Clark for quads");
  if (options.levels < 0 || options.levels > 8)
    fail<InputError>("frame subdivision levels must be in 0..8, got ", options.levels);
  for (Index v = 0; v < nV; ++v)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(vertices(v, c))) fail<InputError>("frame vertex ", v, " has a non-finite coordinate");
  for (Index f = 0; f < nF; ++f)
    for (int a = 0; a < n; ++a) {
      const Index v = faces(f, a);
      if (v < 0 || v >= nV) fail<InputError>("face ", f, " refers to vertex ", v, ", outside 0..", nV - 1);
      for (int b = a + 1; b < n; ++b)
        if (faces(f, b) == v) fail<InputError>("face ", f, " repeats vertex ", v);
    }
  for (const auto& [name, table] : vertex_attributes)
    if (table.rows() != nV)
      fail<InputError>("vertex attribute '", name, "' has ", table.rows(), " rows for ", nV, " vertices");
  for (const auto& [name, table] : face_attributes)
    if (table.rows() != nF) fail<InputError>("face attribute '", name, "' has ", table.rows(), " rows for ", nF, " faces");

  FrameSubdivision out;
  if (options.levels == 0 || nF == 0) {
    out.vertices = vertices;
    out.faces = faces;
    out.vertex_attributes = vertex_attributes;
    out.face_attributes = face_attributes;
    out.face_parent.resize(nF);
    for (Index f = 0; f < nF; ++f) out.face_parent(f) = f;
  }

  // Edges with their faces, for the dihedral test and to check given creases.
  struct EdgeRecord {
    std::array<Index, 2> key;
    Index face;
  };
  std::vector<EdgeRecord> records;
  records.reserve(static_cast<size_t>(nF) * n);
  for (Index f = 0; f < nF; ++f)
    for (int i = 0; i < n; ++i) {
      const Index a = faces(f, i), b = faces(f, (i + 1) % n);
      records.push_back({{std::min(a, b), std::max(a, b)}, f});
    }
  std::sort(records.begin(), records.end(),
            [](const EdgeRecord& x, const EdgeRecord& y) { return x.key != y.key ? x.key < y.key : x.face < y.face; });

  std::vector<Index> crease_pairs;
  const bool by_angle = options.crease_angle_degrees > 0 && options.crease_angle_degrees < 180;
  if (by_angle && options.levels > 0) {
    const double cos_limit = std::cos(options.crease_angle_degrees * M_PI / 180.0);
    std::vector<Eigen::Vector3d> normals(nF);
    for (Index f = 0; f < nF; ++f) normals[f] = face_normal(vertices, faces.row(f).data(), n);
    for (size_t begin = 0; begin < records.size();) {
      size_t end = begin + 1;
      while (end < records.size() && records[end].key == records[begin].key) ++end;
      if (end - begin == 2) {
        const Eigen::Vector3d& a = normals[records[begin].face];
        const Eigen::Vector3d& b = normals[records[begin + 1].face];
        const double la = a.norm(), lb = b.norm();
        if (la > 0 && lb > 0 && a.dot(b) / (la * lb) < cos_limit)
          crease_pairs.insert(crease_pairs.end(), {records[begin].key[0], records[begin].key[1]});
      }
      begin = end;
    }
  }
  for (Eigen::Index c = 0; c < options.crease_edges.rows(); ++c) {
    if (options.crease_edges.cols() != 2) fail<InputError>("crease edges must be #C by 2 vertex pairs");
    const Index a = std::min(options.crease_edges(c, 0), options.crease_edges(c, 1));
    const Index b = std::max(options.crease_edges(c, 0), options.crease_edges(c, 1));
    const EdgeRecord probe{{a, b}, -1};
    const auto it = std::lower_bound(records.begin(), records.end(), probe, [](const EdgeRecord& x, const EdgeRecord& y) {
      return x.key != y.key ? x.key < y.key : x.face < y.face;
    });
    if (it == records.end() || it->key != probe.key)
      fail<InputError>("crease edge ", c, " (", options.crease_edges(c, 0), ", ", options.crease_edges(c, 1),
                       ") is not an edge of the frame");
    crease_pairs.insert(crease_pairs.end(), {a, b});
  }
  // Deduplicate (an edge found by angle may also be given).
  {
    std::vector<std::array<Index, 2>> pairs;
    for (size_t i = 0; i < crease_pairs.size(); i += 2) pairs.push_back({crease_pairs[i], crease_pairs[i + 1]});
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    crease_pairs.clear();
    for (const auto& p : pairs) crease_pairs.insert(crease_pairs.end(), {p[0], p[1]});
  }
  out.crease_count = static_cast<Index>(crease_pairs.size() / 2);
  if (options.levels == 0 || nF == 0) {
    out.normals = PointMatrix::Zero(out.vertices.rows(), 3);
  } else {
    install_error_callback();
    osd_last_error.clear();

    std::vector<int> verts_per_face(nF, n);
    std::vector<float> crease_weights(crease_pairs.size() / 2, Sdc::Crease::SHARPNESS_INFINITE);
    Far::TopologyDescriptor desc;
    desc.numVertices = nV;
    desc.numFaces = nF;
    desc.numVertsPerFace = verts_per_face.data();
    desc.vertIndicesPerFace = faces.data();
    desc.numCreases = static_cast<int>(crease_weights.size());
    desc.creaseVertexIndexPairs = crease_pairs.data();
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

    const int L = options.levels;
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    const Far::TopologyLevel& last = refiner->GetLevel(L);
    const int outV = last.GetNumVertices();
    const int outF = last.GetNumFaces();

    // Points through all levels, then to the limit.
    {
      std::vector<Point3> src(nV), dst;
      for (Index v = 0; v < nV; ++v)
        for (int c = 0; c < 3; ++c) src[v].p[c] = vertices(v, c);
      for (int level = 1; level <= L; ++level) {
        dst.assign(refiner->GetLevel(level).GetNumVertices(), Point3{});
        primvar.Interpolate(level, src, dst);
        src.swap(dst);
      }
      if (options.limit) {
        dst.assign(outV, Point3{});
        primvar.Limit(src, dst);
        src.swap(dst);
      }
      if (!osd_last_error.empty()) fail<InputError>("OpenSubdiv failed: ", osd_last_error);
      out.vertices.resize(outV, 3);
      for (int v = 0; v < outV; ++v)
        for (int c = 0; c < 3; ++c) out.vertices(v, c) = src[v].p[c];
    }
    for (const auto& [name, table] : vertex_attributes) {
      PointMatrix refined(outV, table.cols());
      for (Eigen::Index c = 0; c < table.cols(); ++c) {
        std::vector<Scalar> src(nV), dst;
        for (Index v = 0; v < nV; ++v) src[v].v = table(v, c);
        for (int level = 1; level <= L; ++level) {
          dst.assign(refiner->GetLevel(level).GetNumVertices(), Scalar{});
          primvar.Interpolate(level, src, dst);
          src.swap(dst);
        }
        if (options.limit) {
          dst.assign(outV, Scalar{});
          primvar.Limit(src, dst);
          src.swap(dst);
        }
        for (int v = 0; v < outV; ++v) refined(v, c) = src[v].v;
      }
      out.vertex_attributes[name] = std::move(refined);
    }
    // Faces: Loop keeps triangles, Catmull-Clark makes quads.
    const int outN = options.scheme == FrameScheme::Loop ? 3 : 4;
    out.faces.resize(outF, outN);
    for (int f = 0; f < outF; ++f) {
      const Far::ConstIndexArray fv = last.GetFaceVertices(f);
      if (fv.size() != outN) fail<InputError>("OpenSubdiv produced a face of ", fv.size(), " vertices");
      for (int i = 0; i < outN; ++i) out.faces(f, i) = fv[i];
    }
    {
      std::vector<Index> src(nF), dst;
      for (Index f = 0; f < nF; ++f) src[f] = f;
      for (int level = 1; level <= L; ++level) {
        dst.assign(refiner->GetLevel(level).GetNumFaces(), 0);
        primvar.InterpolateFaceUniform(level, src, dst);
        src.swap(dst);
      }
      out.face_parent = Eigen::Map<const IndexVector>(src.data(), outF);
    }
    for (const auto& [name, table] : face_attributes) {
      SimplexMatrix inherited(outF, table.cols());
      for (int f = 0; f < outF; ++f) inherited.row(f) = table.row(out.face_parent(f));
      out.face_attributes[name] = std::move(inherited);
    }
  }

  // Area-weighted unit normals of the refined mesh.
  out.normals = PointMatrix::Zero(out.vertices.rows(), 3);
  const int outN = static_cast<int>(out.faces.cols());
  for (Eigen::Index f = 0; f < out.faces.rows(); ++f) {
    const Eigen::Vector3d normal = face_normal(out.vertices, out.faces.row(f).data(), outN);
    for (int i = 0; i < outN; ++i) out.normals.row(out.faces(f, i)) += normal.transpose();
  }
  for (Eigen::Index v = 0; v < out.normals.rows(); ++v) {
    const double length = out.normals.row(v).norm();
    if (length > 0) out.normals.row(v) /= length;
  }
  return out;
}

FrameSubdivision subdivide_polyline(const PointMatrix& vertices, const SimplexMatrix& segments,
                                    const FrameSubdivisionOptions& options, const VertexAttributes& vertex_attributes,
                                    const SimplexAttributes& segment_attributes) {
  const Index nV = static_cast<Index>(vertices.rows());
  const Index nE = static_cast<Index>(segments.rows());
  const int D = static_cast<int>(vertices.cols());
  if (segments.cols() != 2) fail<InputError>("polyline segments must be #E by 2, got ", segments.cols(), " columns");
  if (D < 2) fail<InputError>("polyline points need at least 2 coordinates, got ", D);
  if (options.levels < 0 || options.levels > 16)
    fail<InputError>("polyline subdivision levels must be in 0..16, got ", options.levels);
  for (Index e = 0; e < nE; ++e)
    for (int i = 0; i < 2; ++i)
      if (segments(e, i) < 0 || segments(e, i) >= nV)
        fail<InputError>("segment ", e, " refers to vertex ", segments(e, i), ", outside 0..", nV - 1);
  for (Index v = 0; v < nV; ++v)
    for (int c = 0; c < D; ++c)
      if (!std::isfinite(vertices(v, c))) fail<InputError>("polyline vertex ", v, " has a non-finite coordinate");
  for (const auto& [name, table] : vertex_attributes)
    if (table.rows() != nV)
      fail<InputError>("vertex attribute '", name, "' has ", table.rows(), " rows for ", nV, " vertices");
  for (const auto& [name, table] : segment_attributes)
    if (table.rows() != nE)
      fail<InputError>("segment attribute '", name, "' has ", table.rows(), " rows for ", nE, " segments");

  // Points and attributes travel together.
  Eigen::Index C = D;
  for (const auto& [name, table] : vertex_attributes) C += table.cols();
  PointMatrix X(nV, C);
  X.leftCols(D) = vertices;
  {
    Eigen::Index c = D;
    for (const auto& [name, table] : vertex_attributes) {
      X.middleCols(c, table.cols()) = table;
      c += table.cols();
    }
  }
  SimplexMatrix E = segments;
  IndexVector parent(nE);
  for (Index e = 0; e < nE; ++e) parent(e) = e;

  // Neighbours along the curve; -1 where the curve ends or branches.
  auto neighbours = [](Index n, const SimplexMatrix& S, std::vector<Index>& prev, std::vector<Index>& next) {
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
  };
  // Corners (kept fixed): ends, branches, and turns sharper than the crease angle.
  std::vector<Index> prev, next;
  neighbours(nV, E, prev, next);
  std::vector<char> fixed(nV, 0);
  const bool by_angle = options.crease_angle_degrees > 0 && options.crease_angle_degrees < 180;
  const double cos_limit = std::cos(options.crease_angle_degrees * M_PI / 180.0);
  Index corners = 0;
  for (Index v = 0; v < nV; ++v) {
    if (prev[v] < 0) {
      fixed[v] = 1;
    } else if (by_angle) {
      const Eigen::VectorXd a = (vertices.row(v) - vertices.row(prev[v])).transpose();
      const Eigen::VectorXd b = (vertices.row(next[v]) - vertices.row(v)).transpose();
      const double la = a.norm(), lb = b.norm();
      if (la > 0 && lb > 0 && a.dot(b) / (la * lb) < cos_limit) fixed[v] = 1;
    }
    corners += fixed[v];
  }

  // Cubic B-spline subdivision: midpoints on segments, 1/8 (prev) + 3/4 (self) + 1/8 (next) at old points.
  for (int level = 0; level < options.levels; ++level) {
    const Index V = static_cast<Index>(X.rows());
    const Index S = static_cast<Index>(E.rows());
    PointMatrix Y(static_cast<Eigen::Index>(V) + S, C);
    for (Index v = 0; v < V; ++v)
      Y.row(v) = fixed[v] ? Eigen::RowVectorXd(X.row(v)) : Eigen::RowVectorXd(0.75 * X.row(v) + 0.125 * (X.row(prev[v]) + X.row(next[v])));
    SimplexMatrix F(2 * static_cast<Eigen::Index>(S), 2);
    IndexVector P(2 * static_cast<Eigen::Index>(S));
    for (Index e = 0; e < S; ++e) {
      const Index m = V + e;
      Y.row(m) = 0.5 * (X.row(E(e, 0)) + X.row(E(e, 1)));
      F.row(2 * e) << E(e, 0), m;
      F.row(2 * e + 1) << m, E(e, 1);
      P(2 * e) = P(2 * e + 1) = parent(e);
    }
    X = std::move(Y);
    E = std::move(F);
    parent = std::move(P);
    fixed.resize(X.rows(), 0);
    neighbours(static_cast<Index>(X.rows()), E, prev, next);
  }
  if (options.limit && options.levels > 0) {
    PointMatrix Y = X;
    for (Index v = 0; v < static_cast<Index>(X.rows()); ++v)
      if (!fixed[v] && prev[v] >= 0) Y.row(v) = (2.0 / 3.0) * X.row(v) + (1.0 / 6.0) * (X.row(prev[v]) + X.row(next[v]));
    X = std::move(Y);
  }

  FrameSubdivision out;
  out.vertices = X.leftCols(D);
  {
    Eigen::Index c = D;
    for (const auto& [name, table] : vertex_attributes) {
      out.vertex_attributes[name] = X.middleCols(c, table.cols());
      c += table.cols();
    }
  }
  out.faces = std::move(E);
  out.face_parent = std::move(parent);
  for (const auto& [name, table] : segment_attributes) {
    SimplexMatrix inherited(out.faces.rows(), table.cols());
    for (Eigen::Index f = 0; f < out.faces.rows(); ++f) inherited.row(f) = table.row(out.face_parent(f));
    out.face_attributes[name] = std::move(inherited);
  }
  out.crease_count = corners;
  // Normals of planar curves: the segment a -> b has normal (dy, -dx), which
  // points out of a counter-clockwise loop; length-weighted at the points.
  out.normals = PointMatrix::Zero(out.vertices.rows(), D);
  if (D == 2) {
    for (Eigen::Index f = 0; f < out.faces.rows(); ++f) {
      const Eigen::RowVector2d d = out.vertices.row(out.faces(f, 1)) - out.vertices.row(out.faces(f, 0));
      const Eigen::RowVector2d n(d.y(), -d.x());
      out.normals.row(out.faces(f, 0)) += n;
      out.normals.row(out.faces(f, 1)) += n;
    }
    for (Eigen::Index v = 0; v < out.normals.rows(); ++v) {
      const double length = out.normals.row(v).norm();
      if (length > 0) out.normals.row(v) /= length;
    }
  }
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
