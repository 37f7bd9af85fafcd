"""Cavities of closed surfaces (animanifold.cavities): bubbles enclosed in a solid are the
shells whose faces point into them (negative enclosed volume)."""

from __future__ import annotations

import numpy as np
import pytest

from animanifold.cavities import cavities, shell_volumes, surface_components
from helpers.shapes import icosphere, torus


def test_a_hollow_sphere_has_one_cavity_of_the_inner_spheres_volume():
    v, f = icosphere(2)
    inner = 0.5 * v
    hollow = np.vstack([v, inner]), np.vstack([f, f[:, ::-1] + len(v)])
    outer_volume = shell_volumes(v, f)[0]
    volumes = shell_volumes(*hollow)
    assert sorted(volumes) == pytest.approx([-outer_volume / 8, outer_volume], rel=1e-12)
    assert cavities(*hollow) == pytest.approx([outer_volume / 8], rel=1e-12)


def test_separate_and_genus_one_shells_are_no_cavities():
    v, f = icosphere(2)
    apart = np.vstack([v, v + 3]), np.vstack([f, f + len(v)])
    assert len(shell_volumes(*apart)) == 2 and len(cavities(*apart)) == 0
    tv, tf = torus()
    assert len(cavities(tv, tf)) == 0 and shell_volumes(tv, tf)[0] > 0


def test_components_join_faces_through_shared_vertices_only():
    faces = np.array([[0, 1, 2], [2, 3, 4], [5, 6, 7], [7, 8, 5]])
    labels = surface_components(9, faces)
    assert labels[0] == labels[1] and labels[2] == labels[3] and labels[0] != labels[2]


def reference_components(vertex_count: int, faces: np.ndarray) -> list[set[int]]:
    """The faces of each component as sets, by a breadth-first walk over shared vertices."""
    faces_at = [[] for _ in range(vertex_count)]
    for i, face in enumerate(faces):
        for corner in face:
            faces_at[corner].append(i)
    seen, out = set(), []
    for start in range(len(faces)):
        if start in seen:
            continue
        part, queue = {start}, [start]
        while queue:
            for corner in faces[queue.pop()]:
                for other in faces_at[corner]:
                    if other not in part:
                        part.add(other)
                        queue.append(other)
        seen |= part
        out.append(part)
    return out


@pytest.mark.parametrize("seed", range(6))
def test_components_are_those_a_walk_over_shared_vertices_finds(seed):
    """Random triangles on few vertices (many small pieces, shuffled indices) and a long strip
    (a diameter of thousands of faces): the labels part the faces exactly as a walk does."""
    rng = np.random.default_rng(seed)
    vertex_count = 3000
    scattered = rng.integers(0, vertex_count, size=(800, 3))
    strip_vertices = rng.permutation(vertex_count)
    strip = np.stack([strip_vertices[:-2], strip_vertices[1:-1], strip_vertices[2:]], axis=1)[::-1]
    for faces in (scattered, strip, np.vstack([scattered[:100], strip[::3]])):
        labels = surface_components(vertex_count, faces)
        found = {}
        for i, label in enumerate(labels):
            found.setdefault(int(label), set()).add(i)
        assert sorted(map(sorted, found.values())) == sorted(map(sorted, reference_components(vertex_count, faces)))
