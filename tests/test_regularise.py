"""Offline regularisation of a deformation (§4.5.1, issue 5): stretched edges
are split in the undeformed complex and the deformation re-applied until no
edge is longer than ε."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from animanifold.regularisation import _inherit, edges_of, manhattan_lengths
from helpers.shapes import icosphere

METHODS = ("dual", "graph", "uniform")
GRAPH = am.LaplacianOptions(method="graph")
REGULARISED = am.DeformOptions(regularise=am.RegulariseOptions())


def pulled_sphere():
    """An icosphere with its bottom anchored and its top cap pulled 4 radii up."""
    v, f = icosphere(2)
    z = v[:, 2]
    return v, f, np.flatnonzero(z < -0.5), np.flatnonzero(z > 0.8), am.handle_transform(translation=[0, 0, 4.0], dimension=3)


def stitched(times=(0.0, 1.0, 2.0, 3.0)):
    v, f = icosphere(1)
    frames = [v + [0.2 * t, 0, 0] for t in times]
    u = np.arange(len(times) * len(v), dtype=float).reshape(len(times), len(v))
    return am.stitch(frames, f, times, vertex_attributes={"u": u}), len(v)


def mean_length(points, simplices):
    return manhattan_lengths(points, edges_of(simplices, len(points))).mean()


def max_length(points, simplices):
    return manhattan_lengths(points, edges_of(simplices, len(points))).max()


@pytest.mark.parametrize("method", METHODS)
def test_large_extrusion_is_regularised_into_a_valid_manifold(method):
    v, f, anchors, handles, T = pulled_sphere()
    plain = am.laplacian_deform(v, f, anchors, handles, T, options=am.LaplacianOptions(method=method))
    mean0 = mean_length(v, f)
    assert max_length(plain, f) / mean0 > 3.0, "the extrusion should stretch edges well past 2x the mean"

    points, simplices, maps = am.regularise(v, f, anchors, handles, T, laplacian=am.LaplacianOptions(method=method))
    assert maps.converged and maps.iterations >= 1 and sum(maps.splits) == len(maps.new_vertices) > 0
    assert maps.epsilon == pytest.approx(2 * mean0)
    ratio = max_length(points, simplices) / mean0
    assert ratio <= 2.0 + 1e-9, f"max/mean edge length {ratio:.3f} after regularisation"
    assert maps.max_edge_length == pytest.approx(max_length(points, simplices))
    check = _core.check_manifold(simplices)
    assert check.is_oriented_manifold and check.boundary_facets == 0
    # The input vertices come first and keep their rest positions; anchors stay, handles follow T.
    np.testing.assert_array_equal(maps.rest_points[: len(v)], v)
    np.testing.assert_allclose(points[anchors], v[anchors], atol=1e-9)
    np.testing.assert_allclose(points[handles], v[handles] + [0, 0, 4.0], atol=1e-9)
    assert np.isin(anchors, maps.anchors).all() and np.isin(handles, maps.handles).all()
    assert maps.parent_simplex.shape == (len(simplices),) and maps.parent_simplex.max() < len(f)
    # Every output simplex lies inside its input parent (rest positions, barycentric refinement).
    rest = maps.rest_points
    centroid = rest[simplices].mean(1)
    tri = v[f[maps.parent_simplex]]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.abs(np.einsum("ij,ij->i", centroid - tri[:, 0], n)).max() < 1e-9


def test_zero_motion_changes_nothing_even_with_edges_longer_than_epsilon():
    v, f, anchors, handles, _ = pulled_sphere()
    for method in METHODS:
        points, simplices, maps = am.regularise(v, f, anchors, handles, np.eye(4), laplacian=am.LaplacianOptions(method=method))
        np.testing.assert_array_equal(simplices, f)
        np.testing.assert_allclose(points, v, atol=1e-12)
        assert maps.splits == () and maps.converged and len(maps.new_vertices) == 0
    # A stitched manifold with long time edges (far beyond 2x the mean): still nothing to split.
    m, k = stitched(times=(0.0, 10.0, 30.0))
    lengths = manhattan_lengths(m.points, edges_of(m.simplices, len(m.points)))
    assert lengths.max() > 2 * lengths.mean()
    out = am.deform(m, np.arange(k), np.arange(2 * k, 3 * k), np.eye(5), options=REGULARISED)
    np.testing.assert_array_equal(out.simplices, m.simplices)
    np.testing.assert_allclose(out.points, m.points, atol=1e-9)
    assert out.metadata["regularisation"]["iterations"] == 0


def test_iteration_cap_is_reported():
    v, f, anchors, handles, T = pulled_sphere()
    _, _, full = am.regularise(v, f, anchors, handles, T, laplacian=GRAPH)
    assert full.converged and full.iterations >= 2
    points, simplices, capped = am.regularise(v, f, anchors, handles, T, laplacian=GRAPH, options=am.RegulariseOptions(max_iterations=1))
    assert not capped.converged and capped.iterations == 1
    assert capped.max_edge_length > capped.epsilon
    points, simplices, none = am.regularise(v, f, anchors, handles, T, laplacian=GRAPH, options=am.RegulariseOptions(max_iterations=0))
    assert not none.converged and none.splits == ()
    np.testing.assert_array_equal(simplices, f)
    np.testing.assert_allclose(points, am.laplacian_deform(v, f, anchors, handles, T, options=GRAPH), atol=1e-12)


def test_stretched_handle_edges_split_into_handles_that_follow_the_transform():
    """A handle scaled up 3x stretches edges between two handles: their midpoints
    become handles and land exactly where the transform puts them; explicit
    handle positions give the same result (targets interpolated)."""
    v, f, anchors, handles, _ = pulled_sphere()
    T = am.handle_transform(scale=3.0, center=[0, 0, 1.0], translation=[0, 0, 2.0], dimension=3)
    points, simplices, maps = am.regularise(v, f, anchors, handles, T, laplacian=GRAPH)
    assert maps.converged
    new_handles = np.setdiff1d(maps.handles, handles)
    assert len(new_handles) > 0 and (new_handles >= len(v)).all()
    rest = maps.rest_points
    expected = rest[maps.handles] @ T[:3, :3].T + T[:3, 3]
    np.testing.assert_allclose(points[maps.handles], expected, atol=1e-9)
    moved = v[handles] @ T[:3, :3].T + T[:3, 3]
    p2, s2, m2 = am.regularise(v, f, anchors, handles, handle_positions=moved, laplacian=GRAPH)
    np.testing.assert_array_equal(s2, simplices)
    np.testing.assert_allclose(p2, points, atol=1e-9)
    np.testing.assert_array_equal(m2.handles, maps.handles)


def test_inheritance_rule():
    flags = np.array([True, True, False, False, False, False])
    parents = np.array([[0, 1, -1], [1, 2, -1], [0, 4, -1]])  # vertex 5 has parent 4, made in the same batch
    _inherit(flags, parents, np.array([4, 3, 5]))
    np.testing.assert_array_equal(flags, [True, True, False, False, True, True])


def test_animation_manifold_deform_regularises_and_keeps_anchored_frames():
    m, k = stitched()
    anchors = np.arange(2 * k)  # keyframes 0 and 1
    handles = np.arange(3 * k, 4 * k)  # keyframe 3
    T = am.handle_transform(translation=[3.0, 0, 0, 0], dimension=4)
    plain = am.deform(m, anchors, handles, T)
    out = am.deform(m, anchors, handles, T, options=REGULARISED)
    summary = out.metadata["regularisation"]
    assert summary["converged"] and summary["added_vertices"] == len(out.points) - len(m.points) > 0
    assert out.check().is_oriented_manifold
    mean0 = mean_length(m.points, m.simplices)
    assert max_length(plain.points, plain.simplices) / mean0 > 2.5
    assert max_length(out.points, out.simplices) / mean0 <= 2.0 + 1e-9
    np.testing.assert_allclose(out.points[anchors], m.points[anchors], atol=1e-9)
    # Frames between the anchored keyframes are untouched (no split there, nothing moved). The
    # split simplices are no longer prisms: the result slices its tets, so m's tets are the reference.
    assert out.prisms is None
    tets = am.AnimationManifold(m.core_complex, m.metadata)
    for t in (0.0, 0.5, 1.0):
        a, b = tets.slice(t), out.slice(t)
        np.testing.assert_allclose(np.sort(b.vertices, axis=0), np.sort(a.vertices, axis=0), atol=1e-9)
        assert len(a.faces) == len(b.faces)
    # Vertex attributes are interpolated at the new vertices (u is affine along each edge).
    u = out.vertex_attributes["u"][:, 0]
    np.testing.assert_array_equal(u[: len(m.points)], m.vertex_attributes["u"][:, 0])
    assert np.isfinite(u).all() and len(u) == len(out.points)
    # The last keyframe moved with the handles.
    assert out.slice(3.0).vertices[:, 0].mean() == pytest.approx(m.slice(3.0).vertices[:, 0].mean() + 3.0, abs=1e-6)


def test_axis_weights_change_the_measure():
    m, k = stitched(times=(0.0, 4.0, 8.0))
    anchors, handles = np.arange(k), np.arange(2 * k, 3 * k)
    T = am.handle_transform(translation=[2.0, 0, 0, 0], dimension=4)
    w = np.array([1.0, 1.0, 1.0, 0.0])  # measure edges in space only
    out = am.deform(m, anchors, handles, T, options=am.DeformOptions(GRAPH, am.RegulariseOptions(axis_weights=w)))
    spatial = out.metadata["regularisation"]
    timed = am.deform(m, anchors, handles, T, options=am.DeformOptions(GRAPH, am.RegulariseOptions())).metadata["regularisation"]
    spatial_mean = manhattan_lengths(m.points, edges_of(m.simplices, len(m.points)), w).mean()
    assert spatial["epsilon"] == pytest.approx(2 * spatial_mean) and spatial["epsilon"] < timed["epsilon"]
    assert spatial["converged"] and spatial["added_vertices"] > 0
    assert manhattan_lengths(out.points, edges_of(out.simplices, len(out.points)), w).max() <= spatial["epsilon"] + 1e-9


def test_input_errors():
    v, f, anchors, handles, T = pulled_sphere()
    with pytest.raises(ValueError, match="exactly one of transform"):
        am.regularise(v, f, anchors, handles)
    with pytest.raises(ValueError, match="exactly one of transform"):
        am.regularise(v, f, anchors, handles, T, handle_positions=v[handles])
    with pytest.raises(ValueError, match="epsilon must be a positive number"):
        am.RegulariseOptions(epsilon=-1.0)
    with pytest.raises(ValueError, match="axis_weights must be 3"):
        am.regularise(v, f, anchors, handles, T, options=am.RegulariseOptions(axis_weights=[1, 1]))
    with pytest.raises(ValueError, match="max_iterations"):
        am.RegulariseOptions(max_iterations=-1)
    with pytest.raises(ValueError, match=r"handle_positions must be \(\d+, 3\)"):
        am.regularise(v, f, anchors, handles, handle_positions=v[:3])
    with pytest.raises(ValueError, match="both an anchor and a handle"):
        am.regularise(v, f, anchors, anchors, T)


def test_option_errors_name_the_field():
    with pytest.raises(ValueError, match="axis_weights must be finite non-negative"):
        am.RegulariseOptions(axis_weights=[1, -1, 1])
    with pytest.raises(ValueError, match="unknown method 'cotan'"):
        am.LaplacianOptions(method="cotan")
    with pytest.raises(ValueError, match="unknown boundary rule 'pin'"):
        am.LaplacianOptions(boundary="pin")
    with pytest.raises(ValueError, match="steps must be 'auto' or an integer >= 1"):
        am.LaplacianOptions(steps=0)
    with pytest.raises(ValueError, match="restore_iterations"):
        am.LaplacianOptions(restore_iterations=-1)
    with pytest.raises(ValueError, match="tolerance must be a finite non-negative number"):
        am.LaplacianOptions(tolerance=float("nan"))
    with pytest.raises(ValueError, match="regularise must be None or a RegulariseOptions"):
        am.DeformOptions(regularise=True)
    assert am.RegulariseOptions(axis_weights=np.array([1, 1, 0.5])).axis_weights == (1.0, 1.0, 0.5)
