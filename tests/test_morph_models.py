"""Morphs from a sphere to the shared test models bunny.off (3,485 vertices) and
decimated-knight.off (502 vertices, sharp creases of 9° and 17°).

TetGen's -D alone leaves refined faces of these models that are not Delaunay (the bunny 24 of
9,482 with the external skeleton points a morph adds, the knight 87 of 1,932): the conforming stage
mends them (cpp/include/animanifold/conforming_mend.hpp). Then the morph must be valid like any
other: ends reproduced, nothing inverted, every frame a closed, consistently oriented surface.
"""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere
from helpers.surface_properties import assert_closed_oriented_surface, enclosed_volume, euler_characteristic
from helpers.shared_files import shared_mesh
from helpers.seed_morph import skeleton_morph

MODELS = ["bunny.off", "decimated-knight.off"]
TIMES = [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0]


def load(shared_data, name):
    v, f = am.read_mesh(shared_mesh(shared_data, name))
    return np.ascontiguousarray(v, dtype=np.float64), np.ascontiguousarray(f, dtype=np.int32)


def sphere_around(v):
    """The brief's source: an icosphere through the model's farthest vertex from its centroid."""
    s, f = icosphere(4)
    centre = v.mean(0)
    return s * np.linalg.norm(v - centre, axis=1).max() + centre, f


@pytest.mark.parametrize("model", MODELS)
def test_the_conforming_fill_of_the_model_is_delaunay(shared_data, model):
    """The model with its external skeleton points, as the morph conforms it (without its perturbation)."""
    v, f = load(shared_data, model)
    size = np.linalg.norm(np.ptp(v, axis=0))
    k = _core._testing.external_skeleton_points(v, f, 1e-3 * size)
    r = _core._testing.conforming_delaunay_3d(np.vstack([v, k]), f)
    assert r.is_delaunay and r.non_delaunay_faces == 0, r.non_delaunay_faces
    constraints, points = r.constraints, r.points
    assert len(_core._testing.missing_facets(_core._testing.delaunay_exact(points)[0], constraints)) == 0
    # the points added (TetGen's and the mending's) lie on the model, which the refined faces tile
    added = points[len(v) + len(k):]
    assert len(added) >= r.mended_points > 0
    assert _core.distances_to_surface(added, v, f).max() < 1e-12 * size
    area = lambda p, t: 0.5 * np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]), axis=1).sum()
    assert area(points, constraints) == pytest.approx(area(v, f), rel=1e-12)
    report = _core.check_manifold(constraints)
    assert report.is_oriented_manifold and report.boundary_facets == 0


@pytest.mark.parametrize("model", MODELS)
def test_sphere_to_model(shared_data, model):
    v, f = load(shared_data, model)
    sphere = sphere_around(v)
    m = skeleton_morph(sphere, (v, f))
    report = m.validity
    assert report["source_conforming"] and report["target_conforming"]
    assert report["missing_source_faces"] == 0 and report["missing_target_faces"] == 0
    assert report["ends_reproduced"], (report["source_distance"], report["target_distance"])
    assert report["inverted_simplices"] == 0
    assert m.check().is_oriented_manifold
    assert not report["frames_cross_themselves"], report["crossing_frames"]
    for t in TIMES:
        for frame in (m.slice(t, honour_holes=False), m.slice(t)):
            assert_closed_oriented_surface(frame.faces)
            assert enclosed_volume(frame.vertices, frame.faces) > 0
    # the ends are the inputs: genus 0 both, and the same solids
    for t, (pv, pf) in ((0.0, sphere), (1.0, (v, f))):
        frame = m.slice(t)
        assert euler_characteristic(frame.faces) == 2
        assert enclosed_volume(frame.vertices, frame.faces) == pytest.approx(enclosed_volume(pv, pf), rel=1e-9)
