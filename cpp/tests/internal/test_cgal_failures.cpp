// CGAL's failures translated into our errors (cgal_failures.hpp).
#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace animanifold;

namespace {

// A stand-in for the corefinement's "Unauthorized intersections of
// constraints", thrown the way CGAL throws it.
int cgal_refuses() {
  throw CGAL::Precondition_exception("CGAL", "!is_intersecting", "Constrained_triangulation_2.h", 1,
                                     "Unauthorized intersections of constraints");
}

}  // namespace

// The hole-space functions name BooleanError: the failure leaves as one, in
// our words, with CGAL's message (not its failed expression) kept.
TEST(CgalFailures, BecomeTheNamedErrorThatSaysWhatWasBeingDone) {
  try {
    translating_cgal_failures<BooleanError>("computing the hole space of the shape", cgal_refuses);
    FAIL() << "the CGAL failure was not translated";
  } catch (const BooleanError& e) {
    EXPECT_STREQ(e.what(),
                 "CGAL failed while computing the hole space of the shape: Unauthorized intersections of constraints");
  }
}

// Exceptions of CGAL's own that are no Failure_exception keep their what();
// without an error type named, a failure is a MeshingError.
TEST(CgalFailures, OtherExceptionsKeepTheirTextAndDefaultToMeshingError) {
  try {
    translating_cgal_failures("intersecting two solids", []() -> int {
      throw std::runtime_error("Unauthorized intersections of constraints");  // what CDT_2 throws
    });
    FAIL() << "the exception was not translated";
  } catch (const MeshingError& e) {
    EXPECT_STREQ(e.what(), "CGAL failed while intersecting two solids: Unauthorized intersections of constraints");
  }
}

TEST(CgalFailures, OurOwnErrorsAndResultsPassThrough) {
  EXPECT_THROW(translating_cgal_failures<BooleanError>("x", []() -> int { fail<InputError>("bad"); }), InputError);
  EXPECT_THROW(translating_cgal_failures<BooleanError>("x", []() -> int { throw Cancelled(); }), Cancelled);
  EXPECT_EQ(translating_cgal_failures<BooleanError>("x", [] { return 7; }), 7);
}
