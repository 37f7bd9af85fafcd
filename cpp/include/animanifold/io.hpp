// Mesh files through CGAL's IO (OFF, OBJ, PLY, STL), as polygon soups.
// (The manifold cache format lives in the Python package: animanifold.cache.)
#pragma once

#include "animanifold/types.hpp"

#include <string>

namespace animanifold {

struct SurfaceMesh {
  PointMatrix vertices;  // #V by 3
  SimplexMatrix faces;   // #F by 3 triangles
  Index polygons_triangulated = 0;  // input polygons with more than three corners, fan-split
};

// Inputs:
//   path  an OFF, OBJ, PLY or STL file
// Outputs:
//   SurfaceMesh: vertices #V by 3, triangles #F by 3, how many polygons were fan-split
// Throws: IOError (see below); InputError when path is not a regular file
//
// Reads a polygon mesh; polygons with more than three corners are split into
// fans (the same split for files with the same connectivity, so keyframes
// still correspond). Throws IOError naming the file when it cannot be read,
// has no faces, has a face with fewer than three corners, or declares more
// vertices, faces or corners than its size can hold (checked before CGAL
// reads it, so a tiny file cannot make it allocate gigabytes).
SurfaceMesh read_mesh(const std::string& path);

// Inputs:
//   path      the file; its extension picks the format
//   vertices  #V by 3
//   faces     #F by c polygons
// Outputs: the file
// Throws: IOError (see below); InputError for faces out of range
//
// Writes triangles (or any polygons given as rows) with full double precision;
// the format comes from the extension. Throws IOError naming the file.
void write_mesh(const std::string& path, const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
