#pragma once
// The checks of a complex handed to a Laplacian (laplacian.cpp) or a Deformer
// (deformer.cpp), which share them.

#include "animanifold/types.hpp"

namespace animanifold {

// Throws InputError naming the problem: points neither 3D nor 4D, simplices
// of the wrong size or none, a non-finite coordinate (which vertex), a
// simplex naming a vertex out of range or twice. `what` names the caller's
// object ("a Laplacian", "a Laplacian deformation").
void check_laplacian_input(const PointMatrix& V, const SimplexMatrix& S, const char* what);

}  // namespace animanifold
