"""A stand-in morph whose topological noise is known: a tetrahedron's surface swept over [0, 1]
with an island, the boundary of a small 4-simplex, that lives only between two times (tests of
am.morph_noise and of the morph bench's notes)."""

import numpy as np

import animanifold as am

TETRAHEDRON = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
               np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))


def swept_with_island(start: float, end: float) -> am.AnimationManifold:
    """The tetrahedron swept from t = 0 to 1, and beside it the boundary of a 4-simplex whose time
    extent is [start, end]: every frame strictly between them holds a second piece."""
    swept = am.stitch([TETRAHEDRON[0]] * 2, TETRAHEDRON[1], [0.0, 1.0])
    middle = 0.5 * (start + end)
    corners = np.array([[5, 0, 0, start], [6, 0, 0, middle], [5, 1, 0, middle], [5, 0, 1, middle],
                        [5.3, 0.3, 0.3, end]], float)
    if np.linalg.det(corners[1:] - corners[0]) < 0:
        corners[[1, 2]] = corners[[2, 1]]
    # the facets of a positive 4-simplex, each oriented (-1)^i
    facets = [[j for j in range(5) if j != i] for i in range(5)]
    for i in (1, 3):
        facets[i][0], facets[i][1] = facets[i][1], facets[i][0]
    n = len(swept.points)
    return am.AnimationManifold.from_arrays(np.vstack([swept.points, corners]),
                                            np.vstack([swept.simplices, np.array(facets) + n]))
