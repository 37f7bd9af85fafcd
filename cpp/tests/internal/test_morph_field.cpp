// certify_space_time (morph_field.hpp): a field morph's space-time
// triangulation is certified embedded, and each way it could fail to be (a
// layer out of time order, a cell turned over, a simplex missing from a
// transition slab) is found and named. morph() reports the
// certificate and then checks crossings on the middle frame only.
#include "animanifold/morph.hpp"
#include "morph_field.hpp"

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
