#include "animanifold/threads.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_threads(py::module_& m, py::module_& testing) {
  m.def("set_threads", &set_thread_count, py::arg("count"),
        "Threads for the core's parallel work (its loops, OpenBLAS under CHOLMOD): >= 1, or 0 for every core. "
        "Returns the count now in use; raises InputError for a negative count.");
  m.def("threads", &thread_count, "Threads the core's parallel work uses.");
  m.attr("MAX_THREADS") = kMaxThreads;
  testing.def("parallel_team_size", &parallel_team_size,
              "Threads an OpenMP region of the core runs on, as omp_get_num_threads() reports inside it.");
  testing.def("openblas_threads", &blas_thread_count,
              "OpenBLAS's thread count after the core's setting is applied on the calling thread (0: BLAS is not "
              "OpenBLAS).");
}

}  // namespace animanifold::bindings
