#include "animanifold/memory_estimates.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

namespace animanifold {

namespace {

// How much each call holds at its peak beyond its output's arrays (working copies, the
// previous subdivision level, OpenSubdiv's refiner, refine's queue and adjacency), as a
// factor on the output: measured by bench/bench_memory_estimates.py, rounded up.
constexpr double kStitchPeak = 2.0;
constexpr double kManifoldSubdivisionPeak = 3.0;
constexpr double kFrameSubdivisionPeak = 5.0;
constexpr double kRefinementPeak = 4.0;

template <class Tables>
double columns(const Tables& tables) {
  double c = 0;
  for (const auto& [name, table] : tables) c += static_cast<double>(table.cols());
  return c;
}

// Counts are doubles (they may exceed 64 bits) printed as whole numbers.
template <class... Parts>
std::string text(Parts&&... parts) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(0);
  (out << ... << parts);
  return out.str();
}

}  // namespace

MemoryEstimate stitch_memory(const StitchInput& input) {
  const auto m = static_cast<double>(input.times.size());
  const auto rows = static_cast<double>(input.frames.rows());
  const double k = m > 0 ? std::floor(rows / m) : 0, l = static_cast<double>(input.faces.rows());
  const double d = static_cast<double>(input.frames.cols()), n = static_cast<double>(input.faces.cols());
  const double points = m * k, simplices = n * l * std::max(0.0, m - 1);
  const double bytes = points * (d + 1 + columns(input.vertex_attributes)) * sizeof(double) +
                       simplices * (d + 1 + columns(input.face_attributes)) * sizeof(Index);
  return {text("stitching ", m, " keyframes of ", k, " vertices and ", l, " faces (", simplices, " simplices)"),
          bytes * kStitchPeak};
}

MemoryEstimate manifold_subdivision_memory(const Complex& manifold, int levels) {
  const double S = static_cast<double>(manifold.S.rows()), V = static_cast<double>(manifold.V.rows());
  const int k = manifold.vertices_per_simplex();
  const double D = static_cast<double>(manifold.ambient_dimension()), L = std::max(levels, 0);
  const double simplices = S * std::pow(k == 4 ? 8.0 : 4.0, L);
  // Each level adds a vertex per edge (and per octahedron): about a quarter of a level's tets
  // (half its triangles), so the last level's count dominates; kept vertices double per level
  // at most.
  const double vertices = V * std::pow(2.0, L) + simplices / (k == 4 ? 4 : 2);
  const double bytes =
      vertices * ((D + columns(manifold.vertex_attributes)) * sizeof(double) + 2 * sizeof(Index)) +
      simplices * (k + 1 + columns(manifold.simplex_attributes)) * sizeof(Index);
  return {text("subdividing ", S, " simplices ", levels, " times (", simplices, " simplices)"),
          bytes * kManifoldSubdivisionPeak};
}

MemoryEstimate frame_subdivision_memory(Eigen::Index vertices, Eigen::Index faces, int corners,
                                        Eigen::Index attribute_columns, int levels) {
  const double L = std::max(levels, 0), F = static_cast<double>(faces);
  const double out_faces = F * std::pow(corners == 2 ? 2.0 : 4.0, L);
  const double out_vertices = static_cast<double>(vertices) + out_faces;
  // Positions and normals, attributes; corners, parent and attributes per face.
  const double bytes = out_vertices * (6 + static_cast<double>(attribute_columns)) * sizeof(double) +
                       out_faces * (corners + 2) * sizeof(Index);
  return {text("subdividing a frame of ", F, corners == 2 ? " segments " : " faces ", levels, " times (", out_faces,
               corners == 2 ? " segments)" : " faces)"),
          bytes * kFrameSubdivisionPeak};
}

MemoryEstimate frame_subdivision_memory(const PointMatrix& vertices, const SimplexMatrix& faces,
                                        const VertexAttributes& vertex_attributes, int levels) {
  Eigen::Index attribute_columns = 0;
  for (const auto& [name, table] : vertex_attributes) attribute_columns += table.cols();
  return frame_subdivision_memory(vertices.rows(), faces.rows(), static_cast<int>(faces.cols()), attribute_columns,
                                  levels);
}

MemoryEstimate refinement_memory(const Complex& input, const SimplexMatrix& split_vertices) {
  const Eigen::Index N = input.V.rows(), T = split_vertices.rows();
  std::vector<double> star(static_cast<std::size_t>(N), 0.0);
  for (Index id : input.S.reshaped())
    if (id >= 0 && id < N) star[static_cast<std::size_t>(id)] += 1;
  // A split of a face of j + 1 vertices cuts each simplex around it into j + 1.
  double added = 0;
  for (Eigen::Index t = 0; t < T; ++t) {
    double smallest = 0, faces = -1;
    for (Index id : split_vertices.row(t)) {
      if (id < 0 || id >= N) continue;
      const double s = star[static_cast<std::size_t>(id)];
      smallest = faces < 0 ? s : std::min(smallest, s);
      faces += 1;
    }
    added += std::max(faces, 0.0) * smallest;
  }
  const int k = input.vertices_per_simplex();
  const double simplices = static_cast<double>(input.S.rows()) + added, vertices = static_cast<double>(N + T);
  const double bytes =
      vertices * ((input.ambient_dimension() + columns(input.vertex_attributes)) * sizeof(double) + sizeof(Index)) +
      simplices * (k + 1 + columns(input.simplex_attributes)) * sizeof(Index) +
      static_cast<double>(T) * split_vertices.cols() * (sizeof(Index) + sizeof(double));
  return {text("refining ", input.S.rows(), " simplices with ", T, " splits (about ", simplices, " simplices)"),
          bytes * kRefinementPeak};
}

}  // namespace animanifold
