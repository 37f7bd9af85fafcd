// certify_space_time (morph_field.hpp): a field morph's space-time
// triangulation is certified embedded, and each way it could fail to be (a
// layer out of time order, a cell turned over, a simplex missing from a
// transition slab) is found and named. morph() reports the
// certificate and then checks crossings on the middle frame only.
#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/morph.hpp"
#include "animanifold/threads.hpp"
#include "morph_field.hpp"
#include "morph_field_internal.hpp"

#include "../fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <cmath>
#include <vector>

using namespace animanifold;

namespace {

MorphOptions small_field_morph() {
  MorphOptions options;
  options.method = MorphMethod::Field;
  options.field_resolution = 6;
  options.field_layers = 5;
  return options;
}

// The field morph of an octahedron growing to twice its size.
FieldMorph growing_octahedron_morph() {
  PointMatrix VS;
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  const MorphOptions options = small_field_morph();
  StageClock clock(options);
  return field_morph(VS, FS, 2.0 * VS, FS, options, clock);
}

// Its space-time triangulation.
SpaceTimeTriangulation growing_octahedron() { return growing_octahedron_morph().space_time; }

SimplexMatrix without_first_row(const SimplexMatrix& S) { return S.bottomRows(S.rows() - 1); }

bool names(const SpaceTimeCertificate& certificate, const std::string& part) {
  return !certificate.embedded && certificate.failure.find(part) != std::string::npos;
}

}  // namespace

TEST(MorphFieldCertificate, AFieldMorphsSpaceTimeIsCertifiedEmbedded) {
  const SpaceTimeTriangulation space_time = growing_octahedron();
  ASSERT_GT(space_time.source.transition.rows(), 0);
  const SpaceTimeCertificate certificate = certify_space_time(space_time);
  EXPECT_TRUE(certificate.embedded) << certificate.failure;
  EXPECT_EQ(certificate.failure, "");
}

TEST(MorphFieldCertificate, TheCoversCheckedBesideTheFillAreThoseOfTheSidesItReturns) {
  const FieldMorph morph = growing_octahedron_morph();
  const SpaceTimeTriangulation& space_time = morph.space_time;
  for (const auto& [side, cover] : {std::pair{&space_time.source, &morph.covers[0]},
                                    std::pair{&space_time.target, &morph.covers[1]}}) {
    const SideCover again = check_side_cover(side->points, side->plain, side->cells, side->transition, side->times);
    EXPECT_EQ(cover->cells, again.cells);
    EXPECT_EQ(cover->transition, again.transition);
  }
  EXPECT_TRUE(certify_space_time(morph.space_time, &morph.covers).embedded);
  // What the covers say is what the certificate reports.
  std::array<SideCover, 2> covers = morph.covers;
  covers[1].transition = "3 simplices: 1 flat or inverted;";
  const SpaceTimeCertificate certificate = certify_space_time(morph.space_time, &covers);
  EXPECT_TRUE(names(certificate, "the target's transition slab does not tile its region once (3 simplices"))
      << certificate.failure;
}

TEST(MorphFieldCertificate, ALayerOutOfTimeOrderIsFound) {
  SpaceTimeTriangulation space_time = growing_octahedron();
  std::swap(space_time.target.times[1], space_time.target.times[2]);
  EXPECT_TRUE(names(certify_space_time(space_time), "times do not increase"));
}

TEST(MorphFieldCertificate, ACellTurnedOverIsFoundAndNamed) {
  SpaceTimeTriangulation space_time = growing_octahedron();
  std::swap(space_time.source.cells(0, 0), space_time.source.cells(0, 1));
  const SpaceTimeCertificate certificate = certify_space_time(space_time);
  EXPECT_TRUE(names(certificate, "the source's cells")) << certificate.failure;
  EXPECT_TRUE(names(certificate, "1 flat or inverted")) << certificate.failure;
}

TEST(MorphFieldCertificate, ASimplexMissingFromATransitionSlabIsFound) {
  SpaceTimeTriangulation space_time = growing_octahedron();
  space_time.target.transition = without_first_row(space_time.target.transition);
  EXPECT_TRUE(names(certify_space_time(space_time), "the target's transition slab"));
}

TEST(MorphFieldCertificate, SimplicesFlatButForRoundingThatTheZeroSetPassesFailIt) {
  SpaceTimeTriangulation space_time = growing_octahedron();
  EXPECT_EQ(space_time.flat_crossed_simplices, 0);
  space_time.flat_crossed_simplices = 3;
  const SpaceTimeCertificate certificate = certify_space_time(space_time);
  EXPECT_TRUE(names(certificate, "3 simplices the zero set passes through are flat")) << certificate.failure;
}

// The prism over a tet, between times 0 and `dt`, as rows of X (the tet's
// four corners at time 0, then at dt) and its four staircase simplices.
std::array<morph_field::Simplex4, 4> prism(const Eigen::Matrix<double, 4, 3>& tet, double dt, PointMatrix& X) {
  X.resize(8, 4);
  for (int v = 0; v < 4; ++v) X.row(v) << tet.row(v), 0.0, X.row(4 + v) << tet.row(v), dt;
  const Index cell[4] = {0, 1, 2, 3};
  std::array<morph_field::Simplex4, 4> out;
  morph_field::prism_simplices(cell, 0, 4, out.data());
  return out;
}

TEST(MorphFieldCertificate, APrismOverAFlatCellIsFlatButForRoundingInAnyUnitOfTime) {
  // A planar quad's four cocircular corners, one lifted off its plane by
  // rounding (as a torus's quads are): the tet between its two diagonals.
  Eigen::Matrix<double, 4, 3> flat, proper;
  flat << 0, 0, 0, 0.1, 0, 0, 0.1, 0.1, 1e-18, 0, 0.1, 0;
  proper = flat;
  proper(2, 2) = 0.01;
  for (const double range : {1.0, 250.0}) {  // seconds, or a Blender scene's frames
    const double layer = range / 17, time_scale = 2.0 / range;
    PointMatrix X;
    for (const auto& s : prism(flat, layer, X)) EXPECT_TRUE(morph_field::flat_to_rounding(X, s, time_scale)) << range;
    for (const auto& s : prism(proper, layer, X)) EXPECT_FALSE(morph_field::flat_to_rounding(X, s, time_scale)) << range;
  }
}

TEST(MorphFieldCertificate, TheMorphReportsItAndChecksCrossingsOnTheMiddleFrame) {
  PointMatrix VS;
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  const Morph result = morph(VS, FS, 2.0 * VS, FS, small_field_morph());
  EXPECT_TRUE(result.report.crossings_certified) << result.report.certificate_failure;
  EXPECT_EQ(result.report.certificate_failure, "");
  EXPECT_EQ(result.report.crossing_frames_checked, 1);
  EXPECT_GE(result.report.frames_checked, 24);
  EXPECT_TRUE(result.report.crossing_frames.empty());
}

// points_off_flat_cells (morph_field_internal.hpp): a flat cell of four
// cocircular points of the input gets a point on each side of its plane, on
// the normal through its centre; a proper tet, or a flat one with a corner
// off the input, gets none.
TEST(MorphFieldFlatCells, AFlatCellOfTheInputGetsAPointOnEachSideOfItsPlane) {
  PointMatrix P(5, 3);
  P << 0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0, 1, 1, 1;  // a square in z = 0 (cocircular), and an apex
  SimplexMatrix cells(2, 4);
  cells << 0, 1, 2, 3,  // flat
      0, 1, 2, 4;       // proper
  const std::vector<bool> on_surface(5, true);
  const PointMatrix off = morph_field::points_off_flat_cells(cells, P, on_surface, 1.0);
  ASSERT_EQ(off.rows(), 2);
  const double size = std::sqrt(8.0);  // the square's diagonal, its longest edge
  std::vector<double> heights;
  for (Index r = 0; r < 2; ++r) {
    EXPECT_NEAR(off(r, 0), 1.0, 1e-12);
    EXPECT_NEAR(off(r, 1), 1.0, 1e-12);
    heights.push_back(off(r, 2) / size);
  }
  std::sort(heights.begin(), heights.end());
  EXPECT_LT(heights[0], -0.2);  // one on each side, a third of the size or so off the plane
  EXPECT_GT(heights[1], 0.2);
  EXPECT_NE(-heights[0], heights[1]);  // at unequal heights: not cospherical with the corners again

  // Twice the reach, twice as far.
  const PointMatrix farther = morph_field::points_off_flat_cells(cells, P, on_surface, 2.0);
  ASSERT_EQ(farther.rows(), 2);
  EXPECT_NEAR(std::abs(farther(0, 2)), 2 * std::abs(off(0, 2)), 1e-12);

  // A corner off the input is a free point (jittered: no tie of the grid's),
  // so the cell is left alone.
  std::vector<bool> three(5, true);
  three[3] = false;
  EXPECT_EQ(morph_field::points_off_flat_cells(cells, P, three, 1.0).rows(), 0);

  // Lifted off the plane by far more than rounding: a proper tet.
  P(3, 2) = 1e-3;
  EXPECT_EQ(morph_field::points_off_flat_cells(cells, P, on_surface, 1.0).rows(), 0);
}

// A flat octahedron (its poles at +-0.2) whose four tets all hold the chord
// between the poles: through its inside, with only the input's points for
// corners. A small target around the middle leaves the poles outside: the
// unsplit cells put the middle outside at every weight past the end, while
// the blend there is inside (a regular octahedron, scaled).
TEST(MorphFieldChords, AChordWhoseCellsSampleTheBlendWithTheWrongSignGetsAPointAtItsMiddle) {
  PointMatrix VS;
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  VS.col(2) *= 0.2;
  SimplexMatrix cells(4, 4);
  cells << 4, 5, 0, 2, 4, 5, 2, 1, 4, 5, 1, 3, 4, 5, 3, 0;  // around the axis from pole 4 to pole 5
  const std::vector<bool> on_surface(6, true);
  const SignedDistance dS(VS, FS);
  auto chord_points = [&](double target_scale, double w) {
    PointMatrix VT;
    SimplexMatrix FT;
    fixtures::octahedron(VT, FT);
    VT *= target_scale;
    const SignedDistance dT(VT, FT);
    morph_field::EndDistances at_points;
    at_points.extend(VS, dS, dT);
    return morph_field::undersampled_chords(cells, VS, on_surface, FS, dS, dS, dT, at_points, {w}, 1.0);
  };
  const PointMatrix middle = chord_points(0.1, 0.5);
  ASSERT_EQ(middle.rows(), 1);
  EXPECT_LT(middle.row(0).norm(), 0.05 * 0.2);  // the chord's middle, off it by a little
  EXPECT_GT(middle.row(0).norm(), 0.0);
  EXPECT_LT(dS.distances(middle)(0), 0.0);

  // A target holding the whole source: the cells' signs are the blend's.
  EXPECT_EQ(chord_points(3.0, 0.5).rows(), 0);
}

namespace {

// Work beside that only ends when it is stopped: a test that finishes shows
// the stop reached it, whatever the machine's speed.
void until_stopped(const std::function<void()>& stop_poll) {
  for (;;) {
    stop_poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// The message side_by_side() throws, "" when it returns.
std::string thrown_by(const std::function<void(const std::function<void()>&)>& beside, const std::function<void()>& here) {
  try {
    morph_field::side_by_side(beside, here, {});
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MorphFieldSideBySide, ACancelHereOrFromThePollStopsTheWorkBeside) {
  const int before = thread_count();
  set_thread_count(2);
  EXPECT_THROW(morph_field::side_by_side(until_stopped, [] { throw Cancelled(); }, {}), Cancelled);
  // Here done at once; the poll, called while this thread waits, cancels.
  EXPECT_THROW(morph_field::side_by_side(until_stopped, [] {}, [] { throw Cancelled(); }), Cancelled);
  set_thread_count(before);
}

TEST(MorphFieldSideBySide, TheWorkBesidesOwnFailureComesFirstAsWhenTheyRunInTurn) {
  const int before = thread_count();
  for (const int threads : {1, 2}) {
    set_thread_count(threads);
    auto fails = [](const char* what) { return [what](const auto&...) { throw MeshingError(what); }; };
    EXPECT_EQ(thrown_by(fails("the source cannot be meshed"), fails("the target cannot be meshed")),
              "the source cannot be meshed") << threads << " threads";
    EXPECT_EQ(thrown_by([](const auto&) {}, fails("the target cannot be meshed")), "the target cannot be meshed");
    EXPECT_EQ(thrown_by(fails("the source cannot be meshed"), [] {}), "the source cannot be meshed");
    int done = 0;
    EXPECT_EQ(thrown_by([&](const auto&) { ++done; }, [&] { ++done; }), "");
    EXPECT_EQ(done, 2);
  }
  set_thread_count(before);
}

TEST(MorphFieldEnds, BothEndsMeshedSideBySideAreTheEndsMeshedInTurn) {
  PointMatrix VS, corners(8, 3);
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  for (int c = 0; c < 8; ++c)
    corners.row(c) << (c & 1 ? 3.0 : -3.0), (c & 2 ? 3.0 : -3.0), (c & 4 ? 3.0 : -3.0);
  const PointMatrix VT = 2.0 * VS, free_points = 1.3 * VT;  // beyond the target's corners
  const int before = thread_count();
  std::array<morph_field::EndMesh, 2> ends[2];
  for (const int threads : {1, 2}) {
    set_thread_count(threads);
    ends[threads - 1] = morph_field::conform_ends({VS, FS, free_points}, {VT, FS, free_points}, corners, {}, 0);
  }
  set_thread_count(before);
  for (int side = 0; side < 2; ++side) {
    EXPECT_EQ(ends[0][side].points, ends[1][side].points) << side;
    EXPECT_EQ(ends[0][side].constraints, ends[1][side].constraints) << side;
  }
  // Each end is its own input's: the source's points start with its vertices.
  EXPECT_EQ(PointMatrix(ends[1][0].points.topRows(VS.rows())), VS);
  EXPECT_EQ(PointMatrix(ends[1][1].points.topRows(VT.rows())), VT);
}

// The fill is built beside the halves, and each half's stacks are extracted
// by whichever thread is free first: on two threads the morph is the one
// built in turn on one, bit for bit, its certificate included.
TEST(MorphFieldThreads, AFieldMorphOnTwoThreadsIsTheMorphOnOne) {
  PointMatrix VS;
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  const PointMatrix VT = 2.0 * VS + PointMatrix::Constant(VS.rows(), 3, 0.3);
  const int before = thread_count();
  FieldMorph morphs[2];
  for (const int threads : {1, 2}) {
    set_thread_count(threads);
    const MorphOptions options = small_field_morph();
    StageClock clock(options);
    morphs[threads - 1] = field_morph(VS, FS, VT, FS, options, clock);
  }
  set_thread_count(before);
  const Complex &one = morphs[0].morph.manifold, &two = morphs[1].morph.manifold;
  ASSERT_GT(one.S.rows(), 0);
  EXPECT_EQ(one.V, two.V);
  EXPECT_EQ(one.S, two.S);
  EXPECT_TRUE(check_manifold(one.S).is_oriented_manifold());
  for (const FieldMorph& morph : morphs) {
    const SpaceTimeCertificate certificate = certify_space_time(morph.space_time);
    EXPECT_TRUE(certificate.embedded) << certificate.failure;
  }
  EXPECT_EQ(morphs[0].space_time.source.transition, morphs[1].space_time.source.transition);
  EXPECT_EQ(morphs[0].space_time.target.transition, morphs[1].space_time.target.transition);
}
