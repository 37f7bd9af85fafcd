"""Merging exact copies of points: closes the seams where vertices were split.

Convert splits a source's vertices along UV seams (UVs are vertex attributes),
which leaves each seam as a boundary of the manifold and of its frames;
subdivision (manifold or frame) would treat those as real boundaries and open
cracks along them. Welding first merges the copies again.
"""

from __future__ import annotations

import numpy as np


def weld_copies(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(kept, new_cells): rows of `points` that are exact copies of an earlier
    row are merged into it (`kept`: the first copies, in order; `new_cells`
    reindexed), or None when nothing is merged or merging would make a cell
    degenerate (then the split version must be used)."""
    unique, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    if len(unique) == len(points):
        return None
    rank = np.empty(len(unique), dtype=np.int64)
    rank[np.argsort(first)] = np.arange(len(unique))
    new_cells = rank[np.asarray(inverse).reshape(-1)][np.asarray(cells, dtype=np.int64)]
    ordered = np.sort(new_cells, axis=1)
    if np.any(ordered[:, 1:] == ordered[:, :-1]):
        return None
    return np.sort(first), new_cells.astype(np.int32)
