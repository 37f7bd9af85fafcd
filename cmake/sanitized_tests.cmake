# A second, sanitized copy of the C++ tests for CI, cheap enough to build next to the normal
# tree on a fresh machine: only the checked units (CMakeLists.txt: our own units without
# CGAL, less the morph's and the skeleton's stages) and the tests below are compiled again
# with the sanitizers; every other unit is the normal build's object (animanifold_shared_units),
# uninstrumented. ASan still sees every allocation (its allocator replaces malloc for the
# whole process), so our code overrunning a buffer CGAL gave it is found; CGAL's internals
# and the shared units are not checked (scripts/sanitize.sh builds everything sanitized).
#
#   -DANIMANIFOLD_SANITIZED_TESTS=address,undefined   (scripts/test.sh, CI)
#   -DANIMANIFOLD_SANITIZED_TESTS=thread              (ThreadSanitizer on the threaded tests)
# adds animanifold_core_sanitized, animanifold_tests_sanitized and their ctest cases, named
# "sanitized.<Suite>.<Test>". Any finding fails its test: UBSan is compiled not to recover,
# and ASan and TSan stop at their first report.
set(ANIMANIFOLD_SANITIZED_TESTS "" CACHE STRING
    "Sanitizers for the extra sanitized C++ test build (e.g. address,undefined); empty: none")
if(NOT ANIMANIFOLD_SANITIZED_TESTS)
  return()
endif()
if(ANIMANIFOLD_SANITIZE)
  message(FATAL_ERROR "ANIMANIFOLD_SANITIZED_TESTS adds a sanitized copy to a normal build; "
                      "this build is sanitized whole already (ANIMANIFOLD_SANITIZE)")
endif()

# The tests of our own code. Left out: the tests of the CGAL units (booleans, exact
# predicates, the skeleton and the morph's stages), which would run uninstrumented code
# slowly under the sanitizer's allocator and check little of ours.
set(_sanitized_test_names
  test_complex test_conforming_mend test_delaunay test_errors test_flat_polygons
  test_isolated test_laplacian test_memory_estimates test_memory_limit test_normals
  test_perturbation test_progress test_refine test_shelling test_simplex_qp test_slice
  test_stitch test_subdivide test_validation test_cgroup_memory test_enum_names test_threads test_coordinate_bound
  internal/test_zero_set internal/test_isolated_boolean)
set(_sanitized_test_sources "")
foreach(name IN LISTS _sanitized_test_names)
  list(APPEND _sanitized_test_sources ${CMAKE_CURRENT_SOURCE_DIR}/cpp/tests/${name}.cpp)
endforeach()

# -O1: a short build and readable stacks. -UNDEBUG: this is also CI's Debug build of our
# units: Eigen's index and size assertions and our own asserts are on, so an out-of-range
# access aborts where the release build would read past a buffer. CGAL's units are not
# compiled here; CGAL_NDEBUG (animanifold_core_settings) keeps their assertions off in every
# configuration, and tests/test_build_configuration.py checks that a Debug tree's CGAL units
# get it.
# Eigen allocates with its own aligned allocator under ASan and with plain malloc otherwise
# (EIGEN_MALLOC_ALREADY_ALIGNED): a matrix allocated in a shared unit and freed in a checked
# one would be freed wrongly. The checked units get the normal build's choice.
include(CheckCXXSourceCompiles)
set(CMAKE_REQUIRED_LIBRARIES Eigen3::Eigen)
check_cxx_source_compiles("#include <Eigen/Core>
#if !EIGEN_MALLOC_ALREADY_ALIGNED
#error handmade
#endif
int main() { return 0; }" ANIMANIFOLD_EIGEN_MALLOC_ALREADY_ALIGNED)
unset(CMAKE_REQUIRED_LIBRARIES)
if(ANIMANIFOLD_EIGEN_MALLOC_ALREADY_ALIGNED)
  set(_eigen_malloc -DEIGEN_MALLOC_ALREADY_ALIGNED=1)
else()
  set(_eigen_malloc -DEIGEN_MALLOC_ALREADY_ALIGNED=0)
endif()
set(_sanitize_flags -fsanitize=${ANIMANIFOLD_SANITIZED_TESTS} -fno-omit-frame-pointer
    -fno-sanitize-recover=all -O1 -g1 -UNDEBUG ${_eigen_malloc})
add_library(animanifold_core_sanitized STATIC ${ANIMANIFOLD_CHECKED_SOURCES}
            $<TARGET_OBJECTS:animanifold_shared_units>)
animanifold_core_settings(animanifold_core_sanitized)
target_compile_options(animanifold_core_sanitized PRIVATE ${_sanitize_flags})
target_link_options(animanifold_core_sanitized PUBLIC -fsanitize=${ANIMANIFOLD_SANITIZED_TESTS})

add_executable(animanifold_tests_sanitized ${_sanitized_test_sources})
target_compile_options(animanifold_tests_sanitized PRIVATE ${_sanitize_flags})
target_precompile_headers(animanifold_tests_sanitized PRIVATE ${ANIMANIFOLD_TEST_HEADERS})
target_link_libraries(animanifold_tests_sanitized PRIVATE animanifold_core_sanitized GTest::gtest_main)
target_include_directories(animanifold_tests_sanitized PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/cpp/src)
# halt_on_error: the first finding ends the test, which then fails. Leak checks stay on:
# the tests and the core free what they allocate.
gtest_discover_tests(animanifold_tests_sanitized DISCOVERY_TIMEOUT 120 TEST_PREFIX "sanitized."
  PROPERTIES ENVIRONMENT
  "ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1;UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1;TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1")

# The Python module from the same sanitized core, for running Python tests under the
# sanitizer (scripts/sanitized-pytest.sh: CI's fast subset, ThreadSanitizer on the threaded
# tests, scripts/sanitize.sh SANITIZE_SCOPE=own). scripts/build.sh turns it on with the tests.
option(ANIMANIFOLD_SANITIZED_MODULE "Also build a sanitized _core into <build>/sanitized/python/animanifold" OFF)
if(ANIMANIFOLD_SANITIZED_MODULE)
  # NO_EXTRAS: no link-time optimisation, whose link would compile the whole module again.
  pybind11_add_module(_core_sanitized NO_EXTRAS ${ANIMANIFOLD_BINDINGS})
  target_compile_options(_core_sanitized PRIVATE ${_sanitize_flags})
  # The bindings compiled as two units, not one per file: instrumented, pybind11's and Eigen's
  # templates, instantiated again in every file, are most of what compiling them costs.
  set_target_properties(_core_sanitized PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  target_link_libraries(_core_sanitized PRIVATE animanifold_core_sanitized)
  set_target_properties(_core_sanitized PROPERTIES OUTPUT_NAME _core
                        LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/sanitized/python/animanifold)
endif()
