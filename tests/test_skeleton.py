"""The Voronoi skeleton (chapter 7): separability, known medial axes, the
Voronoi properties of every skeleton vertex, no intersection with the mesh,
watertightness, and refusal of bad input."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import animanifold as am
from animanifold import skeleton as skel

from helpers.shapes import cube, icosphere, torus
from helpers.shared_files import shared_mesh

# ---------------------------------------------------------------- helpers


def closed_polygon(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = len(points)
    e = np.stack([np.arange(n), (np.arange(n) + 1) % n], 1).astype(np.int32)
    return np.ascontiguousarray(points, float), e


def rectangle(eps: float, w: float = 2.0, h: float = 1.0):
    """Counter-clockwise w×h rectangle, each side sampled with spacing ≈ eps
    but unevenly (a different smooth warp per side, so opposite samples are not
    mirror images and the Voronoi vertices are not trivially on the axis)."""
    corners = np.array([[0, 0], [w, 0], [w, h], [0, h]], float)
    pts = []
    for s, phase in enumerate((0.0, 0.7, 0.35, 0.9)):
        a, b = corners[s], corners[(s + 1) % 4]
        n = max(2, int(round(np.linalg.norm(b - a) / eps)))
        u = np.arange(n) / n
        warp = lambda x: x + 0.25 * np.sin(2 * np.pi * (x + phase)) / (2 * np.pi)  # noqa: E731
        u = warp(u) - warp(0.0)
        pts.append(a + u[:, None] * (b - a))
    return closed_polygon(np.concatenate(pts))


# The medial axis of the 2×1 rectangle: a central segment and four corner diagonals.
RECTANGLE_AXIS = [((0.5, 0.5), (1.5, 0.5)), ((0, 0), (0.5, 0.5)), ((0, 1), (0.5, 0.5)),
                  ((2, 0), (1.5, 0.5)), ((2, 1), (1.5, 0.5))]


def distance_to_segments(x: np.ndarray, segments) -> np.ndarray:
    best = np.full(len(x), np.inf)
    for a, b in segments:
        a, b = np.asarray(a, float), np.asarray(b, float)
        d = b - a
        t = np.clip(((x - a) @ d) / (d @ d), 0, 1)
        best = np.minimum(best, np.linalg.norm(x - (a + t[:, None] * d), axis=1))
    return best


def star(n: int = 9, seed: int = 3):
    """A spiky, sparsely sampled star polygon: many vertices encroach segments."""
    rng = np.random.default_rng(seed)
    a = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    r = np.where(np.arange(2 * n) % 2 == 0, 1.0, 0.35) * rng.uniform(0.8, 1.2, 2 * n)
    return closed_polygon(np.stack([r * np.cos(a), r * np.sin(a)], 1))


def encroaching_pairs_2d(v: np.ndarray, e: np.ndarray, tol: float = 1e-9) -> int:
    """Brute force: (vertex, segment) pairs with the vertex strictly inside the diametral circle."""
    a, b = v[e[:, 0]], v[e[:, 1]]
    dots = np.einsum("vsk,vsk->vs", v[:, None] - a[None], v[:, None] - b[None])
    strict = dots < -tol * ((b - a) ** 2).sum(1)[None]
    own = (np.arange(len(v))[:, None] == e[None, :, 0]) | (np.arange(len(v))[:, None] == e[None, :, 1])
    return int((strict & ~own).sum())


def jittered_sphere(subdivisions: int, jitter: float, centre=(0.0, 0.0, 0.0), seed: int = 1):
    v, f = icosphere(subdivisions)
    rng = np.random.default_rng(seed)
    v = v * (1 + jitter * rng.standard_normal(len(v)))[:, None]
    return v + np.asarray(centre), f


def nearest_distances(x: np.ndarray, sites: np.ndarray, chunk: int = 2048) -> np.ndarray:
    out = [np.zeros(0)]
    for s in range(0, len(x), chunk):
        d = np.linalg.norm(x[s:s + chunk, None, :] - sites[None], axis=2)
        out.append(d.min(1))
    return np.concatenate(out)


def assert_voronoi_property(sk: am.VoronoiSkeleton, rtol: float = 1e-7):
    """Every skeleton vertex is equidistant from the two sites of each face it is
    on, and no mesh vertex is closer (it lies on the Voronoi diagram of the mesh)."""
    P = sk.refined_vertices
    scale = np.ptp(P, axis=0).max()
    corners = sk.faces.ravel()
    faces_of = np.repeat(np.arange(len(sk.faces)), sk.faces.shape[1])
    x = sk.vertices[corners]
    di = np.linalg.norm(x - P[sk.sites[faces_of, 0]], axis=1)
    dj = np.linalg.norm(x - P[sk.sites[faces_of, 1]], axis=1)
    np.testing.assert_allclose(di, dj, atol=rtol * scale)
    nearest = nearest_distances(x, P)
    assert np.all(nearest >= di - rtol * scale), "a mesh vertex is closer than the face's sites"


def faces_without_on_mesh_vertices(sk: am.VoronoiSkeleton) -> np.ndarray:
    return ~sk.on_mesh[sk.faces].any(1)


def mesh_neighbours(faces: np.ndarray, n: int) -> list[set]:
    out = [set() for _ in range(n)]
    for f in faces:
        for a in f:
            out[a].update(int(b) for b in f if b != a)
    return out


def load(shared_data, name):
    return am.read_mesh(shared_mesh(shared_data, name))


# ---------------------------------------------------------- separability (2D)


def test_lemma_7_5_1_no_vertex_encroaches_after_separation():
    v, e = star()
    assert encroaching_pairs_2d(v, e) > 0, "the test polygon must start out encroached"
    sep = skel.make_voronoi_separable(v, e, max_iterations=10)
    assert sep.separable and sep.splits > 0
    rv, re = sep.vertices, sep.faces
    assert encroaching_pairs_2d(rv, re) == 0
    # The refined polygon is still one closed counter-clockwise chain through the input vertices.
    np.testing.assert_array_equal(rv[: len(v)], v)
    assert np.all(np.sort(re[:, 0]) == np.arange(len(rv))) and np.all(np.sort(re[:, 1]) == np.arange(len(rv)))
    nxt = dict(zip(re[:, 0], re[:, 1]))
    walk, seen = 0, 1
    while nxt[walk] != 0:
        walk, seen = nxt[walk], seen + 1
    assert seen == len(rv)
    area = 0.5 * np.sum(rv[re[:, 0], 0] * rv[re[:, 1], 1] - rv[re[:, 1], 0] * rv[re[:, 0], 1])
    assert area > 0
    # Strongly separable: the only bisectors crossing the polygon are between neighbours,
    # and no skeleton segment touches it.
    sk = am.voronoi_skeleton(v, e, max_iterations=10)
    assert sk.separable and sk.stats["discarded_nonlocal"] == 0
    np.testing.assert_array_equal(sk.refined_vertices, rv)
    hit = skel.faces_intersecting_mesh(sk.vertices, sk.faces, rv, re)
    assert not hit[faces_without_on_mesh_vertices(sk)].any()
    assert_voronoi_property(sk)


def test_closest_point_split_never_reencroaches():
    """Figure 7.8(c): splitting at the closest point leaves the encroacher on the new
    diametral circles, not inside: one round suffices for a single encroacher."""
    v, e = closed_polygon(np.array([[0, 0], [4, 0], [4, 3], [2, 0.8], [0, 3]], float))
    rows, distance = skel.encroachments(v, e)
    np.testing.assert_array_equal(rows, [[3, 0, 1, -1, 2]])
    assert distance[0] == pytest.approx(0.8)
    sep = skel.make_voronoi_separable(v, e, max_iterations=4)
    assert sep.separable and sep.iterations == 1 and sep.splits == 1
    np.testing.assert_allclose(sep.vertices[-1], [2, 0])
    # Two encroachers at the same distance: the closest (then lowest) first, the other next round.
    v2, e2 = closed_polygon(np.array([[0, 0], [4, 0], [4, 3], [2.5, 0.8], [1.5, 0.8], [0, 3]], float))
    sep2 = skel.make_voronoi_separable(v2, e2, max_iterations=4)
    assert sep2.separable and sep2.iterations == 2
    np.testing.assert_allclose(sep2.vertices[len(v2):], [[2.5, 0], [1.5, 0]])


def test_voronoi_vertex_on_the_mesh_is_flagged_figure_7_10():
    """Splitting segment a-b at the foot of p (adjacent to a, sharp corner at a) makes
    the right triangle (a, foot, p): its Voronoi vertex is the midpoint of a-p, on the
    polygon. It is flagged and ends the internal skeleton b_(p, foot) without the
    intersection test tripping over it."""
    v, e = closed_polygon(np.array([[0, 0], [4, 0], [4, 2], [1, 0.5]], float))
    sk = am.voronoi_skeleton(v, e)
    assert sk.separable and sk.iterations == 1 and sk.splits == 1
    np.testing.assert_allclose(sk.refined_vertices[4], [1, 0])
    np.testing.assert_allclose(sk.vertices[sk.on_mesh], [[0.5, 0.25]])
    touching = sk.on_mesh[sk.faces].any(1)
    assert list(sk.side[touching]) == ["internal"]
    np.testing.assert_array_equal(sk.sites[touching], [[3, 4]])
    np.testing.assert_allclose(sk.vertices[sk.faces[touching]][0, :, 1], [0.25, 0.25])


# ------------------------------------------------------------ medial axes


def test_rectangle_internal_skeleton_converges_to_medial_axis_at_eps_squared():
    """Theorem 7.3.1: a skeleton vertex at distance r from its sites is within
    O(eps²/r) of the medial axis (d = r cos α, α = O(eps/r)); so max(error·r)
    falls 4× per halving of eps, while the skeleton covers the whole axis."""
    epsilons = np.array([1 / 8, 1 / 16, 1 / 32, 1 / 64, 1 / 128])
    scaled = []
    for eps in epsilons:
        v, e = rectangle(eps)
        sk = am.voronoi_skeleton(v, e, side="internal")
        assert sk.separable and set(sk.side) == {"internal"}
        x, segments = sk.select("internal")
        r = nearest_distances(x, sk.refined_vertices)
        error = distance_to_segments(x, RECTANGLE_AXIS)
        assert error.max() < 0.2 * eps + 1e-12
        scaled.append((error * r).max())
        # Coverage: every point of the medial axis is within eps of the skeleton.
        s = np.linspace(0, 1, 100)[:, None]
        axis_points = np.concatenate([np.array(a) + s * (np.array(b) - np.array(a)) for a, b in RECTANGLE_AXIS])
        skeleton_segments = list(zip(x[segments[:, 0]], x[segments[:, 1]]))
        assert distance_to_segments(axis_points, skeleton_segments).max() < eps
    slopes = np.diff(np.log(scaled)) / np.diff(np.log(epsilons))
    assert np.all(slopes > 1.7) and np.all(slopes < 2.5), slopes


def test_sphere_internal_skeleton_shrinks_to_its_centre():
    v, f = jittered_sphere(3, 1e-6)
    sk = am.voronoi_skeleton(v, f, side="both")
    assert sk.separable
    x, faces = sk.select("internal")
    assert len(faces) > 100
    assert np.linalg.norm(x, axis=1).max() < 0.01
    # A convex shape has no external skeleton inside its own hull.
    assert not np.any(sk.side == "external")
    assert_voronoi_property(sk)


@pytest.mark.data
def test_torus_internal_skeleton_lies_near_its_core_circle(shared_data):
    v, f = load(shared_data, "torus-800.off")  # axis y, irregular sampling
    r = np.ptp(v[:, 1]) / 2
    R = np.hypot(v[:, 0], v[:, 2]).max() - r
    assert np.hypot(np.hypot(v[:, 0], v[:, 2]) - R, v[:, 1]).max() == pytest.approx(r, rel=0.05)
    sk = am.voronoi_skeleton(v, f, side="both")
    assert sk.separable
    x, faces = sk.select("internal")
    to_core = np.hypot(np.hypot(x[:, 0], x[:, 2]) - R, x[:, 1])
    assert to_core.max() < 0.4 * r
    assert np.median(to_core) < 0.2 * r
    angle = np.arctan2(x[:, 2], x[:, 0])
    assert np.all(np.histogram(angle, bins=24, range=(-np.pi, np.pi))[0] > 0), "the skeleton goes all round"
    # The hole is external, inside the hull, around the axis.
    xe, fe = sk.select("external")
    assert len(fe) > 0 and np.hypot(xe[:, 0], xe[:, 2]).min() < 0.2 * R


def test_cospherical_convex_input_has_an_empty_skeleton():
    """All vertices on one sphere: every Delaunay cell shares one Voronoi vertex
    (Qhull's triangulated pieces keep one centre), so there is no bisector polygon."""
    v, f = icosphere(2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", am.EmptySkeletonWarning)  # a convex shape has no external skeleton
        sk = am.voronoi_skeleton(v, f, side="external")
    assert sk.separable and len(sk.faces) == 0 and len(sk.vertices) == 0
    assert_voronoi_property(sk)


def test_an_empty_skeleton_of_a_shape_that_has_one_is_warned_of():
    """A primitive torus is sampled on circles, so many of its vertices share a sphere and the
    core finds no bisector to keep: the empty result must not pass for a skeleton."""
    v, f = torus()
    with pytest.warns(am.EmptySkeletonWarning, match="not convex.*sampled too regularly"):
        sk = am.voronoi_skeleton(v, f)
    assert len(sk.faces) == 0
    with pytest.warns(am.EmptySkeletonWarning, match="^the internal skeleton came out empty: .*sampled too regularly"):
        am.voronoi_skeleton(*icosphere(2), side="internal")


def test_two_spheres_external_skeleton_contains_their_bisecting_plane():
    a, fa = icosphere(2)
    left, right = a + [-2.0, 0, 0], a + [2.0, 0, 0]
    v = np.concatenate([left, right])
    f = np.concatenate([fa, fa + len(a)]).astype(np.int32)
    sk = am.voronoi_skeleton(v, f, side="external")
    n = len(a)
    cross = (sk.side == "external") & ((sk.sites[:, 0] < n) != (sk.sites[:, 1] < n))
    tris = sk.vertices[sk.faces[cross]]
    # Every point of the disc of radius 0.6 in the plane x = 0 lies on a cross bisector face.
    g = np.linspace(-0.6, 0.6, 9)
    yz = np.array([(y, z) for y in g for z in g if y * y + z * z <= 0.36])
    covered = np.zeros(len(yz), bool)
    for t in tris:
        p, q, r = t[:, 1:]
        m = np.array([q - p, r - p]).T
        if abs(np.linalg.det(m)) < 1e-15:
            continue
        uv = np.linalg.solve(m, (yz - p).T).T
        inside = (uv >= -1e-9).all(1) & (uv.sum(1) <= 1 + 1e-9)
        w = np.column_stack([1 - uv.sum(1), uv])
        xs = w @ t[:, 0]
        covered |= inside & (np.abs(xs) < 0.05)
    assert covered.all(), f"{(~covered).sum()} points of the bisecting disc are not on the skeleton"
    assert_voronoi_property(sk)


# ------------------------------------------------------ skeleton properties


@pytest.mark.data
def test_torus_skeleton_is_voronoi_and_does_not_intersect_the_mesh(shared_data):
    v, f = load(shared_data, "torus-800.off")
    sk = am.voronoi_skeleton(v, f, side="both")
    assert sk.separable and sk.stats["discarded_far"] == 0
    assert len(np.unique(sk.faces)) == len(sk.vertices), "no unreferenced skeleton vertices"
    assert_voronoi_property(sk)
    hit = skel.faces_intersecting_mesh(sk.vertices, sk.faces, sk.refined_vertices, sk.refined_faces)
    clean = faces_without_on_mesh_vertices(sk)
    assert clean.mean() > 0.95
    assert not hit[clean].any(), f"{hit[clean].sum()} skeleton faces intersect the mesh"


def test_the_intersection_check_is_not_vacuous():
    v, f = cube()
    tri = np.array([[0.0, 0, 0], [3, 0, 0], [0, 3, 0]])  # crosses the cube's surface
    far = tri + [10, 0, 0]
    hit = skel.faces_intersecting_mesh(np.concatenate([tri, far]), np.array([[0, 1, 2], [3, 4, 5]]), v, f)
    np.testing.assert_array_equal(hit, [True, False])


def free_edges(faces: np.ndarray) -> np.ndarray:
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    u, counts = np.unique(e, axis=0, return_counts=True)
    return u[counts == 1]


@pytest.mark.data
def test_internal_skeleton_is_watertight(shared_data):
    """§7.4: the skeleton has no holes. Its polygons are welded (shared Voronoi
    vertices), so a free edge can only be a Voronoi edge whose other bisectors
    were discarded; on a separable mesh those are local ones (between mesh
    neighbours), i.e. the free edges run along the mesh's own Voronoi walls."""
    v, f = load(shared_data, "torus.obj")
    sk = am.voronoi_skeleton(v, f, side="internal")
    assert sk.separable
    assert sk.stats["discarded_far"] == 0, "a bisector between distant vertices crosses the mesh"
    P = sk.refined_vertices
    nb = mesh_neighbours(sk.refined_faces, len(P))
    inner = sk.faces[sk.side == "internal"]
    sites = sk.sites[sk.side == "internal"]
    edges = free_edges(inner)
    assert len(edges) > 0
    # Interior fan diagonals are never free; every free edge is a Voronoi edge.
    edge_face = {}
    for k, t in enumerate(inner):
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edge_face[(min(a, b), max(a, b))] = k
    for a, b in edges:
        i, j = sites[edge_face[(a, b)]]
        mid = 0.5 * (sk.vertices[a] + sk.vertices[b])
        d = np.linalg.norm(P - mid, axis=1)
        r = d[i]
        d[[i, j]] = np.inf
        k = int(np.argmin(d))
        assert abs(d[k] - r) < 1e-7, "a free edge is not equidistant from three sites"
        assert k in nb[i] or k in nb[j], f"free edge ({a}, {b}) borders a non-local discarded bisector"


def test_polygon_internal_skeleton_is_connected():
    """2D watertightness: the internal skeleton of a simple polygon is one tree-like piece."""
    v, e = rectangle(1 / 16)
    sk = am.voronoi_skeleton(v, e, side="internal")
    x, s = sk.select("internal")
    parent = list(range(len(x)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in s:
        parent[find(a)] = find(b)
    assert len({find(a) for a in range(len(x))}) == 1


# ------------------------------------------------------ wrap, dihedral, attach


def c_shape():
    """A concave, C-shaped polygon (counter-clockwise)."""
    outer = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2], [3, 2], [3, 3], [0, 3]], float)
    pts = []
    for a, b in zip(outer, np.roll(outer, -1, axis=0)):
        n = int(np.ceil(np.linalg.norm(b - a) / 0.25))
        pts.append(a + np.arange(n)[:, None] / n * (b - a))
    return closed_polygon(np.concatenate(pts))


def test_wrap_bounds_every_cell_and_completes_the_external_skeleton():
    v, e = c_shape()
    wv, we, nv, nf = skel.wrap(v, e, "box", density=3)
    assert nv == len(v) and nf == len(e) and len(wv) == len(v) + 12
    area = lambda vv, ee: 0.5 * np.sum(vv[ee[:, 0], 0] * vv[ee[:, 1], 1] - vv[ee[:, 1], 0] * vv[ee[:, 0], 1])  # noqa: E731
    assert area(wv, we[nf:]) < 0, "the wrap is oriented inward"
    assert area(wv, we) < 0 and area(v, e) > 0
    boxed = am.voronoi_skeleton(v, e, side="external", wrap="box")
    sphered = am.voronoi_skeleton(v, e, side="external", wrap="sphere")
    bare = am.voronoi_skeleton(v, e, side="external", wrap=None)
    length = lambda sk: np.linalg.norm(np.diff(sk.vertices[sk.faces], axis=1), axis=2).sum()  # noqa: E731
    # Without the wrap, the bisectors across the notch's mouth reach infinity and are lost;
    # with it they are bounded and clipped at the hull, on the line x = 3.
    assert length(bare) < length(boxed)
    assert boxed.vertices[:, 0].max() == pytest.approx(3.0)
    assert bare.vertices[:, 0].max() < 2.95
    assert length(sphered) == pytest.approx(length(boxed), rel=1e-9)
    # The external skeleton fills the notch (1..3 × 1..2) and stays inside the hull [0, 3]².
    x = boxed.vertices[np.unique(boxed.faces)]
    assert x.min() >= -1e-9 and x.max() <= 3 + 1e-9
    assert np.any((x[:, 0] > 1.5) & (np.abs(x[:, 1] - 1.5) < 1e-9))
    wv3, wf3, nv3, nf3 = skel.wrap(*cube(), "sphere", density=2)
    report = am._core.check_manifold(wf3[nf3:])
    assert report.is_oriented_manifold and report.boundary_facets == 0
    centre_dir = -(wv3[wf3[nf3:]].mean(1))
    normals = np.cross(wv3[wf3[nf3:, 1]] - wv3[wf3[nf3:, 0]], wv3[wf3[nf3:, 2]] - wv3[wf3[nf3:, 0]])
    assert np.all((normals * centre_dir).sum(1) > 0)


def test_dihedral_test_reports_sharp_edges():
    v, f = cube()
    ok = skel.dihedral_test(v, f)
    assert ok.passes and ok.sharpest == pytest.approx(np.pi / 2)
    sharp = skel.dihedral_test(v, f, limit=np.radians(100))
    assert not sharp.passes and len(sharp.sharp) == 12
    assert np.allclose(sharp.angles, np.pi / 2)
    lengths = np.linalg.norm(v[sharp.sharp[:, 0]] - v[sharp.sharp[:, 1]], axis=1)
    np.testing.assert_allclose(lengths, 2.0)  # the cube's edges, not its face diagonals
    # A thin wedge is sharper than 45°.
    w = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1], [0, 0.2, 0.5], [1, 0.2, 0.5]], float)
    wf = np.array([[0, 2, 4], [1, 5, 3], [0, 1, 3], [0, 3, 2], [0, 4, 5], [0, 5, 1], [2, 3, 5], [2, 5, 4]], np.int32)
    report = skel.dihedral_test(w, wf)
    assert not report.passes and report.sharpest < np.radians(45)
    # 2D: corners.
    sv, se = star()
    r2 = skel.dihedral_test(sv, se, limit=np.radians(60))
    assert r2.sharp.shape[1] == 1 and not r2.passes
    prev, nxt = np.roll(sv, 1, axis=0) - sv, np.roll(sv, -1, axis=0) - sv
    corner = np.arccos(np.einsum("ij,ij->i", prev, nxt) / np.linalg.norm(prev, axis=1) / np.linalg.norm(nxt, axis=1))
    assert set(r2.sharp[:, 0]) == set(np.nonzero(corner < np.radians(60))[0])
    assert set(range(0, len(sv), 2)) <= set(r2.sharp[:, 0]), "every tip of the star is sharp"


def test_attaching_the_skeleton_connects_vertices_on_cell_boundaries():
    v, e = c_shape()
    sk = am.voronoi_skeleton(v, e, side="external", attach=True)
    n = len(sk.refined_vertices)
    att = sk.attachment
    assert att.shape[1] == 2 and len(att) > 0
    assert np.all(att[:, 0] < n) and np.all(att[:, 1] >= n)
    site_vertices = set(sk.sites.ravel().tolist())
    assert not (set(att[:, 0].tolist()) & site_vertices)
    # The skeleton vertex lies on the attached vertex's cell boundary.
    x = sk.vertices[att[:, 1] - n]
    d = np.linalg.norm(x - sk.refined_vertices[att[:, 0]], axis=1)
    np.testing.assert_allclose(d, nearest_distances(x, sk.refined_vertices), rtol=1e-9, atol=1e-12)
    none = am.voronoi_skeleton(v, e, side="external")
    assert none.attachment.shape[0] == 0


@pytest.mark.data
def test_attaching_in_3d_gives_triangles_on_cell_boundaries(shared_data):
    v, f = load(shared_data, "torus.obj")
    sk = am.voronoi_skeleton(v, f, side="external", attach=True)
    n = len(sk.refined_vertices)
    att = sk.attachment
    assert att.shape[1] == 3 and len(att) > 0
    both = np.vstack([sk.refined_vertices, sk.vertices])
    assert np.all(att[:, 0] < n) and np.all(att.max(1) >= n)
    for row in att[:50]:
        mesh = row[row < n][0]
        for s in row[row >= n]:
            x = both[s]
            assert np.linalg.norm(x - sk.refined_vertices[mesh]) == pytest.approx(
                nearest_distances(x[None], sk.refined_vertices)[0], rel=1e-9)


# ------------------------------------------------------------ bad input


def test_open_mesh_is_refused():
    v, f = icosphere(1)
    with pytest.raises(ValueError, match="open"):
        am.voronoi_skeleton(v, f[1:])
    pv, pe = star()
    with pytest.raises(ValueError, match="open"):
        am.voronoi_skeleton(pv, pe[1:])


def test_non_manifold_mesh_is_refused():
    v, f = icosphere(1)
    # A fin: an extra triangle on an existing edge makes it shared by three faces.
    fin_v = np.concatenate([v, [[3.0, 3.0, 3.0]]])
    fin_f = np.concatenate([f, [[f[0, 0], f[0, 1], len(v)]]]).astype(np.int32)
    with pytest.raises(ValueError, match="non-manifold"):
        am.voronoi_skeleton(fin_v, fin_f)
    # Two spheres sharing one vertex: every edge is fine, the vertex is not.
    b = v + (v[0] - (-v[0]))  # the second sphere's antipode of vertex 0 lands on vertex 0
    b_f = f + len(v)
    joined_v = np.concatenate([v, b])
    joined_f = np.concatenate([f, b_f]).astype(np.int32)
    antipode = int(np.argmin(np.linalg.norm(v + v[0], axis=1)))
    joined_f[joined_f == len(v) + antipode] = 0
    joined_v = np.delete(joined_v, len(v) + antipode, axis=0)
    joined_f[joined_f > len(v) + antipode] -= 1
    with pytest.raises(ValueError, match="non-manifold at vertex 0"):
        am.voronoi_skeleton(joined_v, joined_f)


def test_inward_and_inconsistent_orientation_are_refused():
    v, f = icosphere(1)
    with pytest.raises(ValueError, match="oriented inward"):
        am.voronoi_skeleton(v, f[:, ::-1])
    g = f.copy()
    g[0] = g[0, ::-1]
    with pytest.raises(ValueError, match="inconsistently oriented"):
        am.voronoi_skeleton(v, g)


def test_bad_arguments_are_refused():
    v, f = icosphere(1)
    with pytest.raises(ValueError, match="side"):
        am.voronoi_skeleton(v, f, side="inside")
    with pytest.raises(ValueError, match="wrap shape"):
        am.voronoi_skeleton(v, f, wrap="cone")
    with pytest.raises(ValueError, match="max_iterations"):
        am.voronoi_skeleton(v, f, max_iterations=-1)
    with pytest.raises(ValueError, match="columns"):
        am.voronoi_skeleton(v, f[:, :2])
    # Two closed spheres touching at a point, each with its own vertex there.
    b = v + 2 * v[0]
    with pytest.raises(ValueError, match="coincide"):
        am.voronoi_skeleton(np.concatenate([v, b]), np.concatenate([f, f + len(v)]).astype(np.int32))


def test_iteration_cap_is_reported_not_silently_hit():
    v, e = star()
    with pytest.warns(skel.SeparabilityWarning, match="not Voronoi separable after 1 splitting rounds"):
        capped = am.voronoi_skeleton(v, e, max_iterations=1)
    assert not capped.separable and capped.iterations == 1
    full = am.voronoi_skeleton(v, e, max_iterations=10)
    assert full.separable and 1 < full.iterations <= 10
    zero = skel.make_voronoi_separable(v, e, max_iterations=0)
    assert not zero.separable and zero.iterations == 0 and zero.remaining > 0


@pytest.mark.data
def test_bunny_separates_in_three_rounds_with_the_default_rule(shared_data):
    """§7.6.5: 'most models (the bunny for example) take three steps'. The
    dissertation's literal rule (one-ring, all edges) cascades on the bunny's
    obtuse triangles instead (Figure 7.11) and is capped."""
    v, f = load(shared_data, "bunny.off")
    sep = skel.make_voronoi_separable(v, f, max_iterations=4)
    assert sep.separable and sep.iterations == 3
    literal = skel.make_voronoi_separable(v, f, max_iterations=2, neighbourhood=1, in_plane_angle=0.0)
    assert not literal.separable and literal.remaining > 0
    rows, _ = skel.encroachments(sep.vertices, sep.faces)
    assert len(rows) == 0
    # The refined mesh is still a closed oriented manifold.
    report = am._core.check_manifold(sep.faces)
    assert report.is_oriented_manifold and report.boundary_facets == 0


# ------------------------------------------------------------------- CLI


def _cli(argv):
    import argparse

    from animanifold import cli_skeleton

    parser = argparse.ArgumentParser(prog="animanifold")
    sub = parser.add_subparsers(dest="command", required=True)
    cli_skeleton.add_parser(sub)
    args = parser.parse_args(argv)
    return args.func(args)


def test_cli_writes_the_skeleton_and_the_refined_mesh(tmp_path, capsys):
    a, fa = icosphere(2)
    v = np.concatenate([a + [-2.0, 0, 0], a + [2.0, 0, 0]])
    f = np.concatenate([fa, fa + len(a)]).astype(np.int32)
    src = tmp_path / "two.obj"
    am.write_mesh(src, v, f)
    out, refined = tmp_path / "skel.obj", tmp_path / "refined.off"
    assert _cli(["skeleton", str(src), "-o", str(out), "--side", "external", "--refined", str(refined)]) == 0
    printed = capsys.readouterr()
    assert "skeleton:" in printed.out and "separable after" in printed.out
    sv, sf = am.read_mesh(out)
    direct = am.voronoi_skeleton(v, f, side="external")
    assert len(sf) == len(direct.faces) and len(sv) == len(direct.vertices)
    np.testing.assert_allclose(sv, direct.vertices)
    rv, rf = am.read_mesh(refined)
    assert len(rf) == len(direct.refined_faces)
    attached = tmp_path / "attached.obj"
    assert _cli(["skeleton", str(src), "-o", str(attached), "--side", "external", "--attach"]) == 0
    av, af = am.read_mesh(attached)
    with_attachment = am.voronoi_skeleton(v, f, side="external", attach=True)
    assert len(av) == len(direct.refined_vertices) + len(direct.vertices)
    assert len(af) == len(rf) + len(sf) + len(with_attachment.attachment)


def test_cli_errors_are_one_line_with_exit_code_2(tmp_path, capsys):
    v, f = icosphere(1)
    src = tmp_path / "open.obj"
    am.write_mesh(src, v, f[1:])
    assert _cli(["skeleton", str(src), "-o", str(tmp_path / "s.obj")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("animanifold: error: ") and "open" in err and err.count("\n") == 1
    assert _cli(["skeleton", str(tmp_path / "missing.obj"), "-o", str(tmp_path / "s.obj")]) == 2
    assert "does not exist" in capsys.readouterr().err
    sphere = tmp_path / "sphere.obj"
    am.write_mesh(sphere, *icosphere(2))
    assert _cli(["skeleton", str(sphere), "-o", str(tmp_path / "s.obj"), "--side", "external"]) == 2
    assert "empty" in capsys.readouterr().err
    assert _cli(["skeleton", str(sphere), "-o", str(tmp_path / "s.obj"), "--max-iterations", "-1"]) == 2
