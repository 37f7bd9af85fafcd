#include "animanifold/io.hpp"

#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"
#include "mesh_file_check.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <vector>

namespace animanifold {

using Kernel = CGAL::Simple_cartesian<double>;

SurfaceMesh read_mesh(const std::string& path) {
  check_mesh_file(path);
  std::vector<Kernel::Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  const bool ok = translating_cgal_failures<IOError>(
      "reading mesh file '" + path + "'", [&] { return CGAL::IO::read_polygon_soup(path, points, polygons); });
  if (!ok) fail<IOError>("could not read mesh file '", path, "' (unknown extension or malformed contents)");
  if (polygons.empty()) fail<IOError>("mesh file '", path, "' has no faces");

  SurfaceMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      mesh.vertices(static_cast<Eigen::Index>(v), c) = points[v][c];
      if (!std::isfinite(points[v][c])) fail<IOError>("mesh file '", path, "': vertex ", v, " is not finite");
    }
  size_t triangles = 0;
  for (size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f].size() < 3)
      fail<IOError>("mesh file '", path, "': face ", f, " has ", polygons[f].size(), " corners");
    triangles += polygons[f].size() - 2;
    if (polygons[f].size() > 3) ++mesh.polygons_triangulated;
  }
  mesh.faces.resize(static_cast<Eigen::Index>(triangles), 3);
  Eigen::Index row = 0;
  for (size_t f = 0; f < polygons.size(); ++f) {
    const auto& p = polygons[f];
    for (size_t c = 0; c < p.size(); ++c)
      if (p[c] >= points.size())
        fail<IOError>("mesh file '", path, "': face ", f, " refers to vertex ", p[c], " of ", points.size());
    for (size_t c = 1; c + 1 < p.size(); ++c, ++row) {
      mesh.faces(row, 0) = static_cast<Index>(p[0]);
      mesh.faces(row, 1) = static_cast<Index>(p[c]);
      mesh.faces(row, 2) = static_cast<Index>(p[c + 1]);
    }
  }
  return mesh;
}

void write_mesh(const std::string& path, const PointMatrix& vertices, const SimplexMatrix& faces) {
  if (vertices.cols() != 3) fail<InputError>("write_mesh needs 3D vertices, got ", vertices.cols(), " columns");
  std::vector<Kernel::Point_3> points;
  points.reserve(vertices.rows());
  for (Eigen::Index v = 0; v < vertices.rows(); ++v)
    points.emplace_back(vertices(v, 0), vertices(v, 1), vertices(v, 2));
  std::vector<std::vector<std::size_t>> polygons(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (Eigen::Index c = 0; c < faces.cols(); ++c) {
      if (faces(f, c) < 0 || faces(f, c) >= vertices.rows())
        fail<InputError>("face ", f, " refers to vertex ", faces(f, c), " of ", vertices.rows());
      polygons[f].push_back(static_cast<std::size_t>(faces(f, c)));
    }
  const bool ok = translating_cgal_failures<IOError>("writing mesh file '" + path + "'", [&] {
    return CGAL::IO::write_polygon_soup(path, points, polygons, CGAL::parameters::stream_precision(17));
  });
  if (!ok) fail<IOError>("could not write mesh file '", path, "' (unknown extension or unwritable)");
}

}  // namespace animanifold
