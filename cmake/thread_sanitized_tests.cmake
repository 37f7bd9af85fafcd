# ThreadSanitizer on what the caller's threads share, for CI (scripts/test.sh):
#
#   -DANIMANIFOLD_THREAD_SANITIZED_TESTS=ON
#
# adds animanifold_tests_tsan and its ctest cases "tsan.<Suite>.<Test>": the tests of the
# objects threads may share (laplacian.hpp's Deformer, slice.hpp's Slicer with its lazy
# index) and of field morphs run at once from several threads, built with
# -fsanitize=thread. Only the units those objects and morphs live in are compiled again
# with the sanitizer; every other unit (CGAL's among them) comes uninstrumented from
# the normal core (the linker takes an archive member only for a symbol no listed object
# defines), so the build costs a few units, not a tree.
#
# gcc's libgomp is not instrumented, so ThreadSanitizer cannot see its barriers and would
# report every parallel loop's shared variables. The cases run with OMP_NUM_THREADS=1: the
# core's own loops then run on the calling thread, and what is checked is what several
# threads of the caller share (tests/fuzz/README.md, "Sanitizers").
option(ANIMANIFOLD_THREAD_SANITIZED_TESTS "Build the shared-object tests with ThreadSanitizer (ctest's tsan. cases)" OFF)
if(NOT ANIMANIFOLD_THREAD_SANITIZED_TESTS)
  return()
endif()

set(_tsan_units slice slice_cut slice_weld interval_index interval_frame deformer deformer_response
    # the field morph's own stages, the TetGen runner and its child process, and the frame checks
    morph morph_stages morph_field morph_field_points morph_field_refine morph_field_slabs morph_field_timing
    morph_field_topology morph_field_interior morph_field_certificate convex_cover morph_validity zero_set conforming_delaunay_3d conforming_mend
    isolated complex)
set(_tsan_tests test_slice test_laplacian test_morph_threads)
set(_tsan_sources "")
foreach(unit IN LISTS _tsan_units)
  list(APPEND _tsan_sources ${CMAKE_CURRENT_SOURCE_DIR}/cpp/src/${unit}.cpp)
endforeach()
foreach(name IN LISTS _tsan_tests)
  list(APPEND _tsan_sources ${CMAKE_CURRENT_SOURCE_DIR}/cpp/tests/${name}.cpp)
endforeach()

add_executable(animanifold_tests_tsan ${_tsan_sources})
animanifold_core_settings(animanifold_tests_tsan)
target_include_directories(animanifold_tests_tsan PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/cpp/src)
target_compile_options(animanifold_tests_tsan PRIVATE -fsanitize=thread -fno-omit-frame-pointer -O1 -g1)
target_precompile_headers(animanifold_tests_tsan PRIVATE ${ANIMANIFOLD_TEST_HEADERS})
target_link_options(animanifold_tests_tsan PRIVATE -fsanitize=thread)
target_link_libraries(animanifold_tests_tsan PRIVATE animanifold_core GTest::gtest_main)
gtest_discover_tests(animanifold_tests_tsan DISCOVERY_TIMEOUT 120 TEST_PREFIX "tsan."
  PROPERTIES ENVIRONMENT "OMP_NUM_THREADS=1;TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1")
