"""Welding an animation manifold: its exact copies of points merged, so seams close.

Stitching splits vertices along UV seams (UVs are vertex attributes), which
leaves each seam a boundary of the manifold; subdivision would open cracks
along it. :func:`weld` merges the copies first (:mod:`animanifold.seams`).
"""

from __future__ import annotations

import numpy as np

from .manifold import AnimationManifold
from .seams import weld_copies


def weld(manifold: AnimationManifold) -> AnimationManifold:
    """`manifold` with exact copies of points merged (seams closed).

    Merged points keep the first copy's vertex attributes, so UVs are smeared
    in the cells along a seam; simplex attributes, metadata (but the
    keyframe vertex and face counts, which no longer hold) and the hole space
    are kept. Returns `manifold` itself when nothing merges or merging would
    make a cell degenerate.
    """
    copies = weld_copies(manifold.points, manifold.simplices)
    if copies is None:
        return manifold
    kept, simplices = copies
    vertex_attributes = {k: np.asarray(v)[kept] for k, v in manifold.vertex_attributes.items()}
    metadata = {k: v for k, v in manifold.metadata.items() if k not in ("keyframe_vertices", "keyframe_faces")}
    return AnimationManifold.from_arrays(manifold.points[kept], simplices, vertex_attributes,
                                         dict(manifold.simplex_attributes), metadata, manifold.hole_space)
