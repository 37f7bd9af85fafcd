"""The inputs' UV maps and material indices on a morph's frames (animanifold/morph_surface.py)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere, torus

# The torus's UV map wraps around its axis: u jumps from 1 back to 0 across one seam.
SEAM_JUMP = 1.0


def wrapped_uv(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """A cylindrical UV map per face corner: u the angle around z (over a turn), v the height.
    Faces across the seam take u past 1, so the map has a seam of jump 1 along +x."""
    corners = vertices[faces]
    u = (np.arctan2(corners[..., 1], corners[..., 0]) / (2 * np.pi)) % 1.0
    across = np.ptp(u, axis=1) > 0.5
    u[across] = np.where(u[across] < 0.5, u[across] + 1.0, u[across])
    return np.stack([u, corners[..., 2]], axis=-1)


def planar_uv(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """A seamless map: (x, y) of each corner, scaled into about 0..1."""
    return 0.25 * (vertices[faces][..., :2] + 2.0)


def sphere_and_torus():
    sphere = icosphere(3)
    ring = torus(major_radius=0.8, minor_radius=0.3, major=24, minor=12)
    return sphere, ring


def looks(sphere, ring):
    """The sphere: seamless UVs, materials 0 (lower half) and 1; the torus: a wrapped map (a seam),
    materials 2 (x < 0) and 3."""
    sphere_look = am.SurfaceAttributes(planar_uv(*sphere),
                                       (sphere[0][sphere[1]].mean(axis=1)[:, 2] > 0).astype(np.int32))
    ring_look = am.SurfaceAttributes(wrapped_uv(*ring), 2 + (ring[0][ring[1]].mean(axis=1)[:, 0] > 0).astype(np.int32))
    return sphere_look, ring_look


@pytest.fixture(scope="module", params=["field", "skeleton"])
def textured_morph(request):
    sphere, ring = sphere_and_torus()
    sphere_look, ring_look = looks(sphere, ring)
    m = am.morph(sphere, ring, method=request.param, source_attributes=sphere_look, target_attributes=ring_look)
    return m, (sphere, sphere_look), (ring, ring_look)


@pytest.fixture(scope="module")
def plain_morphs():
    """The same morphs without attributes, per method."""
    sphere, ring = sphere_and_torus()
    return {method: am.morph(sphere, ring, method=method) for method in ("field", "skeleton")}


def expected_look(frame, mesh, look):
    """Per frame corner, the input's UV there, and per frame face the material of the input face
    under its centre. The end frames lie on the inputs, but where an input's quad is planar a frame
    face may take its other diagonal and span two input faces: a corner's UV is then its UV in the
    input faces that hold it, on the side of any seam where the face under the frame face's centre
    is (the UV nearest to that face's linear map carried to the corner)."""
    vertices, faces = mesh
    centres = frame.vertices[frame.faces].mean(axis=1)
    distance, under, _ = _core.closest_points(np.ascontiguousarray(centres), vertices, faces)
    corners = frame.vertices[frame.faces].reshape(-1, 3)
    carried = np.einsum("nc,ncd->nd", barycentric(corners, vertices[faces[np.repeat(under, 3)]]),
                        look.uv[np.repeat(under, 3)])
    # Every input face against every corner: those that hold the corner (in their plane, inside).
    triangles = vertices[faces]
    weights = barycentric(corners[:, None], triangles[None])  # (corners, faces, 3)
    normal = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    height = np.abs(np.einsum("nfk,fk->nf", corners[:, None] - triangles[None, :, 0], normal))
    holds = (weights.min(axis=2) > -1e-9) & (height < 1e-9)
    options = np.einsum("nfc,fcd->nfd", weights, look.uv)
    off = np.where(holds, np.abs(options - carried[:, None]).max(axis=2), np.inf)
    uv = options[np.arange(len(corners)), np.argmin(off, axis=1)].reshape(frame.faces.shape + (2,))
    assert holds.any(axis=1).all()  # every corner lies on the input
    return distance, uv, look.material_index[under]


def barycentric(p: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (..., 3) of points p (..., 3) in the planes of triangles (..., 3, 3)."""
    a, b, c = triangles[..., 0, :], triangles[..., 1, :], triangles[..., 2, :]
    normal = np.cross(b - a, c - a)
    area2 = np.sum(normal * normal, axis=-1)
    wa = np.sum(np.cross(c - b, p - b) * normal, axis=-1) / area2
    wb = np.sum(np.cross(a - c, p - c) * normal, axis=-1) / area2
    return np.stack(np.broadcast_arrays(wa, wb, 1 - wa - wb), axis=-1)


@pytest.mark.parametrize("end", ["source", "target"])
def test_the_end_frames_have_the_inputs_uvs_and_materials_exactly(textured_morph, end):
    m, source, target = textured_morph
    (mesh, look), t = (source, m.time_range[0]) if end == "source" else (target, m.time_range[1])
    frame = m.slice(t)
    assert np.unique(frame.faces).size == len(frame.vertices)  # no copy of a vertex left loose
    distance, uv, material = expected_look(frame, mesh, look)
    assert distance.max() < 1e-9  # the end frame lies on the input
    got_uv = frame.vertex_attributes["uv"][frame.faces]
    assert np.abs(got_uv - uv).max() < 1e-9  # the seam's two sides included
    assert np.array_equal(frame.face_attributes["material_index"].reshape(-1), material)


def test_no_in_between_face_spans_a_seam(textured_morph):
    """A frame face takes its UVs from one chart: none stretches across the torus's seam (a jump of
    1 in u), and the faces of early frames keep the source's look, of late ones the target's."""
    m, _, _ = textured_morph
    t0, t1 = m.time_range
    for s in (0.02, 0.25, 0.5, 0.75, 0.98):
        frame = m.slice(t0 + s * (t1 - t0))
        uv = frame.vertex_attributes["uv"][frame.faces]
        assert np.ptp(uv[..., 0], axis=1).max() < 0.5 * SEAM_JUMP, s
        material = frame.face_attributes["material_index"].reshape(-1)
        assert set(np.unique(material)) <= {0, 1, 2, 3}
        from_source = np.mean(material < 2)
        if s <= 0.02:
            assert from_source > 0.75, (s, from_source)
        if s >= 0.98:
            assert from_source < 0.25, (s, from_source)


def test_the_look_is_reported_and_kept_by_the_cache(textured_morph, plain_morphs, tmp_path):
    """Only vertices are added (copies at seams), the simplices are the same morph's."""
    m, _, _ = textured_morph
    plain = plain_morphs[m.metadata["morph"]["method"]]
    report = m.validity["surface_attributes"]
    assert report["uv"] and report["materials"]
    used = np.unique(plain.simplices).size  # the seed's manifolds can hold points no simplex uses
    assert report["seam_vertices"] > 0 and len(m.points) == used + report["seam_vertices"]
    assert len(m.simplices) == len(plain.simplices)
    assert np.array_equal(m.points[m.simplices], plain.points[plain.simplices])
    assert any(stage == "surface attributes" for stage, _ in m.validity["stage_seconds"])
    am.save(m, tmp_path / "look.amf")
    back = am.load(tmp_path / "look.amf")
    assert np.array_equal(back.vertex_attributes["uv"], m.vertex_attributes["uv"])
    assert np.array_equal(back.simplex_attributes["material_index"], m.simplex_attributes["material_index"])


def test_materials_alone_split_no_vertex_and_an_input_without_a_map_reads_zero():
    sphere, ring = sphere_and_torus()
    plain = am.morph(sphere, ring, method="skeleton")
    _, ring_look = looks(sphere, ring)
    only_materials = am.morph(sphere, ring, method="skeleton",
                              target_attributes=am.SurfaceAttributes(material_index=ring_look.material_index))
    assert len(only_materials.points) == len(plain.points)
    assert "uv" not in only_materials.vertex_attributes
    first = only_materials.slice(only_materials.time_range[0])
    assert set(np.unique(first.face_attributes["material_index"])) == {0}  # the source has none: 0
    only_target_map = am.morph(sphere, ring, method="skeleton", target_attributes=am.SurfaceAttributes(uv=ring_look.uv))
    first = only_target_map.slice(only_target_map.time_range[0])
    assert np.array_equal(first.vertex_attributes["uv"], np.zeros((len(first.vertices), 2)))


@pytest.mark.parametrize("look, message", [
    (am.SurfaceAttributes(uv=np.zeros((5, 3, 2))), "source's UV map must be (faces, 3, 2)"),
    (am.SurfaceAttributes(material_index=np.full(1280, -1)), "source's face 0 has material index -1"),
    (am.SurfaceAttributes(material_index=np.full(1280, 0.5)), "source's material indices must be integers"),
])
def test_attributes_that_do_not_fit_are_refused_before_the_morph(look, message):
    sphere, ring = sphere_and_torus()
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        am.morph(sphere, ring, source_attributes=look)


def test_nan_uvs_name_the_face():
    sphere, ring = sphere_and_torus()
    uv = planar_uv(*sphere)
    uv[17, 1, 0] = np.nan
    with pytest.raises(ValueError, match="source's UV map holds NaN or infinity at face 17"):
        am.morph(sphere, ring, source_attributes=am.SurfaceAttributes(uv=uv))


def test_2d_morphs_take_no_attributes():
    square = (np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), np.array([[0, 1], [1, 2], [2, 3], [3, 0]]))
    with pytest.raises(ValueError, match="3D morphs"):
        am.morph(square, square, source_attributes=am.SurfaceAttributes(material_index=np.zeros(4, int)))


def test_closest_points_answer_on_a_known_shape_and_refuse_bad_faces():
    vertices, faces = icosphere(2)
    points = np.array([[0.0, 0.0, 2.0], [0.3, 0.1, -0.2]])
    distance, face, barycentric = _core.closest_points(points, vertices, faces)
    closest = np.einsum("ij,ijk->ik", barycentric, vertices[faces[face]])
    assert np.allclose(np.linalg.norm(closest - points, axis=1), distance)
    assert np.allclose(barycentric.sum(axis=1), 1.0) and (barycentric > -1e-12).all()
    assert distance[0] == pytest.approx(1.0)  # the top vertex of the unit sphere
    assert np.all(distance <= np.linalg.norm(vertices[:, None] - points[None], axis=2).min(axis=0) + 1e-12)
    bad = faces.copy()
    bad[3, 1] = len(vertices)
    with pytest.raises(ValueError, match=f"face 3 refers to vertex {len(vertices)}"):
        _core.closest_points(points, vertices, bad)


def test_frames_cut_by_the_shared_holes_keep_their_look():
    """A wobbly torus into a copy 5 % wider (the shared tunnel is cut out of every in-between
    frame): the raw frames are split along the UV seam, so the cut welds them first, and the cut
    frame takes its UVs and materials back, seam included."""
    from helpers.shapes import torus as make_torus

    v, f = make_torus(major=20, minor=9, wobble=0.1)
    wider = v * [1.05, 1.05, 1.0]
    materials = (v[f].mean(axis=1)[:, 2] > 0).astype(np.int32)
    look = am.SurfaceAttributes(wrapped_uv(v, f), materials)
    m = am.morph((v, f), (wider, f), method="strip", source_attributes=look, target_attributes=look)
    assert m.hole_space is not None
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a frame shown uncut warns
        cut = m.slice(0.5)
    raw = m.slice(0.5, honour_holes=False)
    assert len(cut.faces) != len(raw.faces)  # the tunnel was cut out
    uv = cut.vertex_attributes["uv"]
    assert uv.shape == (len(cut.vertices), 2) and np.ptp(uv[cut.faces][..., 0], axis=1).max() < 0.5 * SEAM_JUMP
    assert set(np.unique(cut.face_attributes["material_index"])) == {0, 1}
    # welded by position, the cut frame is a closed surface
    welded = np.unique(cut.vertices, axis=0, return_inverse=True)[1].reshape(-1)[cut.faces]
    edges = np.sort(welded[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    assert (np.unique(edges, axis=0, return_counts=True)[1] == 2).all()
    # where a cut corner is a raw vertex, its UV is one of that vertex's copies' UVs
    raw_uv = {}
    for p, w in zip(map(tuple, raw.vertices), raw.vertex_attributes["uv"]):
        raw_uv.setdefault(p, []).append(w)
    for p, w in zip(map(tuple, cut.vertices), uv):
        if p in raw_uv:
            assert min(np.abs(w - other).max() for other in raw_uv[p]) < 1e-9
