"""Stand-in morphs whose frames' topology is known: a surface swept over [0, 1] with, for a while,
the boundary of a small 4-simplex beside it (an island, a piece of its own) or inside it, turned
inwards (a bubble). Tests of am.morph_noise and of the morph bench's notes."""

import numpy as np

import animanifold as am

TETRAHEDRON = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
               np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))


def swept_with_island(start: float, end: float, surface=TETRAHEDRON, corner=(5.0, 0.0, 0.0), size: float = 1.0,
                      bubble: bool = False) -> am.AnimationManifold:
    """`surface` swept from t = 0 to 1, and the boundary of a 4-simplex at `corner` (`size` across)
    whose time extent is [start, end]: every frame strictly between them holds its slice, outward
    (an island) or, with `bubble`, inward (a cavity, for a corner inside the surface)."""
    swept = am.stitch([surface[0]] * 2, surface[1], [0.0, 1.0])
    middle = 0.5 * (start + end)
    offsets = size * np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.3, 0.3, 0.3]])
    corners = np.column_stack([np.asarray(corner) + offsets, [start, middle, middle, middle, end]])
    if np.linalg.det(corners[1:] - corners[0]) < 0:
        corners[[1, 2]] = corners[[2, 1]]
    # the facets of the positive 4-simplex, oriented so that its slices enclose positive volume
    # (an island) or negative (a bubble), as test_morph_noise checks
    facets = [[j for j in range(5) if j != i] for i in range(5)]
    for i in ((1, 3) if bubble else (0, 2, 4)):
        facets[i][0], facets[i][1] = facets[i][1], facets[i][0]
    n = len(swept.points)
    return am.AnimationManifold.from_arrays(np.vstack([swept.points, corners]),
                                            np.vstack([swept.simplices, np.array(facets) + n]))
