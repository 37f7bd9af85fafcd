// The pybind11 module `animanifold._core`: thin wrappers only, no logic.
// Each bind_*.cpp registers one header's functions; module.cpp calls them.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <utility>

#include "animanifold/types.hpp"
#include "index_arrays.hpp"

namespace animanifold::bindings {

namespace py = pybind11;

// C-contiguous inputs map onto these without a copy (index arrays: index_arrays.hpp).
using PointsRef = Eigen::Ref<const PointMatrix>;

// For long work that runs with the GIL released (TetGen, in its child
// process): takes the GIL and raises what a signal handler raised meanwhile
// (Ctrl-C's KeyboardInterrupt) as a C++ exception that pybind11 hands back
// to Python, so that the work can be interrupted.
inline void raise_pending_python_signals() {
  py::gil_scoped_acquire acquire;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// Runs `work` with the GIL released, so that other Python threads run while
// the core computes, and returns its result (a C++ value: converting it to
// Python needs the GIL, which is held again when this returns).
template <class Work>
auto without_gil(Work&& work) {
  py::gil_scoped_release release;
  return std::forward<Work>(work)();
}

// A read-only property of a bound result class that returns a copy of
// `member`: callers own the arrays they are given.
template <class Class, class Member>
auto copy_of(Member Class::*member) {
  return [member](const Class& c) -> Member { return c.*member; };
}

void bind_errors(py::module_& m);
void bind_errors_testing(py::module_& testing);
// `testing` is _core._testing: entry points only the tests and benchmarks use.
void bind_complex(py::module_& m, py::module_& testing);
void bind_stitch(py::module_& m);
void bind_slice(py::module_& m, py::module_& testing);
void bind_io(py::module_& m);
void bind_delaunay(py::module_& m, py::module_& testing);
void bind_morph(py::module_& m, py::module_& testing);
void bind_refine(py::module_& m, py::module_& testing);
void bind_subdivide(py::module_& m);
void bind_skeleton(py::module_& m);
void bind_laplacian(py::module_& m, py::module_& testing);
void bind_hole_space(py::module_& m);
void bind_memory(py::module_& m);
void bind_threads(py::module_& m, py::module_& testing);

}  // namespace animanifold::bindings
