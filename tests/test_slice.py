"""Iso-slicing animation manifolds (§2.6, Figure 2.6)."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import cube, face_normals, icosphere, polygon
from helpers.keyframes import TIMES, wobble
from helpers.surface_properties import assert_closed_oriented_surface, edges_of


def canonical_faces(faces: np.ndarray) -> set[tuple[int, ...]]:
    """Faces up to rotation of their indices (orientation kept)."""
    r = np.argmin(faces, axis=1)
    return {tuple(np.roll(f, -i)) for f, i in zip(faces, r)}


@pytest.fixture(scope="module")
def animation():
    v, f = icosphere(2)
    uv = np.stack([np.arctan2(v[:, 1], v[:, 0]), v[:, 2]], 1)
    frames = wobble(v, TIMES)
    m = am.stitch(frames, f, TIMES, vertex_attributes={"uv": uv}, face_attributes={"material_index": np.arange(len(f)) % 4})
    return v, f, uv, frames, m


@pytest.mark.parametrize("i", range(len(TIMES)))
def test_slice_at_keyframe_returns_the_keyframe_exactly(animation, i):
    v, f, uv, frames, m = animation
    k = len(v)
    s = m.slice(TIMES[i])
    # every slice vertex is a manifold vertex of keyframe i (no cut edges, no duplicates)
    assert (s.vertex_edges[:, 0] == s.vertex_edges[:, 1]).all()
    ids = s.vertex_edges[:, 0]
    assert ((ids // k) == i).all()
    assert len(np.unique(ids)) == len(ids) == k
    keyframe_vertex = ids % k
    np.testing.assert_allclose(s.vertices, frames[i][keyframe_vertex], rtol=0, atol=1e-12)
    # same faces, same orientation, up to rotation of indices
    assert len(s.faces) == len(f)
    assert canonical_faces(keyframe_vertex[s.faces]) == canonical_faces(f)
    # attributes come back exactly
    np.testing.assert_array_equal(s.vertex_attributes["uv"], uv[keyframe_vertex])
    assert sorted(s.face_attributes["material_index"].tolist()) == sorted((np.arange(len(f)) % 4).tolist())


def test_between_keyframes_vertices_lie_on_straight_manifold_edges(animation):
    v, f, uv, frames, m = animation
    k = len(v)
    for t in np.linspace(0, 2.5, 23)[1:-1]:
        if np.isclose(TIMES, t).any():
            continue
        s = m.slice(t)
        a, b = s.vertex_edges.T
        seg = np.searchsorted(TIMES, t) - 1  # keyframes seg and seg+1 bracket t
        assert (a // k == seg).all() and (b // k == seg + 1).all(), "cut edges must join the bracketing keyframes"
        lam = (t - TIMES[seg]) / (TIMES[seg + 1] - TIMES[seg])
        np.testing.assert_allclose(s.edge_parameter, lam, atol=1e-12)
        pa, pb = frames[seg][a % k], frames[seg + 1][b % k]
        np.testing.assert_allclose(s.vertices, (1 - lam) * pa + lam * pb, atol=1e-12)
        # vertical edges (same keyframe vertex) are the vertex paths: the linear interpolation
        same = a % k == b % k
        assert same.sum() == k
        np.testing.assert_allclose(s.vertices[same], (1 - lam) * frames[seg][a[same] % k] + lam * frames[seg + 1][a[same] % k], atol=1e-12)


def signed_volume(vertices, faces):
    tri = vertices[faces]
    return np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6


@pytest.mark.parametrize("t", [0.0, 0.15, 0.3, 0.77, 1.05, 2.0, 2.5])
def test_slices_are_closed_with_positive_volume(animation, t):
    *_, m = animation
    s = m.slice(t)
    assert_closed_oriented_surface(s.faces)
    assert signed_volume(s.vertices, s.faces) > 0
    assert (np.linalg.norm(face_normals(s.vertices, s.faces), axis=1) > 0).all(), "a degenerate face was kept"
    np.testing.assert_allclose(np.linalg.norm(s.normals, axis=1), 1, atol=1e-12)


@pytest.mark.parametrize("t", [0.0, 0.15, 0.3, 0.77, 1.05, 2.0, 2.5])
def test_every_face_and_normal_points_outward(t):
    """A sphere that travels and breathes stays star-shaped about its centre in every frame.

    (Under large rotations between keyframes the linear in-betweens can fold:
    the piecewise-linear artifact of §2.2; that is why this uses a gentle motion.)
    """
    v, f = icosphere(2)
    frames = np.stack([v * (1 + 0.4 * np.sin(2 * tk)) + [0.5 * tk, 0.2 * tk * tk, 0] for tk in TIMES])
    s = am.stitch(frames, f, TIMES).slice(t)
    centre = np.array([0.5 * t, 0.2 * t * t, 0])
    fn = face_normals(s.vertices, s.faces)
    assert (np.einsum("ij,ij->i", fn, s.vertices[s.faces].mean(axis=1) - centre) > 0).all(), "a face points inward"
    assert (np.einsum("ij,ij->i", s.normals, s.vertices - centre) > 0).all(), "a smooth normal points inward"


def test_index_and_brute_force_give_the_same_slice(animation):
    *_, m = animation
    slicer = _core.Slicer(m.core_complex)
    for t in [0.0, 0.4, 1.1, 2.5, -1.0, 3.0]:
        a = slicer.slice(3, t, True)
        b = _core._testing.slice(m.core_complex, 3, t)
        assert canonical_faces(a.vertex_edges[a.faces][:, :, 0] * 100000 + a.vertex_edges[a.faces][:, :, 1]) == \
            canonical_faces(b.vertex_edges[b.faces][:, :, 0] * 100000 + b.vertex_edges[b.faces][:, :, 1])


def test_outside_the_time_range_is_empty(animation):
    *_, m = animation
    for t in (-0.5, 2.6):
        s = m.slice(t)
        assert s.vertices.shape == (0, 3) and s.faces.shape == (0, 3)


def translating_cube():
    """The cube [-1,1]^3 moving along x by 2t over t in [0, 1]."""
    v, f = cube()
    return am.stitch([v, v + [2, 0, 0]], f, [0, 1])


def area(vertices, faces):
    return 0.5 * np.linalg.norm(face_normals(vertices, faces), axis=1).sum()


def test_sweep_slice_along_x_matches_the_analytic_solid():
    """At x = 0.5 the cube is present for t in [0, 0.75]: in (y, z, t) a box side 2, 2, 0.75, open at t = 0."""
    m = translating_cube()
    s = m.slice(0.5, axis="x")
    y, z, t = s.vertices.T
    assert (np.abs(y) <= 1 + 1e-12).all() and (np.abs(z) <= 1 + 1e-12).all()
    assert t.min() == pytest.approx(0) and t.max() == pytest.approx(0.75)
    assert area(s.vertices, s.faces) == pytest.approx(4 * 2 * 0.75 + 4, abs=1e-12)
    # normals point out of the box [-1,1]^2 x [0, 0.75]
    mid = s.vertices[s.faces].mean(axis=1) - [0, 0, 0.375]
    assert (np.einsum("ij,ij->i", face_normals(s.vertices, s.faces), mid) > 0).all()
    np.testing.assert_array_less(0, np.einsum("ij,ij->i", s.normals, s.vertices - [0, 0, 0.375]))


def test_sweep_slice_along_y_is_a_sheared_prism():
    """At y = 0.5: {-1+2t <= x <= 1+2t, |z| <= 1, 0 <= t <= 1}, lateral area 4 + 4*sqrt(5)."""
    m = translating_cube()
    s = m.slice(0.5, axis="y")
    x, z, t = s.vertices.T
    assert (x >= -1 + 2 * t - 1e-12).all() and (x <= 1 + 2 * t + 1e-12).all()
    assert area(s.vertices, s.faces) == pytest.approx(4 + 4 * np.sqrt(5), abs=1e-12)
    centre = np.stack([2 * t, 0 * t, t], 1)
    mid_faces = s.vertices[s.faces].mean(axis=1)
    c_faces = np.stack([2 * mid_faces[:, 2], 0 * mid_faces[:, 2], mid_faces[:, 2]], 1)
    assert (np.einsum("ij,ij->i", face_normals(s.vertices, s.faces), mid_faces - c_faces) > 0).all()
    assert (np.einsum("ij,ij->i", s.normals, s.vertices - centre)[np.abs(z) < 1 - 1e-9] > 0).all()
    # the open ends are the only boundary: boundary edges lie at t = 0 or t = 1
    directed = {tuple(e) for e in edges_of(s.faces)}
    open_edges = [e for e in directed if (e[1], e[0]) not in directed]
    assert open_edges and all(np.isin(t[list(e)], (0.0, 1.0)).all() for e in open_edges)


def test_sweep_slice_along_z_is_outward():
    m = translating_cube()
    s = m.slice(0.0, axis="z")  # (x, y, t): a sheared square prism
    x, y, t = s.vertices.T
    mid = s.vertices[s.faces].mean(axis=1)
    centre = np.stack([2 * mid[:, 2], 0 * mid[:, 2], mid[:, 2]], 1)
    assert (np.einsum("ij,ij->i", face_normals(s.vertices, s.faces), mid - centre) > 0).all()
    assert area(s.vertices, s.faces) == pytest.approx(4 + 4 * np.sqrt(5), abs=1e-12)


def test_contour_animation_slices_to_closed_ccw_polygons():
    v, e = polygon(9)
    times = [0.0, 0.5, 2.0]
    frames = np.stack([v, 1.5 * v + [0.3, 0.1], 0.7 * v])
    m = am.stitch(frames, e, times)
    for i, t in enumerate(times):
        s = m.slice(t)
        ids = s.vertex_edges[:, 0] % 9
        assert canonical_faces(ids[s.faces]) == canonical_faces(e)
        np.testing.assert_allclose(s.vertices, frames[i][ids], atol=1e-12)
    s = m.slice(1.0)
    # closed: every vertex starts one segment and ends one; counter-clockwise: positive signed area
    assert sorted(s.faces[:, 0].tolist()) == sorted(s.faces[:, 1].tolist()) == list(range(len(s.vertices)))
    p, q = s.vertices[s.faces[:, 0]], s.vertices[s.faces[:, 1]]
    assert 0.5 * np.sum(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]) > 0
    centre = s.vertices.mean(axis=0)
    assert (np.einsum("ij,ij->i", s.normals, s.vertices - centre) > 0).all()


def test_bad_axis_and_value_raise(animation):
    *_, m = animation
    with pytest.raises(ValueError, match="unknown axis"):
        m.slice(0.5, axis="w")
    with pytest.raises(ValueError, match="not finite"):
        m.slice(float("nan"))
    c = am.stitch(np.stack([polygon(5)[0]] * 2), polygon(5)[1], [0, 1])
    with pytest.raises(ValueError, match="no z axis"):
        c.slice(0.0, axis="z")


def test_interval_frame_moves_to_a_fresh_slice_inside_the_topology_interval(animation):
    *_, m = animation
    assert m.topology_interval(0.3, "t") is None  # a keyframe: the topology changes there
    assert m.topology_interval(-1.0, "t") is None and m.topology_interval(2.6) is None
    assert m.topology_interval(0.5) == (0.3, 1.0)
    frame = m.interval_frame(0.4)
    assert frame.interval == (0.3, 1.0) and frame.value == 0.4
    for t in (0.31, 0.55, 0.999):
        moved, fresh = frame.at(t), m.slice(t)
        np.testing.assert_array_equal(moved.faces, fresh.faces)
        np.testing.assert_array_equal(moved.vertex_edges, fresh.vertex_edges)
        np.testing.assert_allclose(moved.vertices, fresh.vertices, atol=1e-12)
        np.testing.assert_allclose(moved.edge_parameter, fresh.edge_parameter, atol=1e-12)
        np.testing.assert_allclose(moved.normals, fresh.normals, atol=1e-12)
        np.testing.assert_allclose(moved.vertex_attributes["uv"], fresh.vertex_attributes["uv"], atol=1e-12)
        np.testing.assert_array_equal(moved.face_attributes["material_index"], fresh.face_attributes["material_index"])
    only_uv = frame.at(0.5, attributes=["uv"], normals=False)
    assert list(only_uv.vertex_attributes) == ["uv"]
    np.testing.assert_allclose(only_uv.normals, m.slice(0.5).normals, atol=1e-12)  # computed when read
    with pytest.raises(ValueError, match="not in the topology interval"):
        frame.at(1.2)
    with pytest.raises(ValueError, match="no topology interval"):
        m.interval_frame(0.3)  # a keyframe
    with pytest.raises(ValueError, match="no topology interval"):
        m.interval_frame(2.6)  # after the last keyframe
    # sweep views too
    lo, hi = m.topology_interval(0.05, "x")
    inside = 0.5 * (lo + hi)
    np.testing.assert_allclose(m.interval_frame(0.05, "x").at(inside).vertices, m.slice(inside, axis="x").vertices,
                               atol=1e-12)


def test_topology_interval_is_bounded_by_the_nearest_vertex_coordinates(animation):
    *_, m = animation
    for axis in range(4):
        values = np.unique(m.points[:, axis])
        for i in (1, len(values) // 2, len(values) - 1):
            lo, hi = values[i - 1], values[i]
            assert m.topology_interval(0.5 * (lo + hi), axis) == (lo, hi)
            assert m.topology_interval(lo, axis) is None


def test_threads_slicing_a_fresh_manifold_at_once_get_the_serial_slices(animation):
    v, f, uv, frames, _ = animation
    values = [0.2, 0.5, 0.7, 1.4]

    def fresh():
        return am.stitch(frames, f, TIMES, vertex_attributes={"uv": uv})

    serial_slicer = _core.Slicer(fresh()._complex)  # the tets' slice (m.slice plays prisms between keys)
    serial = [serial_slicer.slice(3, t) for t in values]
    for _ in range(5):  # each round a fresh manifold: its indices are built by the racing threads
        m = fresh()
        slicer = _core.Slicer(m._complex)
        barrier = threading.Barrier(len(values))

        def cut(t):
            barrier.wait()
            return slicer.slice(m.dimension - 1, t)

        with ThreadPoolExecutor(len(values)) as pool:
            results = list(pool.map(cut, values))
        for got, want in zip(results, serial):
            np.testing.assert_array_equal(got.faces, want.faces)
            np.testing.assert_array_equal(got.vertices, want.vertices)
