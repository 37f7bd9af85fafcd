"""Index arrays (simplices, faces, integer attributes) converted to the core's int32.

`np.ascontiguousarray(x, dtype=np.int32)` truncates floats (2.7 -> 2) and wraps
int64 values beyond 32 bits (2**32 -> 0) without a word; `as_indices` refuses
both, naming the array, the entry and its value. The core's bindings check the
same for arrays handed to them directly (cpp/bindings/index_arrays.hpp).
"""

from __future__ import annotations

import numpy as np

from . import _core

_LOW, _HIGH = np.iinfo(np.int32).min, np.iinfo(np.int32).max


def as_indices(values, what: str) -> np.ndarray:
    """`values` as a C-contiguous int32 array of the same shape. Raises
    _core.InputError (an animanifold.Error and ValueError) naming `what` when
    they are not integers or do not fit in 32 bits."""
    array = np.asarray(values)
    if array.size == 0:
        return np.ascontiguousarray(array, dtype=np.int32)
    if array.dtype == bool or not np.issubdtype(array.dtype, np.integer):
        raise _core.InputError(f"{what} must be integer indices, got dtype {array.dtype}")
    if array.dtype.itemsize >= 4 and array.dtype != np.int32:
        flat = array.reshape(-1)
        outside = np.flatnonzero((flat < _LOW) | (flat > _HIGH))
        if outside.size:
            entry = np.unravel_index(outside[0], array.shape)
            raise _core.InputError(
                f"{what} holds {flat[outside[0]]} at {tuple(int(i) for i in entry)}, which does not fit a 32-bit index"
            )
    return np.ascontiguousarray(array, dtype=np.int32)


def as_vertex_indices(values, vertex_count: int, what: str) -> np.ndarray:
    """`as_indices(values, what)`, each entry also checked to name one of `vertex_count` vertices:
    numpy indexing would silently wrap a negative index to the end of the array. Raises
    _core.InputError naming `what`, the entry and its value."""
    indices = as_indices(values, what)
    flat = indices.reshape(-1)
    outside = np.flatnonzero((flat < 0) | (flat >= vertex_count))
    if outside.size:
        entry = np.unravel_index(outside[0], indices.shape)
        raise _core.InputError(
            f"{what} holds {flat[outside[0]]} at {tuple(int(i) for i in entry)}, "
            f"not an index of the {vertex_count} vertices"
        )
    return indices
