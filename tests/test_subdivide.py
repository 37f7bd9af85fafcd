"""Smoothing: Schaefer et al. (2004) subdivision of manifolds, OpenSubdiv on frames (issue 8)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers.shapes import cube, icosphere, polygon

import animanifold as am
from animanifold import _core

TIMES = np.arange(5.0)
ZIGZAG = np.array([[0, 0, 0], [1, 1, 0], [2, 0, 0], [3, 1, 0], [4, 0, 0]], float)


def enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    t = vertices[faces]
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6)


def cube_quads() -> tuple[np.ndarray, np.ndarray]:
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    q = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]], np.int32)
    return v, q


def moving_sphere(path: np.ndarray, subdivisions: int = 1, radius: float = 0.5) -> am.AnimationManifold:
    v, f = icosphere(subdivisions)
    return am.stitch([v * radius + p for p in path], f, TIMES[: len(path)])


def keyframe_paths(manifold: am.AnimationManifold, parents: np.ndarray, m: int, k: int) -> np.ndarray:
    """(k, 2m-1, D): for each keyframe vertex j its path through the subdivided
    manifold: keyframe vertex i*k+j (same id after subdivision), the midpoint
    of the edge to (i+1)*k+j, and so on."""
    midpoint = {(int(a), int(b)): i for i, (a, b) in enumerate(parents) if a >= 0 and a != b}
    ids = np.empty((k, 2 * m - 1), np.int64)
    for j in range(k):
        for i in range(m):
            ids[j, 2 * i] = i * k + j
            if i + 1 < m:
                ids[j, 2 * i + 1] = midpoint[(i * k + j, (i + 1) * k + j)]
    return manifold.points[ids]


def turning_angles(paths: np.ndarray) -> np.ndarray:
    """Degrees between consecutive segments of each polyline in (x, y, z, t)."""
    d = np.diff(paths, axis=1)
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.einsum("pij,pij->pi", d[:, 1:], d[:, :-1]), -1, 1)))


# --- manifold subdivision ------------------------------------------------------


def test_one_level_is_conforming_oriented_with_eight_times_the_tets():
    m = moving_sphere(ZIGZAG[:4] * [1, 0.3, 0])
    m1 = am.subdivide(m, levels=1)
    assert len(m1.simplices) == 8 * len(m.simplices) == am.subdivided_simplex_count(m, 1)
    report = m1.check()
    assert report.is_oriented_manifold, report
    assert report.nonmanifold_facets == 0 and report.misoriented_facets == 0
    # Conforming: every interior facet shared by exactly two tets, no tet twice.
    assert 2 * report.interior_facets + report.boundary_facets == 4 * len(m1.simplices)
    assert len(np.unique(np.sort(m1.simplices, axis=1), axis=0)) == len(m1.simplices)
    # The boundary is still the first and last keyframe, refined 1 -> 4, at their times.
    boundary = m1.boundary()
    assert len(boundary) == 4 * len(m.boundary())
    times = m1.points[boundary, -1]
    assert set(np.unique(times)) == {0.0, 3.0}
    assert np.all(times.min(axis=1) == times.max(axis=1))
    assert m1.time_range == (0.0, 3.0)
    # Every end slice is the refined keyframe: closed and outward like the keyframe.
    for t in (0.0, 3.0):
        s = m1.slice(t)
        assert len(s.faces) == 4 * len(m.slice(t).faces)
        assert _core.check_manifold(s.faces).boundary_facets == 0
        assert enclosed_volume(s.vertices, s.faces) > 0


def test_two_levels_give_sixty_four_times_the_tets():
    v, f = icosphere(0)
    m = am.stitch([v, v + [0.5, 0, 0], v + [1, 0.2, 0]], f, [0, 1, 2])
    m2 = am.subdivide(m, levels=2)
    assert len(m2.simplices) == 64 * len(m.simplices)
    assert m2.check().is_oriented_manifold
    assert len(m2.boundary()) == 16 * len(m.boundary())
    assert set(np.unique(m2.points[m2.boundary(), -1])) == {0.0, 2.0}


@pytest.mark.parametrize("levels", [1, 2])
def test_linear_refinement_keeps_every_child_with_its_parents_orientation(levels):
    # Full-dimensional meshes, where orientation is the sign of the volume:
    # tetrahedra in R^3 and triangles in R^2.
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1.2]], float)
    tets = np.array([[0, 1, 2, 3], [1, 4, 2, 3]], np.int32)
    assert np.all(_core._testing.signed_volumes(points, tets) > 0)
    r = _core.subdivide_manifold(_core.Complex(points, tets), levels, "linear")
    vol = _core._testing.signed_volumes(r.manifold.points, r.manifold.simplices)
    assert len(vol) == 2 * 8**levels
    assert vol.min() > 0
    assert vol.sum() == pytest.approx(_core._testing.signed_volumes(points, tets).sum(), rel=1e-12)
    flipped = tets[:, [1, 0, 2, 3]]
    r = _core.subdivide_manifold(_core.Complex(points, flipped), levels, "linear")
    assert _core._testing.signed_volumes(r.manifold.points, r.manifold.simplices).max() < 0

    p2 = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    tris = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    r = _core.subdivide_manifold(_core.Complex(p2, tris), levels, "linear")
    area = _core._testing.signed_volumes(r.manifold.points, r.manifold.simplices)
    assert len(area) == 2 * 4**levels and area.min() > 0 and area.sum() == pytest.approx(1.0)


def test_uniform_motion_stays_uniform_affine_invariance():
    velocity = np.array([0.7, 0.2, -0.1])
    v, f = icosphere(2)
    moving = am.stitch([v + velocity * t for t in TIMES], f, TIMES)
    static = am.stitch([v for _ in TIMES], f, TIMES)
    m1, parents, _ = am.subdivide(moving, 1, return_parents=True)
    s1 = am.subdivide(static, 1)
    # Subdividing the sheared manifold == shearing the subdivided one.
    sheared = s1.points.copy()
    sheared[:, :3] += np.outer(sheared[:, 3], velocity)
    np.testing.assert_allclose(m1.points, sheared, atol=1e-12)
    # Vertex paths (keyframe vertex -> edge midpoint -> next keyframe vertex) stay straight.
    paths = keyframe_paths(m1, parents, len(TIMES), len(v))
    assert turning_angles(paths).max() < 1.0
    # Frames translate with constant velocity: centroid minus velocity*t is constant.
    drift = np.array([m1.slice(t).vertices.mean(axis=0) - velocity * t for t in np.linspace(0, 4, 9)])
    assert np.ptp(drift, axis=0).max() < 0.01


@pytest.mark.parametrize("keep", [False, True])
def test_zigzag_paths_become_smoother_and_frame_volume_is_kept(keep):
    m = moving_sphere(ZIGZAG, subdivisions=2)
    k = len(icosphere(2)[0])
    before = turning_angles(m.points[np.arange(5)[None, :] * k + np.arange(k)[:, None]])
    m1, parents, _ = am.subdivide(m, 1, keep_keyframe_times=keep, return_parents=True)
    after = turning_angles(keyframe_paths(m1, parents, 5, k))
    assert before.max() == pytest.approx(70.53, abs=0.01)  # (1,1,0,1) vs (1,-1,0,1)
    # Free: 35.7 degrees. Keeping keyframe times pins the path's keyframe points
    # in time (and slides them along the manifold), so less smoothing: 52.3.
    assert after.max() < (0.8 if keep else 0.6) * before.max()
    # Volume of frames within 5% of the keyframes' (one level of smoothing shrinks ~3%).
    v0 = enclosed_volume(*[m.slice(0.0).vertices, m.slice(0.0).faces])
    for t in (0.0, 0.5, 1.0, 1.7, 2.0, 3.25, 4.0):
        s = m1.slice(t)
        assert _core.check_manifold(s.faces).boundary_facets == 0
        assert enclosed_volume(s.vertices, s.faces) == pytest.approx(v0, rel=0.05)


def test_keep_keyframe_times_keeps_keyframes_on_their_hyperplanes():
    path = np.array([[0, 0, 0], [0.4, 0.1, 0], [0.8, 0.15, 0], [1.2, 0.1, 0], [1.6, 0, 0]])
    v, f = icosphere(2)
    m = am.stitch([0.5 * v + p for p in path], f, TIMES)
    m1 = am.subdivide(m, levels=1, keep_keyframe_times=True)
    free = am.subdivide(m, levels=1, keep_keyframe_times=False)
    edges = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [0, 2]]]), axis=1), axis=0)
    for i, t in enumerate(TIMES):
        on_plane = np.count_nonzero(m1.points[:, -1] == t)
        assert on_plane == len(v) + len(edges)  # the keyframe's points and its edges' midpoints
        s = m1.slice(t)
        assert len(s.faces) == 4 * len(f)  # exactly the refined keyframe
        report = _core.check_manifold(s.faces)
        assert report.boundary_facets == 0 and report.is_oriented_manifold
        distance = np.abs(np.linalg.norm(s.vertices - path[i], axis=1) - 0.5)
        assert distance.max() < 0.03  # close to the keyframe sphere (radius 0.5)
        assert enclosed_volume(s.vertices, s.faces) > 0
    # Without the option, inner keyframes move in time (but the ends never do).
    inner = np.isin(free.points[:, -1], TIMES[1:-1]).sum()
    assert inner < 3 * (len(v) + len(edges))
    for t in (TIMES[0], TIMES[-1]):
        assert np.count_nonzero(free.points[:, -1] == t) == len(v) + len(edges)
    ends = m1.points[m1.boundary(), -1]
    assert set(np.unique(ends)) == {TIMES[0], TIMES[-1]}


def test_attributes_follow_the_same_stencils_and_simplex_attributes_are_inherited():
    v, f = icosphere(1)
    m = am.stitch(
        [v + [0.3 * t, 0.1 * t * t, 0] for t in TIMES[:4]],
        f,
        TIMES[:4],
        vertex_attributes={"w": np.arange(len(v), dtype=float)},
        face_attributes={"material": np.arange(len(f)) % 3},
    )
    # An attribute that is an affine function of the points stays that function.
    affine = m.points[:, 0] + 2 * m.points[:, 3] - 0.5 * m.points[:, 1]
    m = am.AnimationManifold.from_arrays(
        m.points, m.simplices, {"affine": affine, "w": m.vertex_attributes["w"]},
        {"material": m.simplex_attributes["material"]}, m.metadata,
    )
    m1, _, simplex_parent = am.subdivide(m, 1, return_parents=True)
    expected = m1.points[:, 0] + 2 * m1.points[:, 3] - 0.5 * m1.points[:, 1]
    np.testing.assert_allclose(m1.vertex_attributes["affine"][:, 0], expected, atol=1e-12)
    assert m1.vertex_attributes["w"].shape == (len(m1.points), 1)
    np.testing.assert_array_equal(
        m1.simplex_attributes["material"][:, 0], m.simplex_attributes["material"][simplex_parent, 0]
    )
    # Sliced frames carry them too.
    s = m1.slice(1.5)
    assert s.vertex_attributes["affine"].shape == (len(s.vertices),)
    assert set(np.unique(s.face_attributes["material"])) <= {0, 1, 2}


def test_two_dimensional_animation_subdivides_triangles_and_keeps_contours_closed():
    pv, pe = polygon(12)
    m = am.stitch([pv + [0.2 * i, 0.1 * (i % 2)] for i in range(4)], pe, [0, 1, 2, 3])
    m1 = am.subdivide(m, levels=2, keep_keyframe_times=True)
    assert len(m1.simplices) == 16 * len(m.simplices)
    assert m1.check().is_oriented_manifold
    assert set(np.unique(m1.points[m1.boundary(), -1])) == {0.0, 3.0}
    for t in (0.0, 1.0, 1.5, 3.0):
        s = m1.slice(t)
        n = len(s.vertices)
        # A closed, consistently oriented polyline: each point starts one segment and ends one.
        assert np.array_equal(np.sort(s.faces[:, 0]), np.arange(n))
        assert np.array_equal(np.sort(s.faces[:, 1]), np.arange(n))
        p = s.vertices
        area = 0.5 * np.sum(p[s.faces[:, 0], 0] * p[s.faces[:, 1], 1] - p[s.faces[:, 1], 0] * p[s.faces[:, 0], 1])
        assert area == pytest.approx(3.0, rel=0.06)  # the 12-gon's area is 3; smoothing shrinks it a little


def test_open_keyframes_keep_their_side_boundary():
    v, f = cube()
    half = f[:6]  # three faces of the cube: an open surface
    m = am.stitch([v + [0.1 * i, 0, 0] for i in range(3)], half, [0, 1, 2])
    m1 = am.subdivide(m, levels=1)
    assert m1.check().is_oriented_manifold
    boundary = m1.boundary()
    assert len(boundary) == 4 * len(m.boundary())
    t = m1.points[boundary, -1]
    flat = t.min(axis=1) == t.max(axis=1)
    assert flat.sum() == 4 * 2 * len(half) and set(np.unique(t[flat])) == {0.0, 2.0}


def test_level_zero_and_input_errors():
    m = moving_sphere(ZIGZAG[:2], subdivisions=0)
    same = am.subdivide(m, levels=0)
    np.testing.assert_array_equal(same.points, m.points)
    np.testing.assert_array_equal(same.simplices, m.simplices)
    with pytest.raises(ValueError, match="levels"):
        am.subdivide(m, levels=-1)
    with pytest.raises(ValueError, match="scheme"):
        am.subdivide(m, scheme="loop")
    nonmanifold = np.vstack([m.simplices, m.simplices[:1, [1, 0, 2, 3]]])
    with pytest.raises(ValueError, match="shared by 3 simplices"):
        am.subdivide(am.AnimationManifold.from_arrays(m.points, nonmanifold))
    degenerate = m.simplices.copy()
    degenerate[0, 1] = degenerate[0, 0]
    with pytest.raises(ValueError, match="simplex 0 repeats vertex"):
        am.subdivide(am.AnimationManifold.from_arrays(m.points, degenerate))


def test_subdivided_manifold_round_trips_through_the_cache(tmp_path):
    m1 = am.subdivide(moving_sphere(ZIGZAG[:3], subdivisions=0), levels=1, keep_keyframe_times=True)
    am.save(m1, tmp_path / "m.amf")
    back = am.load(tmp_path / "m.amf")
    np.testing.assert_array_equal(back.points, m1.points)
    assert back.metadata["subdivisions"] == [{"levels": 1, "scheme": "schaefer", "keep_keyframe_times": True}]


# --- OpenSubdiv on frames ------------------------------------------------------


def test_catmull_clark_cube_counts():
    v, q = cube_quads()
    r = am.subdivide_frame(v, q, levels=1, scheme="catmull_clark", crease_angle=0)
    assert r.vertices.shape == (26, 3) and r.faces.shape == (24, 4)
    assert r.crease_count == 0
    np.testing.assert_array_equal(np.bincount(r.face_parent), np.full(6, 4))
    r2 = am.subdivide_frame(v, q, levels=2, scheme="catmull_clark", crease_angle=0)
    assert r2.vertices.shape == (98, 3) and r2.faces.shape == (96, 4)
    # Smooth (no creases): corners are cut, every point lies strictly inside the cube.
    assert np.abs(r2.vertices).max(axis=1).max() < 1 - 1e-3


@pytest.mark.parametrize("scheme,mesh", [("catmull_clark", "quads"), ("loop", "triangles")])
def test_creases_keep_sharp_edges_sharp(scheme, mesh):
    v, f = cube_quads() if mesh == "quads" else cube()
    r = am.subdivide_frame(v, f, levels=3, scheme=scheme, crease_angle=30)
    assert r.crease_count == 12  # the cube's edges, not the triangles' diagonals
    # All points stay on the cube's surface and the corners stay put.
    np.testing.assert_allclose(np.abs(r.vertices).max(axis=1), 1.0, atol=1e-12)
    for corner in v:
        assert np.min(np.linalg.norm(r.vertices - corner, axis=1)) < 1e-12
    # Points on an edge of the cube stay on it (two coordinates at +-1).
    on_edge = np.sum(np.isclose(np.abs(r.vertices), 1.0, atol=1e-12), axis=1) >= 2
    assert on_edge.sum() == 12 * (2**3 - 1) + 8
    # Explicit crease edges do the same for the edges given.
    given = am.subdivide_frame(v, f, levels=1, scheme=scheme, crease_angle=0, crease_edges=[[0, 1], [1, 3]])
    assert given.crease_count == 2


def test_loop_limit_of_an_icosphere_is_close_to_the_sphere():
    v, f = icosphere(2)
    r = am.subdivide_frame(v, f, levels=2, scheme="loop")
    radius = np.linalg.norm(r.vertices, axis=1)
    assert len(r.faces) == 16 * len(f)
    # Loop's limit of the inscribed icosphere shrinks by at most 3% and stays round within 0.6%.
    assert np.abs(radius - 1).max() < 0.03
    assert np.ptp(radius) < 0.006
    # Normals are unit and point outward.
    np.testing.assert_allclose(np.linalg.norm(r.normals, axis=1), 1.0, atol=1e-12)
    assert np.einsum("ij,ij->i", r.normals, r.vertices / radius[:, None]).min() > 0.99


def test_frame_attributes_are_refined_with_the_points():
    v, f = icosphere(1)
    r = am.subdivide_frame(
        v, f, levels=2, vertex_attributes={"x": v[:, 0], "uv": v[:, :2]}, face_attributes={"id": np.arange(len(f))}
    )
    np.testing.assert_allclose(r.vertex_attributes["x"], r.vertices[:, 0], atol=1e-12)
    np.testing.assert_allclose(r.vertex_attributes["uv"], r.vertices[:, :2], atol=1e-12)
    np.testing.assert_array_equal(r.face_attributes["id"], r.face_parent)


def test_frame_input_errors():
    v, q = cube_quads()
    with pytest.raises(ValueError, match="Loop subdivision needs triangles"):
        am.subdivide_frame(v, q, scheme="loop")
    with pytest.raises(ValueError, match="crease edge 0 .* is not an edge"):
        am.subdivide_frame(v, q, scheme="catmull_clark", crease_edges=[[0, 7]])
    with pytest.raises(ValueError, match="face 0 refers to vertex 99"):
        am.subdivide_frame(v, np.array([[0, 1, 99]]))
    with pytest.raises(ValueError, match="scheme"):
        am.subdivide_frame(v, q, scheme="doo-sabin")


def test_slice_with_smooth_levels():
    m = moving_sphere(ZIGZAG[:3], subdivisions=1)
    plain = m.slice(0.5)
    smooth = m.slice(0.5, smooth_levels=2)
    assert len(smooth.faces) == 16 * len(plain.faces)
    assert _core.check_manifold(smooth.faces).boundary_facets == 0
    assert smooth.vertex_edges is None and smooth.edge_parameter is None
    # face_simplex still names the manifold simplex the (parent) face was cut from.
    assert set(np.unique(smooth.face_simplex)) == set(np.unique(plain.face_simplex))
    centre = smooth.vertices.mean(axis=0)
    assert np.einsum("ij,ij->i", smooth.normals, smooth.vertices - centre).min() > 0
    assert enclosed_volume(smooth.vertices, smooth.faces) > 0
    # smooth_levels=0 is the plain slice.
    again = m.slice(0.5, smooth_levels=0)
    np.testing.assert_array_equal(again.faces, plain.faces)
    with pytest.raises(ValueError, match="smooth_levels"):
        m.slice(0.5, smooth_levels=-1)


def test_contour_frames_of_2d_animations_smooth_as_bspline_curves():
    pv, pe = polygon(12)
    m = am.stitch([pv, pv + [1, 0]], pe, [0, 1])
    plain = m.slice(0.5)
    for levels in (1, 3):
        s = m.slice(0.5, smooth_levels=levels, crease_angle=45)  # the 12-gon turns by 30 degrees
        assert len(s.faces) == 2**levels * len(plain.faces)
        n = len(s.vertices)
        assert np.array_equal(np.sort(s.faces[:, 0]), np.arange(n))
        assert np.array_equal(np.sort(s.faces[:, 1]), np.arange(n))
        offset = s.vertices - s.vertices.mean(axis=0)
        radius = np.linalg.norm(offset, axis=1)
        # Round, inside the 12-gon's circumcircle: the frame between the keys is the 12-gon
        # (the prism frame), whose cubic B-spline limit lies at ~(4 + 2 cos 30°) / 6 = 0.955 of it.
        assert radius.max() < 1 and radius.max() - radius.min() < 1e-3 and radius.min() > 0.95
        assert np.einsum("ij,ij->i", s.normals, offset / radius[:, None]).min() > 0.99  # outward, like the slice's
    # A square keeps its corners (turns of 90 degrees > crease angle) and stays a square.
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    edges = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    square = am.stitch([sq, sq + [1, 0]], edges, [0, 1]).slice(0.5, smooth_levels=3)
    centred = np.abs(square.vertices - square.vertices.mean(axis=0)).max(axis=1)
    np.testing.assert_allclose(centred, 0.5, atol=1e-12)
    r = am.subdivide_frame(sq, edges, levels=2, crease_angle=0)
    assert r.crease_count == 0 and len(r.faces) == 16
    assert np.abs(r.vertices - 0.5).max(axis=1).max() < 0.5 - 1e-3  # rounded without corners
    with pytest.raises(ValueError, match="does not apply"):
        am.subdivide_frame(sq, edges, scheme="loop")


def test_welding_closes_seams_before_smoothing():
    """Split copies (as at UV seams) are boundaries until welded; a welded frame smooths into a closed surface."""
    from animanifold.procedural import icosphere as ico
    from animanifold.seams import weld_copies

    v, f = ico(1)
    # split vertex 0 into a copy used by half of its faces (a seam)
    around = np.flatnonzero((f == 0).any(axis=1))
    split = f.copy()
    split[around[: len(around) // 2]] = np.where(split[around[: len(around) // 2]] == 0, len(v), split[around[: len(around) // 2]])
    seamed = np.concatenate([v, v[:1]])
    assert _core.check_manifold(split).boundary_facets > 0
    kept, faces = weld_copies(seamed, split)
    assert len(kept) == len(v) and _core.check_manifold(faces).boundary_facets == 0
    m = am.stitch([seamed, seamed * 1.2], split, [0.0, 1.0])
    # stitch orders the copy next to its original, so both sides of the seam split alike and welding
    # leaves only the two keyframes as boundary
    assert m.check().boundary_facets > 2 * len(f)
    assert am.weld(m).check().boundary_facets == 2 * len(f)
    assert am.weld(m).check().is_oriented_manifold
    s = am.smooth_slice(m.slice(0.5), 1)
    assert _core.check_manifold(s.faces).boundary_facets == 0
    assert weld_copies(v, f) is None  # nothing to merge


@pytest.mark.parametrize("shape", ["surface", "polyline"])
def test_frame_subdivision_reports_its_steps_and_stops_when_asked(shape):
    """The interrupter of every long call: steps with growing fractions, then Cancelled from
    either callable, and the same result as without it when nobody stops it."""
    if shape == "surface":
        v, f = icosphere(2)
    else:
        v, f = polygon(12)
    steps = []
    r = am.subdivide_frame(v, f, levels=2, progress=lambda step, fraction: steps.append((step, fraction)) or True)
    plain = am.subdivide_frame(v, f, levels=2)
    assert np.array_equal(r.vertices, plain.vertices) and np.array_equal(r.faces, plain.faces)
    fractions = [fraction for _, fraction in steps]
    assert len(steps) >= 3 and fractions == sorted(fractions) and 0.0 <= fractions[0] and fractions[-1] <= 1.0
    with pytest.raises(am.Cancelled):
        am.subdivide_frame(v, f, levels=2, interrupted=lambda: True)
    second = []
    with pytest.raises(am.Cancelled):
        am.subdivide_frame(v, f, levels=2, progress=lambda step, fraction: second.append(step) or len(second) < 2)
    assert second == [step for step, _ in steps[:2]]  # stopped at the second step
