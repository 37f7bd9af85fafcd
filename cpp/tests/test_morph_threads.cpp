// Morphs run at once from several of the caller's threads (a pipeline
// morphing shots in parallel, Blender's job beside a script) share nothing
// but the process: each gives, bit for bit, what it gives alone. CI also
// runs this under ThreadSanitizer (cmake/thread_sanitized_tests.cmake),
// which instruments the field method's own units, so a hidden shared state
// (a static cache, a global scratch buffer) is reported where it is touched.
#include "animanifold/morph.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <functional>
#include <thread>

using namespace animanifold;

namespace {

struct Shape {
  PointMatrix V;
  SimplexMatrix F;
};

// The octahedron scaled by `scale`, turned by `degrees` about z and moved
// along x by `shift`.
Shape turned_octahedron(double scale, double degrees, double shift) {
  Shape shape;
  fixtures::octahedron(shape.V, shape.F);
  const double a = degrees * M_PI / 180.0;
  Eigen::Matrix3d turn;
  turn << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  shape.V = ((scale * shape.V) * turn.transpose()).rowwise() + Eigen::RowVector3d(shift, 0, 0);
  return shape;
}

Morph field_morph_of(const Shape& source, const Shape& target) {
  MorphOptions options;
  options.method = MorphMethod::Field;
  options.field_resolution = 6;
  options.field_layers = 5;
  return morph(source.V, source.F, target.V, target.F, options);
}

void expect_same_bits(const Morph& a, const Morph& b) {
  ASSERT_EQ(a.manifold.V.rows(), b.manifold.V.rows());
  ASSERT_EQ(a.manifold.S.rows(), b.manifold.S.rows());
  EXPECT_TRUE((a.manifold.V.array() == b.manifold.V.array()).all());
  EXPECT_TRUE((a.manifold.S.array() == b.manifold.S.array()).all());
  EXPECT_EQ(a.report.frames_checked, b.report.frames_checked);
  EXPECT_EQ(a.report.noise_frames, b.report.noise_frames);
}

}  // namespace

TEST(MorphThreads, FieldMorphsRunAtOnceGiveWhatEachGivesAlone) {
  const Shape small = turned_octahedron(0.8, 0.0, 0.0), large = turned_octahedron(1.2, 30.0, 0.3);
  const Morph grow_alone = field_morph_of(small, large), shrink_alone = field_morph_of(large, small);
  ASSERT_GT(grow_alone.manifold.S.rows(), 0);
  ASSERT_TRUE(grow_alone.report.ends_reproduced);
  ASSERT_GE(grow_alone.report.frames_checked, 24);
  Morph grow, shrink;
  std::exception_ptr failed[2];
  auto run = [](Morph& out, const Shape& from, const Shape& to, std::exception_ptr& error) {
    try {
      out = field_morph_of(from, to);
    } catch (...) {
      error = std::current_exception();
    }
  };
  std::thread first(run, std::ref(grow), std::cref(small), std::cref(large), std::ref(failed[0]));
  std::thread second(run, std::ref(shrink), std::cref(large), std::cref(small), std::ref(failed[1]));
  first.join();
  second.join();
  for (const std::exception_ptr& error : failed)
    if (error) std::rethrow_exception(error);
  expect_same_bits(grow, grow_alone);
  expect_same_bits(shrink, shrink_alone);
}
