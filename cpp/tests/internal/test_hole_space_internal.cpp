// The hole-space functions' translation of CGAL's failures into our errors
// (hole_space_internal.hpp).
#include "animanifold/errors.hpp"
#include "hole_space_internal.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace animanifold;

// CGAL reports what it cannot do by throwing its own exceptions (a stand-in
// for the corefinement's "Unauthorized intersections of constraints" here):
// they leave the hole-space functions as a BooleanError in our words, with
// CGAL's explanation kept.
TEST(HoleSpace, CgalFailuresBecomeBooleanErrorsThatSayWhatWasBeingDone) {
  const auto cgal_refuses = []() -> int {
    throw CGAL::Precondition_exception("CGAL", "!is_intersecting", "Constrained_triangulation_2.h", 1,
                                       "Unauthorized intersections of constraints");
  };
  try {
    holes::translating_cgal_failures("computing the hole space of the shape", cgal_refuses);
    FAIL() << "the CGAL failure was not translated";
  } catch (const BooleanError& e) {
    EXPECT_STREQ(e.what(),
                 "CGAL failed while computing the hole space of the shape: Unauthorized intersections of constraints");
  }
  // Exceptions of CGAL's own that are no Failure_exception keep their what().
  try {
    holes::translating_cgal_failures("intersecting two solids", []() -> int {
      throw std::runtime_error("Unauthorized intersections of constraints");  // what CDT_2 throws
    });
    FAIL() << "the exception was not translated";
  } catch (const BooleanError& e) {
    EXPECT_STREQ(e.what(), "CGAL failed while intersecting two solids: Unauthorized intersections of constraints");
  }
  // Our own errors and results pass through.
  EXPECT_THROW(holes::translating_cgal_failures("x", []() -> int { fail<InputError>("bad"); }), InputError);
  EXPECT_EQ(holes::translating_cgal_failures("x", [] { return 7; }), 7);
}
