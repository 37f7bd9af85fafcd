// certify_space_time (morph_field.hpp): a field morph's space-time
// triangulation is certified embedded, and each way it could fail to be (a
// layer out of time order, a cell turned over, a simplex missing from a
// transition slab) is found and named. morph() reports the
// certificate and then checks crossings on the middle frame only.
#include "animanifold/morph.hpp"
#include "morph_field.hpp"
#include "morph_field_internal.hpp"

#include "../fixtures.hpp"

#include <gtest/gtest.h>

using namespace animanifold;

namespace {

MorphOptions small_field_morph() {
  MorphOptions options;
  options.method = MorphMethod::Field;
  options.field_resolution = 6;
  options.field_layers = 5;
  return options;
}

// The space-time triangulation of an octahedron growing to twice its size.
SpaceTimeTriangulation growing_octahedron() {
  PointMatrix VS;
  SimplexMatrix FS;
  fixtures::octahedron(VS, FS);
  const MorphOptions options = small_field_morph();
  StageClock clock(options);
  return field_morph(VS, FS, 2.0 * VS, FS, options, clock).space_time;
}

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
