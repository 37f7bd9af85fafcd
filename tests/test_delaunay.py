"""Delaunay triangulations (chapter 5): Qhull in any dimension, TetGen and CGAL conforming."""

from __future__ import annotations

import numpy as np
import pytest

from animanifold import _core
from helpers.shapes import icosphere


def circumsphere(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre and radius of the sphere through d+1 points in R^d."""
    a = 2 * (points[1:] - points[0])
    b = (points[1:] ** 2).sum(1) - (points[0] ** 2).sum()
    centre = np.linalg.solve(a, b)
    return centre, float(np.linalg.norm(points[0] - centre))


@pytest.mark.parametrize("dimension", [2, 3, 4])
def test_qhull_delaunay_is_delaunay_and_fills_the_hull(rng, dimension):
    points = rng.random((40, dimension))
    simplices, flat, _ = _core._testing.delaunay(points)
    assert flat == 0
    volumes = _core._testing.signed_volumes(points, simplices)
    assert (volumes > 0).all()
    # empty circumspheres (brute force)
    for s in simplices:
        centre, radius = circumsphere(points[s])
        others = np.delete(np.arange(len(points)), s)
        assert (np.linalg.norm(points[others] - centre, axis=1) >= radius * (1 - 1e-9)).all()
    # a conforming complex of the convex hull: no boundary facet is shared, all facets manifold
    report = _core.check_manifold(simplices)
    assert report.is_oriented_manifold


def perturbed_sphere(rng, subdivisions, scale=(1, 1, 1)):
    v, f = icosphere(subdivisions)
    return v * (1 + 0.05 * rng.random((len(v), 1))) * scale, f


def test_tetgen_conforming_delaunay_keeps_the_surface_and_is_delaunay(rng):
    v, f = perturbed_sphere(rng, 2)
    r = _core._testing.conforming_delaunay_3d(v, f)
    assert r.is_delaunay and r.non_delaunay_faces == 0
    np.testing.assert_array_equal(r.points[: len(v)], v)
    # every refined constraint is a face of the tetrahedralization and lies in its parent triangle
    assert len(_core._testing.missing_facets(r.simplices, r.constraints)) == 0
    parent_normals = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    tri = r.points[r.constraints]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert (np.einsum("ij,ij->i", normals, parent_normals[r.constraint_parent]) > 0).all()
    # the refined surface covers the input exactly (same total area, closed and oriented)
    area = lambda n: 0.5 * np.linalg.norm(n, axis=1).sum()
    assert area(normals) == pytest.approx(area(parent_normals), rel=1e-12)
    assert _core.check_manifold(r.constraints).is_oriented_manifold
    assert _core.check_manifold(r.constraints).boundary_facets == 0


def test_theorem_5_2_1_fill_between_two_conforming_sections_contains_both(rng):
    v, f = perturbed_sphere(rng, 2)
    w, g = perturbed_sphere(rng, 2, scale=(1.5, 1, 0.7))
    s, t = _core._testing.conforming_delaunay_3d(v, f), _core._testing.conforming_delaunay_3d(w, g)
    ps, pt = s.points, t.points
    fill_points = np.concatenate([np.c_[ps, np.zeros(len(ps))], np.c_[pt, np.ones(len(pt))]])
    fill, flat, _ = _core._testing.delaunay(fill_points)
    assert flat == 0
    assert len(_core._testing.missing_facets(fill, s.constraints)) == 0
    assert len(_core._testing.missing_facets(fill, t.constraints + len(ps))) == 0


def test_theorem_fails_visibly_without_conforming(rng):
    """Without conforming a concave surface, some constraint triangles are not in the fill: reported, not hidden."""
    v, f = icosphere(2)
    v = v * (1 + 0.02 * rng.random((len(v), 1)))
    v[:, 2] *= np.where(v[:, 0] > 0.3, 0.2, 1.0)  # a deep dent: non-Delaunay surface triangles
    fill_points = np.concatenate([np.c_[v, np.zeros(len(v))], np.c_[v * 1.2, np.ones(len(v))]])
    fill, _, _ = _core._testing.delaunay(fill_points)
    assert len(_core._testing.missing_facets(fill, f)) > 0


def test_cgal_conforming_delaunay_2d_splits_a_non_delaunay_edge():
    # the long edge (0, 1) crosses the Delaunay edge between the two close points 2 and 3
    p = np.array([[0.0, 0], [10, 0], [5, 0.5], [5, -0.5], [0, 3], [10, -3]])
    e = np.array([[0, 1], [4, 0], [1, 5]], np.int32)
    r = _core._testing.conforming_delaunay_2d(p, e)
    assert r.is_delaunay
    assert len(r.points) > len(p), "the long edge needs Steiner points"
    np.testing.assert_array_equal(r.points[: len(p)], p)
    # the refined segments chain each input edge from its start to its end, in order
    for edge_id, (a, b) in enumerate(e):
        chain = r.constraints[r.constraint_parent == edge_id]
        assert chain[0, 0] == a and chain[-1, 1] == b
        np.testing.assert_array_equal(chain[1:, 0], chain[:-1, 1])
    assert len(_core._testing.missing_facets(r.simplices, r.constraints)) == 0
    assert (_core._testing.signed_volumes(r.points, r.simplices) > 0).all()


def test_bad_input_is_refused(rng):
    with pytest.raises(ValueError, match="at least 4 points"):
        _core._testing.delaunay(rng.random((3, 3)))
    with pytest.raises(ValueError, match="constraint triangle 0 refers to point 99"):
        _core._testing.conforming_delaunay_3d(rng.random((10, 3)), np.array([[0, 1, 99]], np.int32))
    with pytest.raises(ValueError, match="point 2 coincides with point 0"):
        _core._testing.conforming_delaunay_2d(np.array([[0.0, 0], [1, 0], [0, 0], [0, 1]]), np.array([[0, 1]], np.int32))


def test_exact_delaunay_agrees_with_qhull_on_points_in_general_position():
    rng = np.random.default_rng(7)
    for d in (3, 4):
        points = rng.normal(size=(300, d))
        exact, flat, _ = _core._testing.delaunay_exact(points)
        qhull, _, _ = _core._testing.delaunay(points)
        assert flat == 0
        assert {tuple(sorted(s)) for s in exact} == {tuple(sorted(s)) for s in qhull}
        edges = points[exact[:, 1:]] - points[exact[:, :1]]
        assert (np.linalg.det(edges) > 0).all()  # positively oriented
    with pytest.raises(ValueError, match="points 0 and 5 coincide"):
        _core._testing.delaunay_exact(np.vstack([points[:5], points[:1]]))


def test_exact_delaunay_of_two_parallel_planes_keeps_both_triangulations():
    """A morph's fill: every cell of each plane's own Delaunay triangulation is a facet (Theorem 5.2.1)."""
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(60, 3)), rng.normal(size=(50, 3)) * 0.7
    points = np.vstack([np.c_[a, np.zeros(60)], np.c_[b, np.ones(50)]])
    simplices, flat, _ = _core._testing.delaunay_exact(points)
    assert flat == 0
    for offset, plane in ((0, a), (60, b)):
        cells, _, _ = _core._testing.delaunay_exact(plane)
        assert len(_core._testing.missing_facets(simplices, (cells + offset).astype(np.int32))) == 0
