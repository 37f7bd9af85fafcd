#include "animanifold/errors.hpp"
#include "animanifold/memory_limit.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

namespace {

// A Python exception class `name` in module `m` with the given bases (a
// tuple, so that a core error can be both animanifold.Error and the builtin
// callers have always caught).
py::object exception_class(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("animanifold._core.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  py::object cls = py::reinterpret_steal<py::object>(type);
  m.attr(name) = cls;
  return cls;
}

}  // namespace

void bind_errors(py::module_& m) {
  py::object error = exception_class(m, "Error", py::make_tuple(py::handle(PyExc_Exception)),
                                     "Base of every error the core raises on purpose (animanifold.Error).");
  auto derived = [&](const char* name, PyObject* builtin, const char* doc) {
    return builtin ? exception_class(m, name, py::make_tuple(error, py::handle(builtin)), doc)
                   : exception_class(m, name, py::make_tuple(error), doc);
  };
  // Static: the translator below outlives this function and the classes live
  // as long as the module.
  static py::handle input_error = derived("InputError", PyExc_ValueError,
                                          "The caller's data is invalid; the message names the element.").release();
  static py::handle not_manifold_error =
      exception_class(m, "NotManifoldError", py::make_tuple(input_error),
                      "The faces do not form an oriented 2-manifold surface where the call needs one; the message "
                      "names the first face that cannot join it.")
          .release();
  static py::handle file_error = derived("FileError", PyExc_OSError,
                                         "A file could not be read or written, or its contents are damaged.").release();
  static py::handle boolean_error = derived("BooleanError", PyExc_RuntimeError,
                                            "CGAL refused an operand of a Boolean operation, or the result is not "
                                            "a manifold.").release();
  static py::handle meshing_error = derived("MeshingError", PyExc_RuntimeError,
                                            "A library the core calls (TetGen, Qhull, CGAL, CHOLMOD) failed; the "
                                            "message says on what, with the library's text at the end.").release();
  static py::handle time_limit_error =
      exception_class(m, "TimeLimitError", py::make_tuple(meshing_error),
                      "A library call ran past the time limit kept against its looping (TetGen) and was stopped; "
                      "nothing retried it another way, as the result would then depend on the machine's speed.")
          .release();
  static py::handle cancelled = derived("Cancelled", nullptr,
                                        "The caller's progress or interrupt callback stopped a long call.").release();
  static py::handle memory_limit_error =
      derived("MemoryLimitError", PyExc_MemoryError,
              "A call's estimated memory exceeds the limit (animanifold.set_memory_limit); the message names "
              "the call, the estimate and the limit.")
          .release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const NotManifoldError& e) {
      PyErr_SetString(not_manifold_error.ptr(), e.what());
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const IOError& e) {
      PyErr_SetString(file_error.ptr(), e.what());
    } catch (const BooleanError& e) {
      PyErr_SetString(boolean_error.ptr(), e.what());
    } catch (const TimeLimitError& e) {
      PyErr_SetString(time_limit_error.ptr(), e.what());
    } catch (const MeshingError& e) {
      PyErr_SetString(meshing_error.ptr(), e.what());
    } catch (const Cancelled& e) {
      PyErr_SetString(cancelled.ptr(), e.what());
    } catch (const MemoryLimitError& e) {
      PyErr_SetString(memory_limit_error.ptr(), e.what());
    }
  });
}

void bind_errors_testing(py::module_& testing) {
  testing.def(
      "raise_error",
      [](const std::string& type, const std::string& message) {
        if (type == "InputError") fail<InputError>(message);
        if (type == "NotManifoldError") fail<NotManifoldError>(message);
        if (type == "IOError") fail<IOError>(message);
        if (type == "BooleanError") fail<BooleanError>(message);
        if (type == "MeshingError") fail<MeshingError>(message);
        if (type == "TimeLimitError") fail<TimeLimitError>(message);
        if (type == "Cancelled") throw Cancelled();
        if (type == "MemoryLimitError") fail<MemoryLimitError>(message);
        throw std::invalid_argument("unknown core error type '" + type + "'");
      },
      py::arg("type"), py::arg("message"),
      "Throws the core exception named `type` (InputError, NotManifoldError, IOError, BooleanError, MeshingError, TimeLimitError, "
      "Cancelled, "
      "MemoryLimitError) "
      "with `message`, through the module's translator: what a core call raises in that case.");
}

}  // namespace animanifold::bindings
