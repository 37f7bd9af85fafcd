"""The procedural closed test shapes (animanifold.procedural): each is a closed, outward, oriented
manifold without self-intersections, of the promised genus and size."""

from __future__ import annotations

import numpy as np
import pytest

from animanifold import _core, procedural

# name -> (builder, genus, (min, max) vertices, (min, max) triangles)
SHAPES = {
    "smooth_genus(2)": (lambda: procedural.smooth_genus(2), 2, (1182, 1182), (2368, 2368)),
    "smooth_genus(3)": (lambda: procedural.smooth_genus(3), 3, (1596, 1596), (3200, 3200)),
    "smooth_genus(5)": (lambda: procedural.smooth_genus(5), 5, (2424, 2424), (4864, 4864)),
    "ring_of_holes()": (procedural.ring_of_holes, 4, (4000, 6500), (0, np.inf)),
    "blob()": (procedural.blob, 0, (0, np.inf), (9000, 11000)),
    "thick_genus()": (procedural.thick_genus, 3, (0, np.inf), (11050, 14950)),
    "limbs()": (procedural.limbs, 0, (1000, 20000), (2000, 40000)),
    "flat_box()": (procedural.flat_box, 0, (8, 1000), (12, 2000)),
    "flat_box(3)": (lambda: procedural.flat_box(3), 3, (8, 1000), (12, 2000)),
}


@pytest.fixture(scope="module", params=sorted(SHAPES))
def shape(request):
    build, genus, vertex_range, triangle_range = SHAPES[request.param]
    vertices, faces = build()
    return request.param, vertices, faces, genus, vertex_range, triangle_range


def test_arrays(shape):
    _, vertices, faces, *_ = shape
    assert vertices.dtype == np.float64 and vertices.ndim == 2 and vertices.shape[1] == 3
    assert faces.dtype == np.int32 and faces.ndim == 2 and faces.shape[1] == 3
    assert np.isfinite(vertices).all()
    assert faces.min() == 0 and faces.max() == len(vertices) - 1  # every vertex used
    assert len(np.unique(faces, axis=0)) == len(faces)


def test_closed_oriented_manifold(shape):
    _, _, faces, *_ = shape
    report = _core.check_manifold(faces)
    assert report.boundary_facets == 0, report
    assert report.nonmanifold_facets == 0, report
    assert report.misoriented_facets == 0, report
    assert report.degenerate_simplices == 0, report
    assert report.is_oriented_manifold, report


def test_outward(shape):
    _, vertices, faces, *_ = shape
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    assert volume > 0.0
    areas = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    assert areas.min() > 1e-6 * areas.mean()  # no slivers


def test_no_self_intersections(shape):
    _, vertices, faces, *_ = shape
    assert _core.self_intersections(vertices, faces, 1) == []


def test_genus(shape):
    name, vertices, faces, genus, *_ = shape
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edges = np.unique(np.sort(directed, 1), axis=0)
    assert len(edges) * 2 == len(faces) * 3  # closed: every edge on two faces
    euler = len(vertices) - len(edges) + len(faces)
    assert euler == 2 - 2 * genus, name


def test_size(shape):
    name, vertices, faces, _, (vmin, vmax), (fmin, fmax) = shape
    assert vmin <= len(vertices) <= vmax, (name, len(vertices))
    assert fmin <= len(faces) <= fmax, (name, len(faces))


def test_smooth_genus3_is_smooth_genus_3():
    v3, f3 = procedural.smooth_genus3()
    v, f = procedural.smooth_genus(3)
    np.testing.assert_array_equal(v, v3)
    np.testing.assert_array_equal(f, f3)
    v1, f1 = procedural.smooth_genus3(levels=1)
    np.testing.assert_array_equal(procedural.smooth_genus(3, levels=1)[0], v1)


def test_blob_size_follows_request_and_seed():
    for triangles in (2000, 5000, 20000):
        _, faces = procedural.blob(triangles)
        assert abs(len(faces) - triangles) <= 0.1 * triangles
    a, fa = procedural.blob(seed=1)
    b, fb = procedural.blob(seed=2)
    np.testing.assert_array_equal(fa, fb)
    assert not np.allclose(a, b)
    np.testing.assert_array_equal(procedural.blob(seed=1)[0], a)  # deterministic


def test_blob_is_star_shaped():
    """Radial displacement of a sphere: every triangle faces away from the origin."""
    vertices, faces = procedural.blob()
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    assert (np.einsum("ij,ij->i", a, np.cross(b, c)) > 0).all()


def test_ring_of_holes_genus_follows_holes():
    for holes in (1, 3, 6):
        vertices, faces = procedural.ring_of_holes(holes, levels=0)
        assert _core.check_manifold(faces).is_oriented_manifold
        assert len(vertices) - len(faces) // 2 == 2 - 2 * holes


def test_flat_box_sides_are_flat():
    vertices, faces = procedural.flat_box()
    low, high = vertices.min(0), vertices.max(0)
    np.testing.assert_array_equal(low, -high)  # centred exactly
    on_side = (vertices == low) | (vertices == high)
    assert on_side.any(1).all()  # every vertex lies on a side plane
    # and every triangle lies in one side plane
    assert (on_side[faces].all(1)).any(1).all()


def test_thick_genus_size_follows_request():
    vertices, faces = procedural.thick_genus(2, triangles=20000)
    assert abs(len(faces) - 20000) <= 0.15 * 20000
    assert len(vertices) - len(faces) // 2 == 2 - 2 * 2


@pytest.mark.parametrize(
    "call",
    [
        lambda: procedural.smooth_genus(-1),
        lambda: procedural.smooth_genus(1.5),
        lambda: procedural.ring_of_holes(0),
        lambda: procedural.flat_box(True),
        lambda: procedural.geodesic_sphere(0),
        lambda: procedural.blob(0),
        lambda: procedural.thick_genus(3, triangles=-5),
    ],
)
def test_bad_counts_refused(call):
    with pytest.raises(ValueError):
        call()
