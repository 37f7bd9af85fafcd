"""Wording shared by the add-on's messages: the article before an object type, and what a
change of a mesh's connectivity between two samples is, when its counts stay the same."""

from __future__ import annotations

import numpy as np


def with_article(word: str) -> str:
    """'an armature', 'an empty', 'a curve': the word with its indefinite article."""
    return f"{'an' if word[:1].lower() in 'aeiou' else 'a'} {word}"


def object_type(obj) -> str:
    """The object's type in lower case with its article: 'an armature'."""
    return with_article(obj.type.lower().replace("_", " "))


def connectivity_change(poly_start: np.ndarray, loop_vertex: np.ndarray,
                        ref_poly_start: np.ndarray, ref_loop_vertex: np.ndarray) -> str:
    """What differs between two meshes' faces (poly_start (P,), loop_vertex (L,) each) with
    equal vertex and face counts: the first face whose corner count or vertices differ."""
    P = min(len(poly_start), len(ref_poly_start))
    if len(loop_vertex) != len(ref_loop_vertex) or not np.array_equal(poly_start[:P], ref_poly_start[:P]):
        diff = np.flatnonzero(poly_start[:P] != ref_poly_start[:P])
        face = max(int(diff[0]) - 1, 0) if len(diff) else P - 1
        return f"face {face} has another number of corners"
    loop = int(np.flatnonzero(loop_vertex != ref_loop_vertex)[0])
    face = int(np.searchsorted(poly_start, loop, side="right")) - 1
    lo = int(poly_start[face])
    hi = int(poly_start[face + 1]) if face + 1 < len(poly_start) else len(loop_vertex)
    now = ", ".join(str(int(v)) for v in loop_vertex[lo:hi])
    was = ", ".join(str(int(v)) for v in ref_loop_vertex[lo:hi])
    return f"face {face} joins vertices ({now}) instead of ({was})"
