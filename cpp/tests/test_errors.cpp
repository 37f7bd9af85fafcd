// The error hierarchy's helpers (errors.hpp): fail<> and the translator of
// a library's failures into ours.
#include "animanifold/errors.hpp"

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>

using namespace animanifold;

TEST(Errors, FailJoinsItsPartsIntoTheMessage) {
  try {
    fail<InputError>("keyframe ", 3, " has ", 2.5, " vertices");
    FAIL() << "fail<> returned";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "keyframe 3 has 2.5 vertices");
  }
}

TEST(Errors, ALibraryFailureBecomesAMeshingErrorNamingTheLibraryAndTheWork) {
  try {
    translating_library_failures("TetGen", "meshing 8 points", []() -> int { throw std::runtime_error("code 3"); });
    FAIL() << "the failure was not translated";
  } catch (const MeshingError& e) {
    EXPECT_STREQ(e.what(), "TetGen failed while meshing 8 points: code 3");
  }
}

// The error type and the reader of the library's reason are the caller's.
TEST(Errors, TheCallerChoosesTheErrorTypeAndHowTheReasonIsRead) {
  const auto shout = [](const std::exception& e) { return std::string("<") + e.what() + ">"; };
  try {
    translating_library_failures<IOError>("zlib", "reading a.amf", []() -> int { throw std::logic_error("bad"); },
                                          shout);
    FAIL() << "the failure was not translated";
  } catch (const IOError& e) {
    EXPECT_STREQ(e.what(), "zlib failed while reading a.amf: <bad>");
  }
}

TEST(Errors, OurErrorsAndRunningOutOfMemoryPassThrough) {
  const auto passes = [](auto thrower) { return translating_library_failures("L", "x", thrower); };
  EXPECT_THROW(passes([]() -> int { fail<InputError>("a"); }), InputError);
  EXPECT_THROW(passes([]() -> int { fail<IOError>("a"); }), IOError);
  EXPECT_THROW(passes([]() -> int { fail<BooleanError>("a"); }), BooleanError);
  EXPECT_THROW(passes([]() -> int { throw Cancelled(); }), Cancelled);
  EXPECT_THROW(passes([]() -> int { throw std::bad_alloc(); }), std::bad_alloc);
  EXPECT_EQ(passes([] { return 5; }), 5);
}
