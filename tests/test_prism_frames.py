"""In-between frames of stitched keyframes: the keys' faces, each vertex on its vertical edge (prism_frames.py)."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from animanifold.prism_frames import Prisms
from helpers.cache_files import assemble, small_manifold, split
from helpers.keyframes import TIMES, wobble
from helpers.shapes import cube, icosphere, polygon
from helpers.surface_checks import triangles


def _sphere(subdivisions: int = 2):
    v, f = icosphere(subdivisions)
    frames = wobble(v, TIMES)
    uv = np.stack([frames[i][:, :2] * 0.5 + i for i in range(len(TIMES))])  # per key: UVs move too
    m = am.stitch(frames, f, TIMES, vertex_attributes={"uv": uv},
                  face_attributes={"material_index": np.arange(len(f)) % 4})
    return v, f, frames, uv, m


def _between(times=TIMES):
    """A few values strictly inside every gap, the ends' neighbourhoods included."""
    out = []
    for a, b in zip(times[:-1], times[1:]):
        out += [a + (b - a) * s for s in (1e-6, 0.25, 0.5, 0.9, 1 - 1e-6)]
    return out


def _lerp(frames, times, t):
    i = int(np.searchsorted(times, t)) - 1
    s = (t - times[i]) / (times[i + 1] - times[i])
    return (1 - s) * frames[i] + s * frames[i + 1]


def _edges_closed_and_oriented(faces: np.ndarray) -> bool:
    """Every directed edge appears once and its reverse once: closed, consistently oriented."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    keys = {tuple(e) for e in directed.tolist()}
    return len(keys) == len(directed) and all((b, a) in keys for a, b in keys)


def test_in_between_frames_have_the_keys_faces_and_their_blend():
    v, f, frames, uv, m = _sphere()
    assert m.prisms is not None
    for t in _between():
        s = m.slice(t)
        assert np.array_equal(s.faces, f)  # the source's faces, exactly: 1x its face count
        np.testing.assert_allclose(s.vertices, _lerp(frames, TIMES, t), rtol=0, atol=1e-12)
        np.testing.assert_allclose(s.vertex_attributes["uv"], _lerp(uv, TIMES, t), rtol=0, atol=1e-12)
        assert np.array_equal(s.face_attributes["material_index"], np.arange(len(f)) % 4)
        assert _edges_closed_and_oriented(s.faces)
        assert np.all(np.einsum("ij,ij->i", s.normals, s.vertices - s.vertices.mean(axis=0)) > 0)  # outward


def test_in_between_frames_report_their_vertical_edges():
    v, f, frames, uv, m = _sphere(1)
    k = len(v)
    t = 0.5 * (TIMES[1] + TIMES[2])
    s = m.slice(t)
    assert np.array_equal(s.vertex_edges, np.stack([k + np.arange(k), 2 * k + np.arange(k)], axis=1))
    np.testing.assert_allclose(s.edge_parameter, (t - TIMES[1]) / (TIMES[2] - TIMES[1]), rtol=0, atol=1e-15)
    # face_simplex: a tet of the face's own prism, carrying the face's attributes
    assert np.array_equal(s.face_simplex // (3 * len(f)), np.ones(len(f)))
    assert np.array_equal(m.simplex_attributes["material_index"][s.face_simplex, 0], s.face_attributes["material_index"])


def test_keys_are_the_key_meshes_bit_for_bit_over_the_frames_faces():
    v, f, frames, uv, m = _sphere()
    tets = am.AnimationManifold(m.core_complex, m.metadata)  # the same arrays without the prisms
    for i, t in enumerate(TIMES):
        s = m.slice(t)
        assert np.array_equal(s.vertices, frames[i]) and np.array_equal(s.faces, f)
        assert np.array_equal(s.vertex_attributes["uv"], uv[i])
        assert np.array_equal(s.face_attributes["material_index"], np.arange(len(f)) % 4)
        assert np.array_equal(s.vertex_edges[:, 0], s.vertex_edges[:, 1]) and not s.edge_parameter.any()
        assert triangles(s, "material_index") == triangles(tets.slice(t), "material_index")  # the tets' slice: the same triangles
        assert np.all(np.einsum("ij,ij->i", s.normals, s.vertices - s.vertices.mean(axis=0)) > 0)  # outward
    # Within the core's snap of a key, the key too (as the tets' slice snaps to it).
    near = m.slice(TIMES[1] + 1e-13)
    assert np.array_equal(near.vertices, frames[1]) and np.array_equal(near.faces, f)


def test_an_animation_that_keeps_its_faces_has_one_face_list_at_every_frame():
    """Keys and in-between frames share the source's faces, so playback never changes topology."""
    v, f, frames, uv, m = _sphere(1)
    values = sorted(set(TIMES) | set(_between()))
    for s in m.slices(values):
        assert np.array_equal(s.faces, f)


def test_the_prism_frame_is_made_of_the_staircase_frames_points_on_vertical_edges():
    """The same arithmetic as the core's cut: the prism frame's vertices are bit for bit
    the tets' slice's points on the vertical edges."""
    v, f, frames, uv, m = _sphere(1)
    tets = am.AnimationManifold(m.core_complex, m.metadata)
    t = 0.37
    s, stair = m.slice(t), tets.slice(t)
    assert len(stair.faces) > 3 * len(s.faces)  # the staircase: ~4 triangles per face
    rows = {tuple(e): i for i, e in enumerate(stair.vertex_edges.tolist())}
    same = [rows[tuple(e)] for e in s.vertex_edges.tolist()]
    assert np.array_equal(s.vertices, stair.vertices[same])


def test_slices_and_interval_frames_give_the_prism_frame():
    v, f, frames, uv, m = _sphere(1)
    values = _between()
    for s, t in zip(m.slices(values), values):
        fresh = m.slice(t)
        assert np.array_equal(s.vertices, fresh.vertices) and np.array_equal(s.faces, fresh.faces)
    frame = m.interval_frame(0.5)
    assert frame.interval == (TIMES[1], TIMES[2]) == m.topology_interval(0.5)
    assert np.array_equal(frame.slice.faces, f)
    for t in (0.31, 0.6, 0.99):
        moved = frame.at(t)
        assert np.array_equal(moved.faces, f)
        np.testing.assert_allclose(moved.vertices, _lerp(frames, TIMES, t), rtol=0, atol=1e-12)
        np.testing.assert_allclose(moved.vertex_attributes["uv"], _lerp(uv, TIMES, t), rtol=0, atol=1e-12)


def test_a_gap_not_played_as_prisms_keeps_the_tets_slice():
    """A gap whose keys differ in connectivity, or that a morph joined, is marked off: its
    frames stay the tets' slice, while the other gaps play prisms."""
    v, f, frames, uv, m = _sphere(1)
    p = m.prisms
    gaps = np.array(p.gaps)
    gaps[1] = False
    marked = am.AnimationManifold(m.core_complex, m.metadata, prisms=Prisms(p.times, p.key_vertices, p.faces,
                                                                              p.face_simplices, gaps))
    tets = am.AnimationManifold(m.core_complex, m.metadata)
    inside = 0.5 * (TIMES[1] + TIMES[2])
    assert np.array_equal(marked.slice(inside).faces, tets.slice(inside).faces)
    assert len(marked.slice(inside).faces) > len(f)
    assert np.array_equal(marked.interval_frame(inside).slice.faces, tets.slice(inside).faces)
    assert np.array_equal(marked.slice(0.1).faces, f)
    # The key below the gap takes its faces from the gap's tets: the tets' slice; the key above, the prisms'.
    assert np.array_equal(marked.slice(TIMES[1]).faces, tets.slice(TIMES[1]).faces)
    assert np.array_equal(marked.slice(TIMES[2]).faces, f)


def test_contours_play_prisms_too():
    v, e = polygon(24)
    times = np.array([0.0, 1.0, 3.0])
    frames = np.stack([v * (1 + 0.2 * t) + [0.3 * t, 0] for t in times])
    m = am.stitch(frames, e, times)
    for t in (0.5, 2.2):
        s = m.slice(t)
        assert np.array_equal(s.faces, e)
        np.testing.assert_allclose(s.vertices, _lerp(frames, times, t), rtol=0, atol=1e-12)


def test_save_and_load_keep_the_prisms(tmp_path):
    v, f, frames, uv, m = _sphere(1)
    path = am.save(m, tmp_path / "m.amf")
    loaded = am.load(path)
    assert loaded.prisms is not None
    for name in ("times", "key_vertices", "faces", "face_simplices", "gaps"):
        assert np.array_equal(getattr(loaded.prisms, name), getattr(m.prisms, name)), name
    for t in _between():
        a, b = m.slice(t), loaded.slice(t)
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)


def test_a_cache_written_before_the_prisms_loads_without_them(tmp_path):
    """A file without the prism arrays (version 1, as every stitched cache was written before)
    loads, and its in-between frames are the tets' slice as before."""
    v, f, frames, uv, m = _sphere(1)
    old = am.AnimationManifold(m.core_complex, m.metadata)  # what the old writer saw
    path = am.save(old, tmp_path / "old.amf")
    assert int.from_bytes(path.read_bytes()[8:12], "little") == 1
    loaded = am.load(path)
    assert loaded.prisms is None
    assert np.array_equal(loaded.slice(0.5).faces, old.slice(0.5).faces)
    assert len(loaded.slice(0.5).faces) > len(f)


@pytest.mark.parametrize("change, message", [
    (lambda a: a.__setitem__("prism_key_vertices", a["prism_key_vertices"][::-1].copy()), "not all at its time"),
    (lambda a: a.__setitem__("prism_faces", a["prism_faces"] + 10**6), "prism face corner"),
    (lambda a: a.__setitem__("prism_face_simplices", a["prism_face_simplices"] - 10**6), "prism face simplex"),
    (lambda a: a.pop("prism_gaps"), "prism_gaps missing"),
])
def test_a_damaged_prism_structure_is_refused_naming_it(tmp_path, change, message):
    v, f, frames, uv, m = _sphere(1)
    arrays = m.prisms.arrays()
    change(arrays)
    with pytest.raises(ValueError, match=message):
        Prisms.from_arrays(arrays).checked(m.points, len(m.simplices))


def test_deform_keeps_the_prisms_only_while_every_key_stays_at_its_time():
    v, f = cube()
    times = np.array([0.0, 1.0, 2.0])
    frames = np.stack([v * (1 + 0.1 * t) for t in times])
    m = am.stitch(frames, f, times)
    k = len(v)
    move = am.handle_transform(translation=[0.5, 0, 0, 0])
    # The solve moves free vertices through time too: the middle key leaves its time.
    free = am.deform(m, np.arange(k), np.arange(2 * k, 3 * k), move)
    assert np.ptp(free.points[k:2 * k, 3]) > 0 and free.prisms is None
    # Every vertex pinned or moved in space: each key stays at its time, the prisms hold.
    pinned = am.deform(m, np.arange(2 * k), np.arange(2 * k, 3 * k), move)
    assert pinned.prisms is not None
    t = 1.5
    np.testing.assert_allclose(pinned.slice(t).vertices, 0.5 * (pinned.points[k:2 * k, :3] + pinned.points[2 * k:, :3]),
                               rtol=0, atol=1e-12)
    assert np.array_equal(pinned.slice(t).faces, f)


def test_refine_subdivide_and_weld_drop_the_prisms():
    v, f, frames, uv, m = _sphere(1)
    edges = np.unique(np.sort(m.simplices[:, [0, 1]], axis=1), axis=0)[:10]
    refined, _ = am.refine(m, (edges.astype(np.int32), np.full(edges.shape, 0.5)))
    assert refined.prisms is None
    assert am.subdivide(m, levels=1).prisms is None
    # a seam: faces on one side use a copy of vertex 0, which weld merges
    k = len(v)
    seamed_faces = np.array(f)
    side = np.flatnonzero((f == 0).any(axis=1))[:2]
    seamed_faces[side] = np.where(f[side] == 0, k, f[side])
    seamed = am.stitch(np.concatenate([frames, frames[:, :1]], axis=1), seamed_faces, TIMES)
    assert seamed.prisms is not None
    assert am.weld(seamed).prisms is None


def test_a_loose_key_vertex_is_left_out_of_the_frame_as_the_tets_slice_leaves_it():
    v, f, frames, uv, m = _sphere(1)
    loose = am.stitch(np.concatenate([frames, frames[:, :1] + 5.0], axis=1), f, TIMES)
    s = loose.slice(0.5)
    assert len(s.vertices) == len(v) and np.array_equal(s.faces, f)


def _saved_prism_arrays(tmp_path):
    """(header, payload, {name: (offset, dtype, shape)}) of a saved manifold with prisms."""
    data = am.save(small_manifold(prisms=True), tmp_path / "m.amf").read_bytes()
    version, header, payload = split(data)
    assert version == 2
    offsets, start = {}, 0
    widths = ([("points", "<f8", header["points"], 4), ("simplices", "<i4", header["simplices"], 4)]
              + [(k, "<f8", header["points"], c) for k, c in header["vertex_attributes"]]
              + [(k, "<i4", header["simplices"], c) for k, c in header["simplex_attributes"]]
              + [tuple(entry) for entry in header["arrays"]])
    for name, dtype, rows, cols in widths:
        offsets[name] = (start, dtype, (rows, cols))
        start += np.dtype(dtype).itemsize * rows * cols
    assert start == len(payload)
    return header, payload, offsets


@pytest.mark.parametrize("name, value, message", [
    ("prism_key_vertices", 10**6, "prism key vertex 1000000"),
    ("prism_face_simplices", -1, "prism face simplex -1"),
    ("prism_times", -0.5, r"prism gap 0 \(-0.5 to 0.3\) does not hold"),
])
def test_a_cache_with_a_damaged_prism_array_is_refused_naming_it(tmp_path, name, value, message):
    header, payload, offsets = _saved_prism_arrays(tmp_path)
    start, dtype, _ = offsets[name]
    damaged = bytearray(payload)
    damaged[start:start + np.dtype(dtype).itemsize] = np.array([value], dtype=dtype).tobytes()
    path = tmp_path / "damaged.amf"
    path.write_bytes(assemble(2, header, bytes(damaged)))
    with pytest.raises(am.CacheError, match=message):
        am.load(path)


def test_a_cache_with_half_the_prism_arrays_is_refused(tmp_path):
    header, payload, offsets = _saved_prism_arrays(tmp_path)
    start, _, _ = offsets["prism_gaps"]
    assert header["arrays"][-1][0] == "prism_gaps"
    header["arrays"] = header["arrays"][:-1]
    path = tmp_path / "half.amf"
    path.write_bytes(assemble(2, header, payload[:start]))
    with pytest.raises(am.CacheError, match="prism_gaps missing"):
        am.load(path)


def test_a_key_moved_off_its_time_drops_only_the_gaps_beside_it():
    v, f, frames, uv, m = _sphere(1)
    k = len(v)
    points = np.array(m.points)
    points[2 * k + 5, 3] += 0.01  # one vertex of key 2 (t = 1.0) moves into the gap after it
    kept = m.prisms.holds_for(points, len(m.simplices))
    assert kept.gaps.tolist() == [True, False, False, True]
    points[2 * k + 5, 3] = TIMES[0] - 0.01  # now below every other key: gap 0 is reached into too
    assert m.prisms.holds_for(points, len(m.simplices)).gaps.tolist() == [False, False, False, True]
    moved = am.AnimationManifold.from_arrays(points, m.simplices, prisms=kept.holds_for(points, len(m.simplices)))
    assert len(moved.slice(2.0).faces) == len(f) and len(moved.slice(0.5).faces) > len(f)


def test_prism_frames_are_the_same_bits_on_one_and_two_threads():
    v, f, frames, uv, m = _sphere(4)
    previous = am.threads()
    try:
        am.set_threads(1)
        one = [m.slice(t) for t in (0.15, 0.65, 1.8)]
        am.set_threads(2)
        two = [m.slice(t) for t in (0.15, 0.65, 1.8)]
    finally:
        am.set_threads(previous)
    for a, b in zip(one, two):
        for name in ("vertices", "faces", "normals", "vertex_edges", "edge_parameter", "face_simplex"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert np.array_equal(a.vertex_attributes["uv"], b.vertex_attributes["uv"])


def test_a_vertex_attribute_the_same_at_every_key_is_one_shared_array_at_the_keys():
    """Playback reuses what it made of a key's UVs when the next key hands out the same
    unchangeable array: only when every key's values are equal."""
    v, f, frames, uv, m = _sphere(1)
    still = am.stitch(frames, f, TIMES, vertex_attributes={"uv": uv[0], "moving": uv})
    first, second = still.slice(TIMES[0]), still.slice(TIMES[2])
    assert first.vertex_attributes["uv"] is second.vertex_attributes["uv"]
    assert not first.vertex_attributes["uv"].flags.writeable
    assert np.array_equal(second.vertex_attributes["uv"], uv[0])
    assert first.vertex_attributes["moving"] is not second.vertex_attributes["moving"]
    assert np.array_equal(second.vertex_attributes["moving"], uv[2])
    assert np.array_equal(m.slice(TIMES[3]).vertex_attributes["uv"], uv[3])  # animated UVs: each key its own
