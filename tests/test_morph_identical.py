"""Identical source and target with the skeleton method: the rockerArm ambiguity of Figure 8.9.

Stripping (§8.5) leaves bumps or dents in the frames in between when S = T. With the
skeleton method the fill over cells outside both inputs is removed (the inputs coincide
there: `shared_prisms` in morph_skeleton.hpp), so every frame is the input itself: within
rounding of it, closed, oriented, of the same volume, and the hole space is never entered.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from animanifold.meshio import read_mesh
from helpers.shapes import torus
from helpers.contours import blob, polygon_area, polygons
from helpers.surface_properties import assert_closed_oriented_surface, enclosed_volume, euler_characteristic
from helpers.shared_files import shared_mesh
from helpers.seed_morph import skeleton_morph

# Frames strictly inside the range, some away from any round fraction.
TIMES = [0.01, 0.1, 0.25, 0.37, 0.5, 0.61, 0.75, 0.9, 0.99]


def surface_distance(vertices, faces, other_vertices, other_faces) -> float:
    """Two-sided distance between two surfaces (or polylines), over vertices and face centres."""
    a = np.vstack([vertices, vertices[faces].mean(1)])
    b = np.vstack([other_vertices, other_vertices[other_faces].mean(1)])
    return max(_core.distances_to_surface(a, other_vertices, other_faces).max(),
               _core.distances_to_surface(b, vertices, faces).max())


def loop_area(vertices, edges) -> float:
    p, q = vertices[edges[:, 0]], vertices[edges[:, 1]]
    return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]))


def check_identical_morph(shape):
    vertices, faces = shape
    diagonal = np.linalg.norm(np.ptp(vertices, axis=0))
    m = skeleton_morph(shape, shape)
    report = m.validity
    assert report["inputs_coincide"] and report["shared_stripped_simplices"] > 0, report
    assert report["source_free_vertices"] == report["target_free_vertices"] == 0  # nothing pushed
    assert report["ends_reproduced"] and report["inverted_simplices"] == 0, report
    assert not report["frames_cross_themselves"], report["crossing_frames"]
    # The shared hole space is the whole concavity, and no frame enters it: none is kept to cut with.
    assert report["shared_hole_volume"] > 0 and m.hole_space is None and report["holes_preserved"]
    assert m.check().is_oriented_manifold
    for t in TIMES:
        frame = m.slice(t)
        assert surface_distance(frame.vertices, frame.faces, vertices, faces) <= 1e-9 * diagonal, t
        if vertices.shape[1] == 3:
            assert_closed_oriented_surface(frame.faces)
            assert euler_characteristic(frame.faces) == euler_characteristic(faces)
            assert enclosed_volume(frame.vertices, frame.faces) == pytest.approx(enclosed_volume(vertices, faces),
                                                                                  rel=1e-9)
        else:  # closed counter-clockwise loops enclosing the contour's area
            assert sorted(frame.faces[:, 0].tolist()) == sorted(frame.faces[:, 1].tolist())
            assert polygon_area(frame) == pytest.approx(loop_area(vertices, faces), rel=1e-9)
    return m


def test_identical_tori_morph_into_the_torus_at_every_frame():
    check_identical_morph(torus(wobble=0.2))


def test_identical_genus_3_models_morph_into_the_model_at_every_frame(shared_data):
    check_identical_morph(read_mesh(shared_mesh(shared_data, "3holes.off")))


def test_identical_concave_contours_morph_into_the_contour_at_every_frame():
    check_identical_morph(polygons(blob(48, 1.0, (0, 0), 0.45, 5)))


def refuse_hole_space(vertices, faces, *, interrupted=None):
    """A stand-in for CGAL refusing a real model's hole space ("Unauthorized intersections of
    constraints" on a CAD-like part): the morph's handling must not depend on finding such a model."""
    raise am.BooleanError("CGAL failed while computing the hole space of the shape: Unauthorized intersections "
                          "of constraints")


def test_identical_inputs_need_no_hole_space_when_cgal_cannot_compute_it(monkeypatch):
    monkeypatch.setattr(sys.modules["animanifold.morph_pipeline"], "hole_space", refuse_hole_space)
    shape = torus(wobble=0.2)
    m = skeleton_morph(shape, shape)
    report = m.validity
    assert report["inputs_coincide"] and m.hole_space is None and report["holes_preserved"]
    assert any("none is needed: the inputs coincide" in e and "Unauthorized" in e for e in report["hole_errors"])
    vertices, faces = shape
    diagonal = np.linalg.norm(np.ptp(vertices, axis=0))
    for t in TIMES:
        frame = m.slice(t)
        assert surface_distance(frame.vertices, frame.faces, vertices, faces) <= 1e-9 * diagonal, t


def test_a_hole_space_cgal_refuses_stops_the_morph_before_it_runs(monkeypatch):
    from helpers.shapes import icosphere

    monkeypatch.setattr(sys.modules["animanifold.morph_pipeline"], "hole_space", refuse_hole_space)
    ran = []
    monkeypatch.setattr(_core, "morph", lambda *a, **k: ran.append(1))
    with pytest.raises(am.BooleanError) as error:
        skeleton_morph(icosphere(2), torus(wobble=0.2))
    message = str(error.value)
    assert "the hole space of the source cannot be computed" in message and "Unauthorized" in message
    assert "method='field'" in message  # the way out
    assert not ran  # minutes of morph are not spent first, nor twice by the retry
