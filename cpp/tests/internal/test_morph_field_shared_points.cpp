// Points of the two ends that coincide but for rounding get one position
// (share_coincident_points, morph_field_internal.hpp).
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

// The end of a tetrahedron input (0,0,0), (1,0,0), (0,1,0) and `apex`, with
// box corners at +-3 and the points `more` after them; its bottom face split
// at a Steiner point `steiner` (the last point) into three.
EndMesh tetrahedron_end(const Eigen::RowVector3d& apex, const PointMatrix& more, const Eigen::RowVector3d& steiner) {
  EndMesh end;
  end.points.resize(4 + 8 + more.rows() + 1, 3);
  end.points.topRows(4) << 0, 0, 0, 1, 0, 0, 0, 1, 0, apex;
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a) end.points(4 + c, a) = (c >> a) & 1 ? 3.0 : -3.0;
  end.points.middleRows(12, more.rows()) = more;
  const Index s = end.points.rows() - 1;
  end.points.row(s) = steiner;
  end.constraints.resize(6, 3);
  end.constraints << 0, 2, s, 2, 1, s, 1, 0, s, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  end.input_points = 4;
  end.free_points = static_cast<Index>(more.rows());
  end.steiner_points = 1;
  return end;
}

const Eigen::RowVector3d kSteiner(0.3, 0.3, 0.0);

}  // namespace

TEST(SharedPoints, ATargetSteinerPointRoundedAwayFromTheSourcesTakesItsPosition) {
  EndMesh source = tetrahedron_end({0, 0, 1}, PointMatrix(0, 3), kSteiner);
  EndMesh target = tetrahedron_end({0, 0, 1}, PointMatrix(0, 3), {std::nextafter(0.3, 1.0), 0.3, 0.0});
  const PointMatrix before = source.points;
  EXPECT_EQ(share_coincident_points(source, target), 1);
  EXPECT_EQ(target.points, source.points);
  EXPECT_EQ(source.points, before);
}

TEST(SharedPoints, AnInputsVertexStaysAndTheOtherEndsPointMovesOntoIt) {
  // The target's apex (an input vertex) and a free point of the source 4e-16 apart.
  const Eigen::RowVector3d apex(0, 0, 2);
  PointMatrix free(1, 3);
  free << 0, 0, std::nextafter(2.0, 3.0);
  EndMesh source = tetrahedron_end({0, 0, 1}, free, kSteiner);
  EndMesh target = tetrahedron_end(apex, PointMatrix(0, 3), kSteiner);
  const PointMatrix target_before = target.points;
  EXPECT_EQ(share_coincident_points(source, target), 1);
  EXPECT_EQ(target.points, target_before);
  EXPECT_EQ(Eigen::RowVector3d(source.points.row(12)), apex);
}

TEST(SharedPoints, TwoInputVerticesRoundedApartStayAsTheyAreAndTheRestIsShared) {
  // The apexes (input vertices of both) 2e-16 apart, and the Steiner points too.
  const Eigen::RowVector3d steiner(std::nextafter(0.3, 1.0), 0.3, 0.0);
  EndMesh source = tetrahedron_end({0, 0, 1}, PointMatrix(0, 3), kSteiner);
  EndMesh target = tetrahedron_end({0, 0, std::nextafter(1.0, 2.0)}, PointMatrix(0, 3), steiner);
  const PointMatrix source_before = source.points, target_before = target.points;
  EXPECT_EQ(share_coincident_points(source, target), 1);
  EXPECT_EQ(source.points, source_before);
  EXPECT_EQ(target.points.topRows(12), target_before.topRows(12));
  EXPECT_EQ(Eigen::RowVector3d(target.points.row(12)), kSteiner);
}

TEST(SharedPoints, PointsFartherApartThanRoundingAreNotMoved) {
  EndMesh source = tetrahedron_end({0, 0, 1}, PointMatrix(0, 3), kSteiner);
  EndMesh target = tetrahedron_end({0, 0, 1}, PointMatrix(0, 3), {0.3 + 1e-9, 0.3, 0.0});
  const PointMatrix target_before = target.points;
  EXPECT_EQ(share_coincident_points(source, target), 0);
  EXPECT_EQ(target.points, target_before);
}
