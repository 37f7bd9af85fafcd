"""Stitching keyframes into an animation manifold (§2.2)."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.keyframes import TIMES, wobble
from helpers.shapes import cube, icosphere, polygon


@pytest.fixture
def sphere_manifold():
    v, f = icosphere(2)
    return v, f, wobble(v, TIMES), am.stitch(wobble(v, TIMES), f, TIMES)


def test_tet_count_is_exactly_three_per_face_per_segment(sphere_manifold):
    v, f, frames, m = sphere_manifold
    assert m.simplices.shape == (3 * len(f) * (len(TIMES) - 1), 4)
    assert m.points.shape == (len(TIMES) * len(v), 4)
    assert m.time_range == (0.0, 2.5)


def test_manifold_is_conforming_and_consistently_oriented(sphere_manifold):
    *_, m = sphere_manifold
    report = m.check()
    assert report.nonmanifold_facets == 0
    assert report.misoriented_facets == 0
    assert report.degenerate_simplices == 0
    assert report.is_oriented_manifold
    # no duplicate tets
    assert len(np.unique(np.sort(m.simplices, axis=1), axis=0)) == len(m.simplices)


def test_boundary_is_first_keyframe_as_is_and_last_keyframe_reversed(sphere_manifold):
    v, f, frames, m = sphere_manifold
    k = len(v)
    boundary = m.boundary()
    first = boundary[(boundary < k).all(axis=1)]
    last = boundary[(boundary >= (len(TIMES) - 1) * k).all(axis=1)]
    assert len(first) + len(last) == len(boundary) == 2 * len(f)

    def canonical(tris):  # rotate each triangle so its smallest index comes first
        r = np.argmin(tris, axis=1)
        rolled = np.stack([np.roll(t, -i) for t, i in zip(tris, r)])
        return {tuple(t) for t in rolled}

    assert canonical(first) == canonical(f)
    assert canonical(last - (len(TIMES) - 1) * k) == canonical(f[:, [1, 0, 2]])


def test_manifold_normals_point_outward_in_space():
    """For a translating shape the spatial part of every tet's wedge normal is the face's outward normal."""
    v, f = icosphere(2)
    shift = np.array([0.7, -0.2, 0.4])
    frames = np.stack([v + shift * t for t in TIMES])
    m = am.stitch(frames, f, TIMES)
    n = _core._testing.simplex_normals(m.points, m.simplices)
    centroid = m.points[m.simplices].mean(axis=1)
    centre = shift * centroid[:, 3:4]
    assert (np.einsum("ij,ij->i", n[:, :3], centroid[:, :3] - centre) > 0).all()
    # and the time component is what keeps the normal orthogonal to the motion (n . (shift, 1) = 0)
    np.testing.assert_allclose(n[:, :3] @ shift + n[:, 3], 0, atol=1e-12)


def test_tets_keep_positive_orientation_in_a_static_reference():
    """A shape that does not move: every tet has the tent orientation, so spatial normals are outward."""
    v, f = cube()
    m = am.stitch([v, v, v], f, [0, 1, 2])
    n = _core._testing.simplex_normals(m.points, m.simplices)
    c = m.points[m.simplices].mean(axis=1)
    assert (np.einsum("ij,ij->i", n[:, :3], c[:, :3]) > 0).all()


def test_contours_stitch_into_triangles_in_r3():
    v, e = polygon(7)
    frames = np.stack([v, 1.5 * v + [0.2, 0], 0.5 * v])
    m = am.stitch(frames, e, [0, 1, 3])
    assert m.simplices.shape == (2 * 7 * 2, 3)
    assert m.points.shape == (21, 3)
    report = m.check()
    assert report.is_oriented_manifold and report.boundary_facets == 14


def test_the_manifold_check_is_a_bound_report_with_a_plain_dict_for_json(sphere_manifold):
    v, f, _, m = sphere_manifold
    report = m.check()
    assert isinstance(report, _core.ManifoldReport)
    plain = report.to_dict()
    assert plain == {"interior_facets": report.interior_facets, "boundary_facets": report.boundary_facets,
                     "nonmanifold_facets": 0, "misoriented_facets": 0, "degenerate_simplices": 0,
                     "is_oriented_manifold": True}
    assert report.boundary_facets == 2 * len(f)  # the first and last keyframe
    assert repr(report) == f"ManifoldReport({plain})"


def test_attributes_are_carried(sphere_manifold):
    v, f, frames, _ = sphere_manifold
    uv = v[:, :2] * 0.5 + 0.5
    material = np.arange(len(f)) % 3
    m = am.stitch(frames, f, TIMES, vertex_attributes={"uv": uv}, face_attributes={"material_index": material})
    assert m.vertex_attributes["uv"].shape == (len(m.points), 2)
    np.testing.assert_array_equal(m.vertex_attributes["uv"][: len(v)], uv)
    np.testing.assert_array_equal(m.vertex_attributes["uv"][-len(v):], uv)
    mat = m.simplex_attributes["material_index"][:, 0]
    # simplices of one prism are consecutive: 3 per face per segment
    np.testing.assert_array_equal(mat, np.tile(np.repeat(material, 3), len(TIMES) - 1))


def test_per_keyframe_vertex_attributes(sphere_manifold):
    v, f, frames, _ = sphere_manifold
    weight = np.stack([np.full(len(v), float(i)) for i in range(len(TIMES))])  # (m, k)
    m = am.stitch(frames, f, TIMES, vertex_attributes={"w": weight})
    np.testing.assert_array_equal(m.vertex_attributes["w"][:, 0], np.repeat(np.arange(len(TIMES)), len(v)))


def test_arrays_are_read_only_views_without_copies(sphere_manifold):
    *_, m = sphere_manifold
    p1, p2 = m.points, m.points
    assert not p1.flags.writeable
    assert p1.__array_interface__["data"][0] == p2.__array_interface__["data"][0]
    with pytest.raises(ValueError):
        p1[0, 0] = 1.0
