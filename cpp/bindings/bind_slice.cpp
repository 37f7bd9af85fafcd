#include "animanifold/errors.hpp"
#include "animanifold/slice.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_slice(py::module_& m, py::module_& testing) {
  py::class_<Slice, std::shared_ptr<Slice>>(m, "Slice", "One iso-slice (frame) of a manifold.")
      .def_readonly("vertices", &Slice::vertices)
      .def_readonly("faces", &Slice::faces)
      .def_readonly("normals", &Slice::normals)
      .def_readonly("vertex_attributes", &Slice::vertex_attributes)
      .def_readonly("face_attributes", &Slice::face_attributes)
      .def_readonly("vertex_edges", &Slice::vertex_edges)
      .def_readonly("edge_parameter", &Slice::edge_parameter)
      .def_readonly("face_simplex", &Slice::face_simplex);

  py::class_<IntervalFrame, std::shared_ptr<IntervalFrame>>(
      m, "IntervalFrame",
      "A frame with how it moves inside its topology interval (lo, hi): at v in it, the slice has the same "
      "faces and vertex p is at slice.vertices[p] + (v - value) * rate[p] (vertex attributes and "
      "edge_parameter likewise, with attribute_rates and parameter_rate).")
      .def_readonly("axis", &IntervalFrame::axis)
      .def_readonly("value", &IntervalFrame::value, "The value the slice was cut at.")
      .def_readonly("slice", &IntervalFrame::slice, "The Slice at `value`.")
      .def_property_readonly("interval", [](const IntervalFrame& f) { return py::make_tuple(f.lo, f.hi); },
                             "The open topology interval (lo, hi) around `value`.")
      .def_readonly("rate", &IntervalFrame::rate, "(P, D-1): d vertices / d value.")
      .def_readonly("attribute_rates", &IntervalFrame::attribute_rates, "Name -> (P, c): d attribute / d value.")
      .def_readonly("parameter_rate", &IntervalFrame::parameter_rate, "(P,): d edge_parameter / d value.");

  py::class_<Slicer>(m, "Slicer", "A manifold with its cached interval indices (one per slicing axis).")
      .def(py::init<std::shared_ptr<const Complex>>(), py::arg("manifold"), py::keep_alive<1, 2>(),
           "Slices `manifold` (a Complex), building each axis's interval index on first use.")
      .def("slice",
           [](Slicer& s, int axis, double value, bool use_index) {
             return without_gil([&] { return std::make_shared<Slice>(s.slice(axis, value, use_index)); });
           },
           py::arg("axis"), py::arg("value"), py::arg("use_index") = true,
           "The Slice of the manifold at coordinate `value` along `axis` (3 is time); `use_index` False tests "
           "every simplex instead. Raises InputError for an axis out of range.")
      .def("interval_frame",
           [](Slicer& s, int axis, double value) {
             return without_gil([&] { return std::make_shared<IntervalFrame>(s.interval_frame(axis, value)); });
           },
           py::arg("axis"), py::arg("value"),
           "The frame at `value` with its topology interval and rates; ValueError where it has none "
           "(a vertex coordinate, outside the manifold).")
      .def("slice_in_interval",
           [](Slicer& s, const IntervalFrame& frame, double value) {
             return without_gil([&] { return std::make_shared<Slice>(s.slice_in_interval(frame, value)); });
           },
           py::arg("frame"), py::arg("value"),
           "The Slice at `value` from `frame` (an IntervalFrame of this slicer): its faces with the points "
           "computed at `value`, identical to slice(frame.axis, value) at the cost of a gather and a lerp. "
           "ValueError when `value` is outside the frame's topology interval.")
      .def("topology_interval",
           [](Slicer& s, int axis, double value) {
             return without_gil([&] { return s.index(axis).topology_interval(value); });
           },
           py::arg("axis"), py::arg("value"),
           "The open interval (lo, hi) around `value` without vertex coordinates (every slice in it has "
           "the same faces), or None where the faces change (a vertex coordinate, outside the manifold).")
      .def("index_memory_bytes", [](Slicer& s, int axis) { return s.index(axis).memory_bytes(); }, py::arg("axis"),
           "Bytes held by the interval index of `axis` (built if needed).");

  testing.def("slice_stages",
        [](Slicer& s, int axis, double value) {
          SliceStages stages;
          without_gil([&] { s.slice(axis, value, true, &stages); });
          py::dict out;
          out["stab"] = stages.stab, out["cut"] = stages.cut, out["weld"] = stages.weld;
          out["output"] = stages.output, out["normals"] = stages.normals;
          return out;
        },
        py::arg("slicer"), py::arg("axis"), py::arg("value"),
        "Seconds each stage of slicer.slice(axis, value) took: stab, cut, weld, output, normals "
        "(the benchmark's breakdown).");
  testing.def("slice",
        [](const Complex& c, int axis, double value) {
          return without_gil([&] { return std::make_shared<Slice>(slice(c, axis, value)); });
        },
        py::arg("manifold"), py::arg("axis"), py::arg("value"),
        "One slice without an index or cached normals (tests every simplex).");
}

}  // namespace animanifold::bindings
