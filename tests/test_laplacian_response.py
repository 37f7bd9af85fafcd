"""A Deformer's deform by a transform: the solution is affine in the transform, so the
Deformer solves once for its base and its response to each homogeneous coordinate of the
handles, and then combines them (cpp/src/deformer_response.hpp). These tests compare that
with a fresh sparse solve (deform to the same handle positions), after restore too, and
on 1 and 2 threads."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from helpers.shapes import icosphere


@pytest.fixture(autouse=True)
def restore_thread_count():
    before = am.threads()
    yield
    am.set_threads(before)


def sphere_manifold():
    """An animated icosphere in R^4: tets, with boundary at both ends."""
    v, f = icosphere(2)
    frames = [v * (1 + 0.2 * i) + [0.3 * i, 0, 0] for i in range(4)]
    m = am.stitch(frames, f, np.arange(4, dtype=float))
    return np.ascontiguousarray(m.points), np.ascontiguousarray(m.simplices)


def cases():
    v, f = icosphere(3)
    p, s = sphere_manifold()
    out = []
    for method in ("dual", "uniform", "graph", "cotangent"):
        out.append((f"surface-{method}", v, f, method, 0.0))
    for method in ("dual", "uniform", "graph"):
        out.append((f"manifold-{method}", p, s, method, 0.0))
    out.append(("surface-dual-soft", v, f, "dual", 2.0))
    out.append(("manifold-uniform-soft", p, s, "uniform", 2.0))
    return out


CASES = cases()


def constraints(points):
    x = points[:, 0]
    lo, hi = np.quantile(x, [0.2, 0.8])
    return np.flatnonzero(x <= lo), np.flatnonzero(x >= hi)


def transforms(points, handles):
    D = points.shape[1]
    centre = points[handles].mean(0)
    R = am.rotation_matrix([0, 0, 1], 0.7) if D == 3 else am.rotation_matrix([1, 1, 0], 0.5)[:3, :3]
    shear = np.eye(D)
    shear[0, 1] = 0.3
    return [
        am.handle_transform(rotation=R, translation=[0.2] * D, center=centre, dimension=D),
        am.handle_transform(translation=[0.0] * (D - 1) + [-0.4], dimension=D),
        am.handle_transform(rotation=shear, center=centre, dimension=D),  # an affine map, not a motion
    ]


def moved(points, handles, T):
    D = points.shape[1]
    return points[handles] @ T[:D, :D].T + T[:D, D]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_deform_by_a_transform_equals_a_fresh_solve(case):
    _, v, f, method, weight = case
    anchors, handles = constraints(v)
    d = am.Deformer(v, f, anchors, handles, method, constraint_weight=weight)
    assert d.info.grown == 0  # grown handles follow the transform, not a fresh solve's positions
    fresh = am.Deformer(v, f, anchors, handles, method, constraint_weight=weight)
    scale = np.abs(v).max()
    for T in transforms(v, handles):
        combined = d.deform(T)
        solved = fresh.deform(handle_positions=moved(v, handles, T))
        assert np.abs(combined - solved).max() < 1e-10 * scale
        if weight == 0:  # hard constraints: anchors stay exactly, handles land where T puts them
            assert np.array_equal(combined[anchors], v[anchors])
            assert np.abs(combined[handles] - moved(v, handles, T)).max() < 1e-14 * scale
        np.testing.assert_array_equal(d.points, combined)


def test_restore_after_a_combined_deform_equals_restore_after_a_fresh_solve():
    p, s = sphere_manifold()
    anchors, handles = constraints(p)
    T = transforms(p, handles)[0]
    d = am.Deformer(p, s, anchors, handles, "dual")
    fresh = am.Deformer(p, s, anchors, handles, "dual")
    d.deform(T)
    fresh.deform(handle_positions=moved(p, handles, T))
    a = d.restore(max_iterations=20, tolerance=1e-9)
    b = fresh.restore(max_iterations=20, tolerance=1e-9)
    assert d.status.iterations == fresh.status.iterations
    assert np.abs(a - b).max() < 1e-9 * np.abs(p).max()


def test_deform_in_steps_still_solves_each_increment():
    """steps > 1 restores between increments, which the affine response cannot give: the
    result differs from the one-step deform and matches a one-off laplacian_deform."""
    v, f = icosphere(3)
    anchors, handles = constraints(v)
    T = transforms(v, handles)[0]
    d = am.Deformer(v, f, anchors, handles, "dual")
    one = d.deform(T)
    three = d.deform(T, steps=3)
    assert np.abs(one - three).max() > 1e-6
    np.testing.assert_array_equal(three, am.Deformer(v, f, anchors, handles, "dual").deform(T, steps=3))


def test_combined_deforms_are_the_same_bits_on_one_and_two_threads():
    p, s = sphere_manifold()
    anchors, handles = constraints(p)

    def solve():
        d = am.Deformer(p, s, anchors, handles, "dual")
        return [d.deform(T).tobytes() for T in transforms(p, handles)]

    am.set_threads(1)
    one = solve()
    am.set_threads(2)
    assert solve() == one


def test_setup_phases_are_reported():
    v, f = icosphere(2)
    anchors, handles = constraints(v)
    info = am.Deformer(v, f, anchors, handles, "dual").info
    assert info.factor_flops > 0 and info.factor_nonzeros > 0
    for phase in ("laplacian_seconds", "normal_seconds", "analyse_seconds", "factorise_seconds"):
        assert getattr(info, phase) >= 0
