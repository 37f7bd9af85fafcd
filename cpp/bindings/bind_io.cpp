#include "animanifold/io.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_io(py::module_& m) {
  m.def("read_mesh",
        [](const std::string& path) {
          SurfaceMesh mesh = without_gil([&] { return read_mesh(path); });
          return py::make_tuple(mesh.vertices, mesh.faces, mesh.polygons_triangulated);
        },
        py::arg("path"), "(vertices, triangles, polygons_triangulated) of an OFF/OBJ/PLY/STL file, via CGAL; raises FileError "
        "(an OSError) naming the file when it cannot be read.");
  m.def("write_mesh",
        [](const std::string& path, PointsRef V, SimplicesRef F) {
          without_gil([&] { write_mesh(path, V, F); });
        },
        py::arg("path"), py::arg("vertices"), py::arg("faces"),
        "Writes vertices (#V by 3) and triangles (#F by 3) to an OFF/OBJ/PLY/STL file (by extension); raises "
        "FileError naming the file when it cannot be written.");
}

}  // namespace animanifold::bindings
