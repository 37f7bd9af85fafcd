// A mesh file checked before CGAL's readers see it. They size their arrays
// from the counts a file declares (OFF's header and each face's corner count,
// PLY's element counts and each list's length), so a 44-byte file could make them allocate
// gigabytes; and reading a FIFO or /dev/zero would block or never end.
#pragma once

#include <string>

namespace animanifold {

// Inputs:
//   path  the mesh file read_mesh() is about to read
// Throws:
//   IOError when it does not exist, or declares more vertices, faces or
//     corners than its size can hold (naming the file and the count)
//   InputError when it is not a regular file (a directory, device or pipe)
void check_mesh_file(const std::string& path);

}  // namespace animanifold
