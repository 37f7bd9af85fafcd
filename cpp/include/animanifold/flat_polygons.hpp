// Flat convex polygons of a triangle mesh, triangulated again as fans from
// their centre.
//
// Blender's cylinder and cone caps are n-gons of cocircular points (with the
// rest of the primitive, all cospherical), which Blender splits into
// triangles between rim points only: ears and strips with angles of π/n at
// the rim. The conforming mesher needs each of those chords as a Delaunay
// edge of points that have none of their own (any chord of cocircular points
// is as Delaunay as any other, and the perturbation picks at random): it
// splits them and splits again near the rim, where chords meet at π/n. A
// 64-sided cylinder -> a torus: with the caps as Blender gives them, TetGen
// leaves hundreds of points it cannot move off the caps, the fill holds many
// of the torus's free vertices near the plane, and the frames run through
// themselves and hold a bubble of a large share of the volume before t1;
// with fans from one rim vertex, TetGen finishes at no perturbation. With the caps as fans from their centre (Blender's "Triangle
// Fan" fill), every triangle is Delaunay in its plane and the morph has
// none of that. The surface is the same: only the triangulation of each
// flat polygon changes, with one vertex added at its centre (the frames at
// the ends reproduce the input as it was given).
#pragma once

#include "animanifold/types.hpp"

namespace animanifold {

struct FannedMesh {
  PointMatrix V;  // the input's vertices, in order, then one centre per fanned polygon
  SimplexMatrix F;  // the faces not fanned, in order, then the fans
  Index polygons = 0;  // how many flat polygons were fanned
};

// Inputs:
//   V, F         #V by 3 points, #F by 3 triangles, closed and outward
//   min_corners  the fewest corners a polygon needs to be fanned
// Outputs:
//   FannedMesh: the input's vertices then the centres, faces not fanned then the fans
// Throws: nothing
//
// The closed, outward triangle mesh (V, F) (#V by 3, #F by 3) with every
// flat convex polygon of at least `min_corners` corners triangulated again as
// a fan from the mean of its corners. A flat polygon is a set of
// edge-connected faces facing the same way and lying within 1e-10 of the
// size (bounding-box diagonal) of one face's plane, that make a disc with all
// its vertices on its boundary (no vertex inside: a subdivided face, or one
// that already is a fan from its centre, is left alone) whose boundary is
// strictly convex (no straight corner: a voxel model's row of squares stays
// as it is). Quads and triangles (fewer than `min_corners`) are left as they
// are: a cube's faces stay two triangles.
FannedMesh fan_flat_polygons(const PointMatrix& V, const SimplexMatrix& F, Index min_corners = 6);

}  // namespace animanifold
