"""Laplacian deformation (chapter 4): weights, the small QP solver, the dual
Laplacian with ghost vertices, boundary rules, the Deformer and restore."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.laplacian_shapes import block, face_normals, folded_edges, uniform_delta
from helpers.shapes import icosphere, polygon

METHODS_3D = ("uniform", "cotangent", "graph", "dual")
METHODS_ANY = ("uniform", "graph", "dual")


def dense(csr) -> np.ndarray:
    indptr, indices, data, shape = csr
    out = np.zeros(shape)
    for r in range(shape[0]):
        out[r, indices[indptr[r]:indptr[r + 1]]] += data[indptr[r]:indptr[r + 1]]
    return out


def bbox_diagonal(points: np.ndarray) -> float:
    return float(np.linalg.norm(points.max(0) - points.min(0)))


# --- meshes -----------------------------------------------------------------

def closed_surface():
    v, f = icosphere(2)
    return np.ascontiguousarray(v * [1.0, 0.8, 1.3]), f


def open_surface():
    """A bumpy open grid (triangles in R^3 with a boundary)."""
    n = 9
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    z = 0.1 * np.sin(3 * x) * np.cos(2 * y)
    v = np.stack([x.ravel(), y.ravel(), z.ravel()], 1)
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return v, f.astype(np.int32)


def moving_contour(static: bool = False):
    """An animated contour: 3 keyframes of a 12-gon stitched into triangles in R^3."""
    v, e = polygon(12)
    frames = [v, v, v] if static else [v, 1.2 * v + [0.1, 0], 0.9 * v + [0.3, 0.1]]
    m = am.stitch(frames, e, [0.0, 1.0, 2.0])
    return np.ascontiguousarray(m.points), np.ascontiguousarray(m.simplices), 12


def moving_sphere(static: bool = False, keyframes: int = 3):
    """An animated surface: keyframes of an icosphere stitched into tets in R^4."""
    v, f = icosphere(1)
    frames = [v * (1 if static else 1 + 0.2 * i) + (0 if static else [0.2 * i, 0, 0]) for i in range(keyframes)]
    m = am.stitch(frames, f, np.arange(keyframes, dtype=float))
    return np.ascontiguousarray(m.points), np.ascontiguousarray(m.simplices), len(v)


def meshes_and_methods():
    cases = []
    for name, (v, f) in (("closed", closed_surface()), ("open", open_surface())):
        cases += [(name, v, f, m) for m in METHODS_3D]
    p, s, _ = moving_contour()
    cases += [("contour-manifold", p, s, m) for m in METHODS_ANY]
    p, s, _ = moving_sphere()
    cases += [("surface-manifold", p, s, m) for m in METHODS_ANY]
    return cases


CASES = meshes_and_methods()
CASE_IDS = [f"{c[0]}-{c[3]}" for c in CASES]


def constraints(points: np.ndarray):
    """Anchors: the lowest 15% along the first axis; handles: the highest 15%."""
    x = points[:, 0]
    lo, hi = np.quantile(x, [0.15, 0.85])
    return np.flatnonzero(x <= lo), np.flatnonzero(x >= hi)


# --- the small QP solver ----------------------------------------------------

def qp_reference(H: np.ndarray, g: np.ndarray, lower: float) -> tuple[np.ndarray, float]:
    """Brute force: every KKT point of every active set, keep the best feasible one."""
    k = len(g)
    best, best_value = None, np.inf
    for size in range(1, k + 1):
        for free in itertools.combinations(range(k), size):
            free = list(free)
            fixed = [j for j in range(k) if j not in free]
            w = np.full(k, lower)
            # min ½wᵀHw + gᵀw on the free set with Σw = 1: KKT system.
            Hff = H[np.ix_(free, free)]
            rhs = -(g[free] + H[np.ix_(free, fixed)] @ w[fixed])
            K = np.block([[Hff, np.ones((size, 1))], [np.ones((1, size)), np.zeros((1, 1))]])
            b = np.concatenate([rhs, [1 - lower * len(fixed)]])
            try:
                sol = np.linalg.solve(K, b)
            except np.linalg.LinAlgError:
                continue
            w[free] = sol[:size]
            if (w < lower - 1e-12).any():
                continue
            value = 0.5 * w @ H @ w + g @ w
            if value < best_value:
                best, best_value = w, value
    return best, best_value


def random_qp(rng, k: int, D: int, lam: float, ridge: float = 1e-8):
    E = rng.normal(size=(k, D)) * rng.uniform(0.2, 2.0, size=(k, 1))
    c = (E**2).sum(1)
    m = c.mean()
    H = 2 * (E @ E.T) / m + 2 * ridge * np.eye(k)
    g = lam * c / m
    return E, H, g


@pytest.mark.parametrize("k", [2, 3, 5, 8, 10])
def test_simplex_qp_matches_brute_force_active_sets(rng, k):
    for trial in range(8):
        D = 3 + trial % 2
        lam = [0.0, 0.1, 1.0, 5.0][trial % 4]
        lower = [0.0, 1e-3, 0.05][trial % 3]
        _, H, g = random_qp(rng, k, D, lam)
        w, value, iterations, converged = _core._testing.simplex_qp(H, g, lower)
        w_ref, value_ref = qp_reference(H, g, lower)
        assert converged
        assert abs(w.sum() - 1) < 1e-12 and (w >= lower - 1e-14).all()
        assert value <= value_ref + 1e-10 * max(1.0, abs(value_ref))
        # Strictly convex (ridge): the minimiser is unique.
        np.testing.assert_allclose(w, w_ref, atol=1e-6)


def projected_gradient_reference(H, g, lower, iterations=20000):
    """Accelerated projected gradient onto {Σw = 1, w ≥ lower} (independent of the active-set code)."""
    k = len(g)

    def project(y):  # Euclidean projection onto the shifted simplex
        s = 1 - k * lower
        u = np.sort(y - lower)[::-1]
        css = np.cumsum(u) - s
        rho = np.nonzero(u - css / np.arange(1, k + 1) > 0)[0][-1]
        return np.maximum(y - lower - css[rho] / (rho + 1), 0) + lower

    step = 1 / np.linalg.eigvalsh(H).max()
    w = np.full(k, 1 / k)
    y, t = w.copy(), 1.0
    for _ in range(iterations):
        w_next = project(y - step * (H @ y + g))
        t_next = (1 + np.sqrt(1 + 4 * t * t)) / 2
        y = w_next + (t - 1) / t_next * (w_next - w)
        w, t = w_next, t_next
    return w, 0.5 * w @ H @ w + g @ w


def test_simplex_qp_on_one_ring_sized_problems_matches_projected_gradient(rng):
    for k in (16, 24, 40):
        for lam in (0.0, 0.1):
            _, H, g = random_qp(rng, k, 4, lam, ridge=1e-4)
            w, value, _, converged = _core._testing.simplex_qp(H, g, 1e-3)
            _, value_ref = projected_gradient_reference(H, g, 1e-3)
            assert converged
            assert value <= value_ref + 1e-9
            # KKT: on free weights the gradient is constant, elsewhere it is not smaller.
            gradient = H @ w + g
            free = w > 1e-3 + 1e-10
            nu = gradient[free].mean()
            assert np.ptp(gradient[free]) < 1e-8
            assert (gradient[~free] >= nu - 1e-8).all()


def test_simplex_qp_rejects_infeasible_floor_and_indefinite_H():
    with pytest.raises(ValueError, match="infeasible"):
        _core._testing.simplex_qp(np.eye(3), np.zeros(3), 0.5)
    with pytest.raises(ValueError, match="positive definite"):
        _core._testing.simplex_qp(-np.eye(3), np.zeros(3), 0.0)


def test_graph_weights_on_the_block_are_affine_and_above_the_floor():
    """Graph weights of the 2.5k-vertex block (their speed against the seed's 55 s is
    bench/bench_laplacian.py's figure): each row sums to 1 and no weight is under the floor."""
    V, F = block()
    W = _core._testing.primal_weights(V, F, "graph")
    Wd = dense(W)
    np.testing.assert_allclose(Wd.sum(1), 1, atol=1e-12)
    assert (Wd[Wd != 0] >= 1e-3 - 1e-12).all()


def test_graph_weights_without_edge_term_put_flat_vertices_on_their_neighbours():
    """Eq. 4.3 minimises |δ|: an interior vertex of a flat grid gets δ = 0 (no tangential drift)."""
    v, f = open_surface()
    v[:, 2] = 0
    L, delta = _core._testing.laplacian_system(v, f, "graph", lam=0.0)
    interior = ~_core._testing.boundary_vertices(f, len(v))
    assert np.abs(delta[interior]).max() < 1e-8


def test_boundary_vertices_use_eq_4_3_whatever_the_method():
    v, f = open_surface()
    boundary = _core._testing.boundary_vertices(f, len(v))
    assert boundary.sum() == 32
    reference = dense(_core._testing.primal_weights(v, f, "graph", lam=0.0))
    for method in ("uniform", "cotangent", "graph"):
        W = dense(_core._testing.primal_weights(v, f, method))
        np.testing.assert_allclose(W[boundary], reference[boundary], atol=1e-12)
    # ...while interior rows differ between schemes.
    assert np.abs(dense(_core._testing.primal_weights(v, f, "uniform"))[~boundary] - reference[~boundary]).max() > 1e-3


def test_cotangent_weights_of_a_symmetric_vertex_are_equal_and_need_triangles_in_r3():
    v, f = icosphere(0)
    W = dense(_core._testing.primal_weights(v, f, "cotangent"))
    np.testing.assert_allclose(W[W != 0], 0.2, atol=1e-12)
    p, s, _ = moving_sphere()
    with pytest.raises(ValueError, match="cotangent weights exist only for triangle meshes in R\\^3"):
        am.Deformer(p, s, [0], [5], method="cotangent")


# --- the dual operator --------------------------------------------------------

def test_ghost_dual_vertex_of_a_triangle_is_two_thirds_edge_minus_one_third_opposite():
    S = np.array([[0, 1, 2]], np.int32)
    (D, neighbours, ghosts) = _core._testing.dual_operator(S, 3)
    D = dense(D)
    assert D.shape == (4, 3) and ghosts.shape == (3, 2)
    np.testing.assert_allclose(D[0], [1 / 3] * 3)
    for row, (s, i) in enumerate(ghosts, start=1):
        expected = np.full(3, 2 / 3)
        expected[S[s, i]] = -1 / 3
        np.testing.assert_allclose(D[row], expected)
    # Equals the centroid of the triangle rotated by π about the boundary edge's midpoint.
    P = np.array([[0.0, 0, 0], [1, 0, 0], [0.2, 0.9, 0.3]])
    A, B, C = P
    np.testing.assert_allclose(D[1] @ P, (B + C + (B + C - A)) / 3)


def test_ghost_dual_vertex_of_a_tet_reflects_the_opposite_vertex_through_the_facet_centroid():
    S = np.array([[0, 1, 2, 3]], np.int32)
    D, neighbours, ghosts = _core._testing.dual_operator(S, 4)
    D = dense(D)
    P = np.random.default_rng(1).normal(size=(4, 4))
    for row, (s, i) in enumerate(ghosts, start=1):
        facet = [c for c in range(4) if c != i]
        mirrored = 2 * P[facet].mean(0) - P[i]
        np.testing.assert_allclose(D[row] @ P, (P[facet].sum(0) + mirrored) / 4, atol=1e-14)
        assert abs(D[row].sum() - 1) < 1e-14  # affine: commutes with any motion


def test_dual_laplacian_coordinates_are_normal_to_the_neighbour_hyperplane():
    p, s, _ = moving_sphere()
    L, delta = _core._testing.laplacian_system(p, s, "dual")
    D, neighbours, _ = _core._testing.dual_operator(s, len(p))
    C = dense(D) @ p
    normals = _core._testing.simplex_normals(C, neighbours)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    tangential = delta - (delta * normals).sum(1, keepdims=True) * normals
    assert np.abs(tangential).max() < 1e-12 * bbox_diagonal(p) + 1e-14
    np.testing.assert_allclose(dense(L) @ p, delta, atol=1e-13)


# --- the Deformer: exactness properties -----------------------------------------

@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_zero_handle_motion_returns_the_input(case):
    _, v, f, method = case
    anchors, handles = constraints(v)
    d = am.Deformer(v, f, anchors, handles, method)
    out = d.deform(np.eye(v.shape[1] + 1))
    assert np.abs(out - v).max() < 1e-9 * bbox_diagonal(v)
    if method == "dual":
        restored = d.restore()
        assert d.status.converged and d.status.iterations <= 2
        assert np.abs(restored - v).max() < 1e-9 * bbox_diagonal(v)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_translating_the_handles_without_anchors_translates_the_whole_shape(case):
    _, v, f, method = case
    _, handles = constraints(v)
    t = np.array([0.3, -0.2, 0.5, 0.1][: v.shape[1]])
    d = am.Deformer(v, f, [], handles, method)
    out = d.deform(am.handle_transform(translation=t, dimension=v.shape[1]))
    np.testing.assert_allclose(out, v + t, atol=1e-9 * bbox_diagonal(v))


@pytest.mark.parametrize("method", METHODS_ANY)
def test_all_vertices_as_soft_handles_translate_the_shape(method):
    v, f = closed_surface()
    t = [0.1, 0.2, -0.3]
    d = am.Deformer(v, f, [], np.arange(len(v)), method, constraint_weight=1.0)
    out = d.deform(am.handle_transform(translation=t, dimension=3))
    np.testing.assert_allclose(out, v + t, atol=1e-9)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_anchors_stay_handles_land_and_the_normal_equations_hold(case):
    _, v, f, method = case
    anchors, handles = constraints(v)
    D = v.shape[1]
    R = am.rotation_matrix([0, 0, 1], 0.4)
    T = am.handle_transform(rotation=R, translation=[0.2] * D, center=v[handles].mean(0), dimension=D)
    d = am.Deformer(v, f, anchors, handles, method)
    out = d.deform(T)
    assert np.abs(out[anchors] - v[anchors]).max() < 1e-12
    expected = v[handles] @ T[:D, :D].T + T[:D, D]
    assert np.abs(out[handles] - expected).max() < 1e-12
    # LᵀL x = Lᵀ b on the free vertices (the constrained ones are eliminated).
    L = dense(d._core.laplacian)
    delta = d._core.delta
    free = np.setdiff1d(np.arange(len(v)), np.concatenate([anchors, handles]))
    residual = (L.T @ (L @ out - delta))[free]
    scale = np.abs(L.T @ delta).max() + np.abs(L.T @ L @ out).max()
    assert np.abs(residual).max() < 1e-10 * scale
    assert not np.allclose(out[free], v[free])  # something did move


def test_soft_constraints_solve_the_stacked_least_squares_problem():
    v, f = closed_surface()
    anchors, handles = constraints(v)
    w = 3.0
    d = am.Deformer(v, f, anchors, handles, "dual", constraint_weight=w)
    T = am.handle_transform(translation=[0, 0, 0.5], dimension=3)
    out = d.deform(T)
    L = dense(d._core.laplacian)
    C = np.concatenate([anchors, handles])
    E = np.zeros((len(C), len(v)))
    E[np.arange(len(C)), C] = w
    A = np.vstack([L, E])
    target = np.concatenate([v[anchors], v[handles] + [0, 0, 0.5]])
    b = np.vstack([d._core.delta, w * target])
    residual = A.T @ (A @ out - b)
    assert np.abs(residual).max() < 1e-10 * np.abs(A.T @ b).max()
    assert np.abs(out[anchors] - v[anchors]).max() > 1e-6  # soft: anchors give a little


def test_handle_positions_move_each_handle_to_its_row():
    v, f = closed_surface()
    anchors, handles = constraints(v)
    P = v[handles] + np.linspace(0, 0.3, len(handles))[:, None] * [0, 1, 0]
    d = am.Deformer(v, f, anchors, handles, "graph")
    out = d.deform(handle_positions=P)
    np.testing.assert_allclose(out[handles], P, atol=1e-12)
    np.testing.assert_allclose(out[anchors], v[anchors], atol=1e-12)


# --- rotation invariance and the Figure 4.11 stress test --------------------------

def bend(method: str, steps: int = 1):
    V, F = block(6, 6, 24, (1.0, 1.0, 4.0))
    z = V[:, 2]
    bottom, top = np.flatnonzero(z < 1e-9), np.flatnonzero(z > z.max() - 1e-9)
    length = z.max()
    radius = length / (np.pi / 2)  # a quarter circle of the bar's length
    cap = np.array([0.0, 0.0, length])
    T = am.handle_transform(
        rotation=am.rotation_matrix([1, 0, 0], -np.pi / 2), center=cap, translation=[0, radius, radius] - cap, dimension=3
    )
    d = am.Deformer(V, F, bottom, top, method)
    out = d.deform(T, steps=steps)
    if method == "dual":
        out = d.restore(max_iterations=100, tolerance=1e-6)
        assert d.status.converged, d.status
    return V, F, out


def feature_size_errors(V, F, out):
    before, after = uniform_delta(V, F), uniform_delta(out, F)
    feature = before > 1e-6  # the block's edges and corners
    relative = np.abs(after - before)[feature] / before[feature]
    overall = np.abs(after - before).mean() / before.mean()
    return relative.max(), overall


def test_bending_a_bar_by_a_quarter_turn_preserves_local_feature_size_with_dual_restore():
    """Figure 4.3's idea on a bar bent by π/2 at the handles. Stated tolerance:
    the local feature size |δ_i| (1-ring, rigid-invariant) of every feature
    vertex stays within 15% and the mean change is below 25% of the mean size;
    uniform weights (not rotation-invariant) do measurably worse."""
    V, F, dual = bend("dual")
    dual_max, dual_mean = feature_size_errors(V, F, dual)
    assert dual_max < 0.15 and dual_mean < 0.25, (dual_max, dual_mean)
    V, F, uniform = bend("uniform")
    uniform_max, uniform_mean = feature_size_errors(V, F, uniform)
    assert uniform_max > 2 * dual_max and uniform_mean > 1.5 * dual_mean, (uniform_max, uniform_mean)
    assert folded_edges(V, dual, F) == 0 and folded_edges(V, uniform, F) > 0


def twisted_normals(V, F, angle):
    """The input face normals rotated about z by the twist angle at each face's height."""
    n0 = face_normals(V, F)
    a = angle * V[F].mean(1)[:, 2] / V[:, 2].max()
    c, s = np.cos(a), np.sin(a)
    return np.stack([c * n0[:, 0] - s * n0[:, 1], s * n0[:, 0] + c * n0[:, 1], n0[:, 2]], 1)


@pytest.mark.parametrize("quarter_turns", [1, 2, 3])
def test_figure_4_11_block_twist_has_no_inverted_faces_with_dual_restore(quarter_turns):
    """Bottom cap anchored, top cap rotated by π/4, π/2, 3π/4 about the block's
    axis, dragged in increments of π/4 (steps) with restore after each."""
    angle = quarter_turns * np.pi / 4
    V, F = block()
    z = V[:, 2]
    bottom, top = np.flatnonzero(z < 1e-9), np.flatnonzero(z > z.max() - 1e-9)
    T = am.handle_transform(rotation=am.rotation_matrix([0, 0, 1], angle), center=[0, 0, z.max()], dimension=3)
    d = am.Deformer(V, F, bottom, top, "dual")
    d.deform(T, steps=quarter_turns)
    out = d.restore(max_iterations=100)
    assert d.status.converged and d.status.iterations <= 40, d.status
    expected = twisted_normals(V, F, angle)
    dots = (face_normals(out, F) * expected).sum(1)
    assert (dots > 0).all(), f"{np.count_nonzero(dots <= 0)} inverted faces"
    assert folded_edges(V, out, F) == 0
    if quarter_turns >= 2:  # the comparison of Figure 4.11: equal weights crumple
        uniform = am.Deformer(V, F, bottom, top, "uniform").deform(T)
        assert ((face_normals(uniform, F) * expected).sum(1) < 0).sum() > 50


def test_one_off_deformation_picks_steps_from_the_rotation():
    V, F = block()
    bottom, top = np.flatnonzero(V[:, 2] < 1e-9), np.flatnonzero(V[:, 2] > V[:, 2].max() - 1e-9)
    angle = 3 * np.pi / 4
    T = am.handle_transform(rotation=am.rotation_matrix([0, 0, 1], angle), center=[0, 0, V[:, 2].max()], dimension=3)
    assert am.laplacian.steps_for_rotation(am.laplacian.rotation_angle(T[:3, :3])) == 3
    out = am.laplacian_deform(V, F, bottom, top, T)  # dual, steps="auto", restored
    assert ((face_normals(out, F) * twisted_normals(V, F, angle)).sum(1) > 0).all()
    # Explicit positions: the best-fit rotation of the handles gives the same count.
    d = am.Deformer(V, F, bottom, top)
    P = V[top] @ T[:3, :3].T + T[:3, 3]
    d.deform(handle_positions=P, steps="auto")
    out = d.restore(max_iterations=100)
    assert d.status.converged
    np.testing.assert_allclose(out[top], P, atol=1e-12)
    assert ((face_normals(out, F) * twisted_normals(V, F, angle)).sum(1) > 0).all()
    with pytest.raises(ValueError, match="steps must be 'auto' or an integer >= 1"):
        d.deform(T, steps=0)


def test_affine_power_splits_a_transform_into_equal_steps():
    R = am.rotation_matrix([1, 2, 3], 2.0)
    T = am.handle_transform(rotation=R, translation=[1, 2, 3], scale=1.5, center=[0.5, 0, 0], dimension=3)
    third = _core._testing.affine_power(T, 1 / 3)
    np.testing.assert_allclose(third @ third @ third, T, atol=1e-12)
    np.testing.assert_allclose(_core._testing.affine_power(T, 0.0), np.eye(4), atol=1e-12)
    with pytest.raises(ValueError, match="reflects"):
        _core._testing.affine_power(np.diag([-1.0, 1, 1, 1]), 0.5)


# --- boundaries of animation manifolds ------------------------------------------------

def static_sheet(static: bool = True):
    """A flat open grid held still over 3 keyframes: tets in R^4 lying in a 3-plane."""
    v, f = open_surface()
    v[:, 2] = 0
    m = am.stitch([v, v, v], f, [0.0, 1.0, 2.0])
    return np.ascontiguousarray(m.points), np.ascontiguousarray(m.simplices), len(v)


@pytest.mark.parametrize("maker", [moving_contour, static_sheet], ids=["contour-R3", "sheet-R4"])
def test_dual_on_a_static_open_manifold_needs_constraints_in_two_keyframes(maker):
    """A static stitched contour is a cylinder, flat along time; the ghost
    vertices reproduce affine functions exactly, so the time coordinate is a
    free direction of the dual Laplacian unless constraints sit at two
    different times: 'error' says one more constraint is needed, 'grow' grows
    into the next keyframe, 'ghost_anchors' pins the boundary. (A curved
    static surface in R^4 is only nearly deficient: its dual neighbour
    hyperplanes need not contain the time axis; the flat sheet is exact.)"""
    p, s, k = maker(static=True)
    anchors, handles = np.array([0, 1, 2]), np.array([k - 1, k - 2, k // 2])  # all in keyframe 0
    T = am.handle_transform(translation=[0.2] + [0.0] * (p.shape[1] - 1), dimension=p.shape[1])
    with pytest.raises(ValueError, match=r"at least 1 more independent constraint\(s\).*ghost vertices at the boundary"):
        am.Deformer(p, s, anchors, handles, "dual", boundary="error")
    grown = am.Deformer(p, s, anchors, handles, "dual", boundary="grow")
    assert grown.info.grown > 0 and len(grown.anchors) > len(anchors)
    ghosts = am.Deformer(p, s, anchors, handles, "dual", boundary="ghost_anchors")
    assert ghosts.info.ghost_anchor_rows == ghosts.info.ghosts > 0
    for d in (grown, ghosts):
        np.testing.assert_allclose(d.deform(np.eye(p.shape[1] + 1)), p, atol=1e-9)
        out = d.deform(T)
        assert np.isfinite(out).all()
        np.testing.assert_allclose(out[anchors], p[anchors], atol=1e-12)
        d.restore()
        assert d.status.converged
    # Constraints in two keyframes: full rank under every rule, no growth needed.
    two = np.concatenate([anchors, k + anchors])
    for rule in ("error", "grow", "ghost_anchors"):
        d = am.Deformer(p, s, two, handles, "dual", boundary=rule)
        assert d.info.grown == 0
        assert np.isfinite(d.deform(T)).all()


@pytest.mark.parametrize("rule", ["error", "grow", "ghost_anchors"])
@pytest.mark.parametrize("method", METHODS_ANY)
def test_open_moving_manifold_deforms_under_each_boundary_rule(method, rule):
    p, s, k = moving_sphere(keyframes=4)
    anchors = np.arange(2 * k)  # keyframes 0 and 1
    handles = np.arange(3 * k, 4 * k)  # keyframe 3
    T = am.handle_transform(translation=[0.0, 0.5, 0.0, -0.5], dimension=4)
    d = am.Deformer(p, s, anchors, handles, method, boundary=rule)
    out = d.deform(T)
    np.testing.assert_allclose(out[anchors], p[anchors], atol=1e-12)
    np.testing.assert_allclose(out[handles], p[handles] + T[:4, 4], atol=1e-12)
    middle = out[2 * k:3 * k] - p[2 * k:3 * k]
    assert (middle[:, 1] > 0.01).all()  # keyframe 2 follows part of the way
    if method == "dual":
        d.restore()
        assert d.status.converged


def test_a_component_without_constraints_is_refused_not_solved():
    v, f = closed_surface()
    w = v + [5.0, 0, 0]
    points = np.vstack([v, w])
    faces = np.vstack([f, f + len(v)])
    for method in ("uniform", "dual"):
        with pytest.raises(ValueError, match="rank-deficient"):
            am.Deformer(points, faces, [0], [1], method, boundary="error")
        with pytest.raises(ValueError, match="no anchor or handle in its component"):
            am.Deformer(points, faces, [0], [1], method, boundary="grow")


# --- Python API --------------------------------------------------------------------

def test_input_errors_name_the_culprit():
    v, f = closed_surface()
    with pytest.raises(ValueError, match=r"anchors\[1\] is vertex 9999, outside 0..161"):
        am.Deformer(v, f, [0, 9999], [5])
    with pytest.raises(ValueError, match="vertex 5 is both an anchor and a handle"):
        am.Deformer(v, f, [0, 5], [5, 6])
    with pytest.raises(ValueError, match="no anchors and no handles"):
        am.Deformer(v, f, [], [])
    with pytest.raises(ValueError, match="vertex 3 is listed more than once in handles"):
        am.Deformer(v, f, [0], [3, 3])
    with pytest.raises(ValueError, match="unknown method 'cotan'"):
        am.Deformer(v, f, [0], [1], method="cotan")
    with pytest.raises(ValueError, match="unknown boundary rule"):
        am.Deformer(v, f, [0], [1], boundary="pin")
    d = am.Deformer(v, f, [0], [1], method="uniform")
    with pytest.raises(ValueError, match=r"handle_transform must be \(4, 4\)"):
        d.deform(np.eye(5))
    with pytest.raises(ValueError, match="last row"):
        d.deform(np.ones((4, 4)))
    with pytest.raises(ValueError, match=r"handle_positions must be \(1, 3\)"):
        d.deform(handle_positions=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="restore applies to method='dual' only"):
        d.restore()
    with pytest.raises(ValueError, match="restore needs a deformation first"):
        am.Deformer(v, f, [0], [1])._core.restore(10, 1e-6)
    with pytest.raises(ValueError, match="simplices must be"):
        am.Deformer(v, f[:, :2], [0], [1])


def test_boolean_masks_select_vertices():
    v, f = closed_surface()
    anchors, handles = constraints(v)
    mask_a = np.zeros(len(v), bool)
    mask_a[anchors] = True
    mask_h = np.zeros(len(v), bool)
    mask_h[handles] = True
    T = am.handle_transform(translation=[0, 0, 1], dimension=3)
    a = am.Deformer(v, f, mask_a, mask_h, "uniform").deform(T)
    b = am.Deformer(v, f, anchors, handles, "uniform").deform(T)
    np.testing.assert_array_equal(a, b)


def test_animation_manifold_deform_returns_a_new_manifold_with_earlier_frames_untouched():
    v, f = icosphere(1)
    times = [0.0, 1.0, 2.0, 3.0]
    frames = [v + [0.3 * t, 0, 0] for t in times]
    m = am.stitch(frames, f, times, vertex_attributes={"u": np.arange(len(v), dtype=float)})
    k = len(v)
    anchors = np.arange(2 * k)
    handles = np.arange(3 * k, 4 * k)
    moved = am.deform(m, anchors, handles, am.handle_transform(translation=[0, 1.0, 0, 0], dimension=4))
    assert isinstance(moved, am.AnimationManifold) and moved is not m
    np.testing.assert_array_equal(moved.simplices, m.simplices)
    np.testing.assert_allclose(moved.points[: 2 * k], m.points[: 2 * k], atol=1e-12)
    np.testing.assert_allclose(moved.points[3 * k:, 1], m.points[3 * k:, 1] + 1.0, atol=1e-12)
    assert moved.check().is_oriented_manifold
    np.testing.assert_array_equal(moved.vertex_attributes["u"], m.vertex_attributes["u"])
    frame = moved.slice(3.0)
    assert np.abs(frame.vertices[:, 1].mean() - 1.0) < 0.05  # the last keyframe moved up
    np.testing.assert_allclose(moved.slice(0.5).vertices, m.slice(0.5).vertices, atol=1e-12)


def test_zero_detail_vertices_get_uniform_weights_and_no_detail():
    """The hook for §4.5.1 regularisation: vertices added by refinement."""
    v, f = closed_surface()
    L, delta = _core._testing.laplacian_system(v, f, "graph", zero_detail_vertices=[7])
    L = dense(L)
    neighbours = np.flatnonzero(L[7] < 0)
    np.testing.assert_allclose(L[7, neighbours], -1 / len(neighbours))
    np.testing.assert_array_equal(delta[7], 0)
    Ld, delta_d = _core._testing.laplacian_system(v, f, "dual", zero_detail_vertices=[7])
    incident = np.flatnonzero((f == 7).any(1))
    np.testing.assert_array_equal(delta_d[incident], 0)
    assert np.abs(delta_d).sum() > 0
