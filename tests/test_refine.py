"""Barycentric refinement (chapter 6, issue 4): the §6.4 example, the invariants
every batch of splits must keep, orderings, attributes and input errors."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

import animanifold as am
from animanifold import _core

# ---------------------------------------------------------------------------
# Shapes


def icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """(0, ±1, ±φ) and cyclic permutations; faces = triples at mutual distance 2, outward."""
    phi = (1 + 5**0.5) / 2
    V = []
    for s1 in (-1, 1):
        for s2 in (-phi, phi):
            V += [(0, s1, s2), (s1, s2, 0), (s2, 0, s1)]
    V = np.array(V, dtype=np.float64)
    F = []
    for a, b, c in itertools.combinations(range(12), 3):
        if all(abs(np.linalg.norm(V[x] - V[y]) - 2) < 1e-9 for x, y in ((a, b), (b, c), (a, c))):
            n = np.cross(V[b] - V[a], V[c] - V[a])
            F.append((a, b, c) if n @ V[a] > 0 else (a, c, b))
    return V, np.array(F, dtype=np.int32)


def heightfield(n: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """A bumpy open n×n grid surface in R^3 (it has a boundary)."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    z = 0.3 * np.sin(3 * x) * np.cos(2 * y)
    V = np.c_[x.ravel(), y.ravel(), z.ravel()]
    F = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            F += [(a, b, c), (a, c, d)]
    return V, np.array(F, dtype=np.int32)


def cube_tets() -> tuple[np.ndarray, np.ndarray]:
    """The unit cube as six positive tets around the diagonal 0-7 (Kuhn)."""
    V = np.array([[(i >> a) & 1 for a in range(3)] for i in range(8)], dtype=np.float64)
    S = []
    for axes in itertools.permutations(range(3)):
        v, tet = 0, [0]
        for a in axes:
            v |= 1 << a
            tet.append(v)
        S.append(tet)
    S = np.array(S, dtype=np.int32)
    flip = _core._testing.signed_volumes(V, S) < 0
    S[flip] = S[flip][:, [0, 2, 1, 3]]
    return V, S


def octahedron() -> tuple[np.ndarray, np.ndarray]:
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
    F = []
    for a in (0, 1):
        for b in (2, 3):
            for c in (4, 5):
                n = np.cross(V[b] - V[a], V[c] - V[a])
                F.append((a, b, c) if n @ V[a] > 0 else (a, c, b))
    return V, np.array(F, dtype=np.int32)


def stitched_octahedron() -> am.AnimationManifold:
    """An octahedron that moves, grows and twists over three keyframes: tets in R^4."""
    V, F = octahedron()
    frames = []
    for i, angle in enumerate((0.0, 0.4, 0.9)):
        rot = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]])
        frames.append(V @ rot.T * (1 + 0.25 * i) + [0.3 * i, 0, -0.1 * i])
    return am.stitch(frames, F, [0.0, 1.0, 2.5])


SHAPES = {
    "heightfield": heightfield,
    "icosahedron": icosahedron,
    "cube tets": cube_tets,
    "animation manifold": lambda: (
        np.array(stitched_octahedron().points),
        np.array(stitched_octahedron().simplices),
    ),
}

# ---------------------------------------------------------------------------
# Invariants


def facet_table(S: np.ndarray):
    """(facets (#S*k, k-1), owner simplex, boundary mask) with the §2.4 facet rule."""
    k = S.shape[1]
    F = _core._testing.facets(S)
    _, inverse, counts = np.unique(np.sort(F, axis=1), axis=0, return_inverse=True, return_counts=True)
    return F, np.arange(len(F)) // k, counts[inverse.reshape(-1)] == 1


def barycentric(points: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, float]:
    """Coordinates of `points` (P, D) in the simplex `corners` (n, D), and the worst distance off its plane."""
    E = (corners[1:] - corners[0]).T
    lam, *_ = np.linalg.lstsq(E, (points - corners[0]).T, rcond=None)
    residual = np.linalg.norm(E @ lam - (points - corners[0]).T, axis=0).max()
    return np.vstack([1 - lam.sum(axis=0), lam]).T, residual


def assert_valid_refinement(V, S, r: am.Refinement, splits, epsilon: float) -> None:
    k = S.shape[1]
    P, T = r.points, r.simplices
    scale = np.ptp(V, axis=0).max()

    report = _core.check_manifold(T)
    assert report.is_oriented_manifold, report
    assert report.boundary_facets >= _core.check_manifold(S).boundary_facets

    # Total measure unchanged.
    assert _core._testing.simplex_volumes(P, T).sum() == pytest.approx(_core._testing.simplex_volumes(V, S).sum(), rel=1e-10)

    # Orientation: every child agrees with its parent within their common plane;
    # full-dimensional complexes have only positive simplices.
    parent = r.parent_simplex
    assert parent.shape == (len(T),) and parent.min() >= 0 and parent.max() < len(S)
    Ec = P[T[:, 1:]] - P[T[:, :1]]
    Ep = V[S[parent, 1:]] - V[S[parent, :1]]
    assert np.linalg.det(Ec @ Ep.transpose(0, 2, 1)).min() > 0
    if k == V.shape[1] + 1:
        assert _core._testing.signed_volumes(P, T).min() > 0

    # Each child lies inside its parent (the parent map is right).
    for s in range(len(T)):
        lam, off = barycentric(P[T[s]], V[S[parent[s]]])
        assert off < 1e-9 * scale and lam.min() > -1e-9, (s, lam)

    # Boundary unchanged as a point set: every new boundary facet lies inside
    # an old boundary facet of its parent, and the total boundary measure is equal.
    F0, owner0, boundary0 = facet_table(S)
    F1, owner1, boundary1 = facet_table(T)
    assert _core._testing.simplex_volumes(P, F1[boundary1]).sum() == pytest.approx(
        _core._testing.simplex_volumes(V, F0[boundary0]).sum(), rel=1e-10, abs=1e-12
    )
    for row in np.flatnonzero(boundary1):
        p = parent[owner1[row]]
        candidates = [p * k + i for i in range(k) if boundary0[p * k + i]]
        inside = False
        for c in candidates:
            lam, off = barycentric(P[F1[row]], V[F0[c]])
            inside |= off < 1e-9 * scale and lam.min() > -1e-9
        assert inside, f"boundary facet {F1[row]} left the input boundary"

    # Every requested point is a vertex (up to the sliver control's moves of at
    # most epsilon per dropped coordinate), or sits next to the vertex it snapped to.
    new, snapped = r.new_vertex_of_split, r.snapped_vertex_of_split
    assert np.all((new >= 0) != (snapped >= 0))
    assert len(P) == len(V) + np.count_nonzero(new >= 0)
    assert np.array_equal(P[: len(V)], V)
    for t, (ids, coords) in enumerate(splits):
        wanted = np.asarray(coords) @ V[np.asarray(ids)]
        at = new[t] if new[t] >= 0 else snapped[t]
        assert np.linalg.norm(P[at] - wanted) <= 2 * k * epsilon * scale + 1e-12, t
        if new[t] >= 0:
            assert r.split_of_vertex[new[t]] == t
    assert np.all(r.split_of_vertex[: len(V)] == -1)


# ---------------------------------------------------------------------------
# §6.4


def test_icosahedron_example_of_section_6_4():
    V, F = icosahedron()
    A, B, C = F[0]
    splits = [
        ([A, B], [0.5, 0.5]),
        ([A, B], [0.4999999, 0.5000001]),
        ([B, C], [0.5, 0.5]),
        ([A, B, C], [0.3, 0.3, 0.4]),
    ]
    r = am.refine_complex(V, F, splits, epsilon=1e-3, order="given")
    D = r.new_vertex_of_split[0]
    assert D == 12
    # Operation 2 is discarded: it coincides with D.
    assert r.new_vertex_of_split[1] == -1 and r.snapped_vertex_of_split[1] == D
    # The list becomes [B, C],[0.5, 0.5] and [D, C],[0.6, 0.4], applied in that order.
    assert list(r.new_vertex_of_split[2:]) == [13, 14]
    applied = [
        {int(v): w for v, w in zip(r.applied_simplex[t], r.applied_barycentric[t]) if v >= 0} for t in (2, 3)
    ]
    assert applied[0] == pytest.approx({int(B): 0.5, int(C): 0.5})
    assert applied[1] == pytest.approx({int(D): 0.6, int(C): 0.4})
    assert r.points[14] == pytest.approx(0.3 * V[A] + 0.3 * V[B] + 0.4 * V[C])
    assert r.simplices.shape == (26, 3)
    assert_valid_refinement(V, F, r, splits, 1e-3)

    # The greedy order inserts the same points and removes the same split.
    g = am.refine_complex(V, F, splits, epsilon=1e-3, order="degeneracy")
    assert list(g.new_vertex_of_split < 0) == [False, True, False, False]
    assert np.sort(g.points, axis=0) == pytest.approx(np.sort(r.points, axis=0))


# ---------------------------------------------------------------------------
# Property tests: random batches on a surface, a full-space complex and an
# animation manifold.


def split_strategy(k: int, simplex_count: int):
    face = st.integers(1, 2**k - 1)
    weights = st.lists(st.one_of(st.floats(0.0, 1.0), st.just(1e-5), st.just(0.0)), min_size=k, max_size=k)
    return st.lists(st.tuples(st.integers(0, simplex_count - 1), face, weights), min_size=1, max_size=40)


def as_splits(S: np.ndarray, drawn) -> list:
    """Hypothesis draws → (vertex_ids, barycentric) pairs on faces of S; repeats some to force removals."""
    splits = []
    for s, mask, weights in drawn:
        columns = [c for c in range(S.shape[1]) if mask >> c & 1]
        w = np.array([weights[c] for c in columns])
        if w.sum() <= 0:
            w = np.ones(len(columns))
        splits.append((S[s, columns], w / w.sum()))
    return splits + splits[: len(splits) // 4]


@pytest.mark.parametrize("shape", list(SHAPES))
@pytest.mark.parametrize("order", ["given", "degeneracy"])
@seed(20240604)
@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_batches_keep_a_valid_oriented_complex(shape, order, data):
    V, S = SHAPES[shape]()
    splits = as_splits(S, data.draw(split_strategy(S.shape[1], len(S))))
    r = am.refine_complex(V, S, splits, epsilon=1e-3, order=order)
    assert_valid_refinement(V, S, r, splits, 1e-3)


def test_random_batch_with_zero_epsilon_inserts_every_point_exactly():
    V, S = cube_tets()
    rng = np.random.default_rng(5)
    splits = []
    for _ in range(200):
        s = rng.integers(len(S))
        m = rng.integers(2, 5)
        w = rng.uniform(0.05, 1, m)
        splits.append((rng.permutation(S[s])[:m], w / w.sum()))
    r = am.refine_complex(V, S, splits, epsilon=0.0, order="degeneracy")
    assert np.all(r.new_vertex_of_split >= 0)
    for t, (ids, w) in enumerate(splits):
        assert np.linalg.norm(r.points[r.new_vertex_of_split[t]] - w @ V[ids]) < 1e-12
    assert _core.check_manifold(r.simplices).is_oriented_manifold
    assert _core._testing.simplex_volumes(r.points, r.simplices).sum() == pytest.approx(1.0, rel=1e-12)


# ---------------------------------------------------------------------------
# Orderings on the set-up of Figure 6.3: a contour's points embedded in the
# side of a cube.


def cube_surface() -> tuple[np.ndarray, np.ndarray]:
    V = np.array([[(i >> a) & 1 for a in range(3)] for i in range(8)], dtype=np.float64)
    F = []
    for a, b, c, d in [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]:
        F += [(a, b, c), (a, c, d)]
    F = np.array(F, dtype=np.int32)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    flip = np.einsum("ij,ij->i", n, V[F].mean(axis=1) - 0.5) < 0
    F[flip] = F[flip][:, [0, 2, 1]]
    return V, F


def contour_splits(V, F, count: int) -> list:
    """Points of a star-shaped closed contour on the top side (z = 1), as splits of the triangle holding each."""
    theta = np.linspace(0, 2 * np.pi, count, endpoint=False)
    radius = 0.3 + 0.12 * np.cos(5 * theta)
    points = np.c_[0.5 + radius * np.cos(theta), 0.5 + radius * np.sin(theta), np.ones(count)]
    top = [f for f in range(len(F)) if np.all(V[F[f], 2] == 1)]
    splits = []
    for p in points:
        # The triangle holding p best: a point on the square's diagonal is in both
        # triangles, and rounding can put it a few ulps outside each.
        lam, f = max(((barycentric(p[None], V[F[f]])[0][0], f) for f in top), key=lambda lf: lf[0].min())
        assert lam.min() >= -1e-12, p
        lam = np.clip(lam, 0.0, None)
        splits.append((F[f], lam / lam.sum()))
    assert len(splits) == count
    return splits


@pytest.mark.parametrize("count", [20, 40, 60])
def test_degeneracy_order_gives_the_same_vertices_and_no_worse_slivers(count):
    V, F = cube_surface()
    splits = contour_splits(V, F, count)
    given_ = am.refine_complex(V, F, splits, order="given")
    greedy = am.refine_complex(V, F, splits, order="degeneracy")
    for r in (given_, greedy):
        assert_valid_refinement(V, F, r, splits, 1e-3)
    # Same vertex set (the points may be moved by at most the sliver tolerance).
    assert len(given_.points) == len(greedy.points) == len(V) + count
    distance = np.linalg.norm(given_.points[:, None] - greedy.points[None], axis=2)
    assert distance.min(axis=1).max() < 1e-2 and distance.min(axis=0).max() < 1e-2
    # The orders did differ.
    assert not np.array_equal(given_.new_vertex_of_split, greedy.new_vertex_of_split)
    worst_given = _core._testing.edge_length_degeneracy(given_.points, given_.simplices).max()
    worst_greedy = _core._testing.edge_length_degeneracy(greedy.points, greedy.simplices).max()
    assert worst_greedy <= worst_given
    if count == 40:
        assert worst_greedy < worst_given - 0.02  # the figure's "fewer degenerate triangles"


def test_edge_length_degeneracy_is_the_normalised_variance():
    V, F = heightfield(4)
    lengths = np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F], axis=2)
    expected = lengths.var(axis=1) / lengths.mean(axis=1) ** 2
    assert _core._testing.edge_length_degeneracy(V, F) == pytest.approx(expected, rel=1e-9, abs=1e-15)


# ---------------------------------------------------------------------------
# The AnimationManifold method, attributes, bulk input.


def test_animation_manifold_refine_keeps_attributes_and_slices():
    V, F = octahedron()
    frames = [V * (1 + 0.2 * i) + [0, 0.1 * i, 0] for i in range(3)]
    m = am.stitch(frames, F, [0.0, 1.0, 2.0], face_attributes={"material": np.arange(len(F))})
    # A linear vertex attribute (the coordinates) must stay equal to the points.
    m = am.AnimationManifold.from_arrays(
        m.points, m.simplices, {"xyzt": np.array(m.points)}, m.simplex_attributes, m.metadata
    )
    rng = np.random.default_rng(3)
    splits = []
    for s in rng.integers(0, len(m.simplices), 80):
        w = rng.dirichlet(np.ones(4))
        splits.append((m.simplices[s], w))
    refined, r = am.refine(m, splits, epsilon=1e-3, order="degeneracy")
    assert isinstance(refined, am.AnimationManifold)
    assert refined.metadata == m.metadata
    assert refined.check().is_oriented_manifold
    assert np.abs(refined.vertex_attributes["xyzt"] - refined.points).max() < 1e-12
    assert np.array_equal(refined.simplex_attributes["material"], m.simplex_attributes["material"][r.parent_simplex])
    assert_valid_refinement(np.array(m.points), np.array(m.simplices), r, splits, 1e-3)
    # The manifold is the same point set, so every frame has the same area.
    for t in (0.0, 0.37, 1.5, 2.0):
        a, b = m.slice(t), refined.slice(t)
        area = [_core._testing.simplex_volumes(s.vertices, s.faces).sum() for s in (a, b)]
        assert area[1] == pytest.approx(area[0], rel=1e-9), t


def test_bulk_arrays_match_the_list_form():
    V, S = cube_tets()
    ids = np.array([[0, 7, -1], [S[2, 0], S[2, 1], S[2, 2]]])
    coords = np.array([[0.5, 0.5, 0.0], [0.2, 0.3, 0.5]])
    bulk = am.refine_complex(V, S, (ids, coords))
    listed = am.refine_complex(V, S, [([0, 7], [0.5, 0.5]), (S[2, :3], [0.2, 0.3, 0.5])])
    assert np.array_equal(bulk.points, listed.points) and np.array_equal(bulk.simplices, listed.simplices)


@pytest.mark.parametrize(
    "splits, message",
    [
        ([([0, 7], [0.5, 0.5]), ([1, 6], [0.5, 0.5])], r"split 1: vertices \(1, 6\) are not a simplex"),
        ([([0, 9], [0.5, 0.5])], r"split 0: vertex 9 is outside 0\.\.7"),
        ([([0, 7], [0.5, 0.6])], r"split 0: barycentric coordinates sum to 1\.1"),
        ([([0, 7], [1.5, -0.5])], r"split 0: barycentric coordinate -0\.5 of vertex 7"),
        ([([0, 7], [0.5, 0.5]), ([0, 7], [1.0])], r"split 1 has 2 vertex ids but 1 barycentric"),
        ([([0, 1, 3, 7, 5], [0.2] * 5)], r"split 0 names 5 vertices"),
        ([([0, -7], [0.5, 0.5])], r"split 0: vertex -7"),
        ([([0, 0], [0.5, 0.5])], r"split 0: vertex 0 is named twice"),
        ([([0, 7],)], r"split 0 must be a pair"),
    ],
)
def test_bad_splits_raise_value_errors_naming_them(splits, message):
    V, S = cube_tets()
    with pytest.raises(ValueError, match=message):
        am.refine_complex(V, S, splits)


def test_bad_options_raise_value_errors():
    V, S = cube_tets()
    with pytest.raises(ValueError, match="unknown order"):
        am.refine_complex(V, S, [], order="random")
    with pytest.raises(ValueError, match="epsilon"):
        am.refine_complex(V, S, [([0, 7], [0.5, 0.5])], epsilon=0.7)
    with pytest.raises(ValueError, match="simplex 1 repeats vertex 3"):
        am.refine_complex(V, np.array([[0, 1, 2, 4], [3, 3, 5, 6]]), [])
