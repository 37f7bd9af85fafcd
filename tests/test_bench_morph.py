"""The measuring helpers of bench/bench_morph.py (not its timings): exact
point-to-mesh distances, Hausdorff distances and topology on tiny meshes."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from helpers.shapes import icosphere

_spec = importlib.util.spec_from_file_location(
    "bench_morph", Path(__file__).resolve().parents[1] / "bench" / "bench_morph.py")
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def torus(n_major=12, n_minor=8, R=2.0, r=0.6):
    u, v = np.meshgrid(np.arange(n_major) * 2 * np.pi / n_major, np.arange(n_minor) * 2 * np.pi / n_minor, indexing="ij")
    x = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a, b = i * n_minor + j, (i + 1) % n_major * n_minor + j
    c, d = (i + 1) % n_major * n_minor + (j + 1) % n_minor, i * n_minor + (j + 1) % n_minor
    return x, np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])


def brute_force_distance(points, vertices, faces):
    tri = vertices[faces]
    rows = np.repeat(np.arange(len(points)), len(faces))
    cols = np.tile(np.arange(len(faces)), len(points))
    p = points[rows]
    q = bench.closest_points_on_triangles(p, tri[cols, 0], tri[cols, 1], tri[cols, 2])
    return np.linalg.norm(q - p, axis=1).reshape(len(points), len(faces)).min(1)


def with_a_large_face(shape):
    """The mesh plus one triangle far larger than its faces (measured apart)."""
    v, f = shape
    return np.concatenate([v, [[-3.0, -3, 1.5], [3, -3, 1.5], [0, 4, 1.5]]]), np.concatenate([f, [len(v) + np.arange(3)]])


@pytest.mark.parametrize("shape", [icosphere(2), torus(), with_a_large_face(icosphere(2))])
def test_pruned_distance_is_the_exact_distance_to_the_mesh(shape, rng):
    v, f = shape
    points = np.concatenate([rng.uniform(v.min(0) - 1, v.max(0) + 1, (300, 3)), bench.surface_samples(v, f)])
    d = bench.distance_to_mesh(points, v, f, chunk=97)
    np.testing.assert_allclose(d, brute_force_distance(points, v, f), rtol=0, atol=1e-12)
    # the closest point of a face to its own corners, edges and centre is itself
    assert d[300:].max() < 1e-12


def test_closest_point_regions():
    a, b, c = np.array([[0.0, 0, 0]]), np.array([[1.0, 0, 0]]), np.array([[0.0, 1, 0]])
    cases = {(0.2, 0.2, 3.0): (0.2, 0.2, 0), (-1, -1, 0): (0, 0, 0), (2, -1, 0): (1, 0, 0), (-1, 2, 0): (0, 1, 0),
             (0.5, -1, 1): (0.5, 0, 0), (-1, 0.5, 0): (0, 0.5, 0), (1, 1, -2): (0.5, 0.5, 0)}
    for p, q in cases.items():
        np.testing.assert_allclose(bench.closest_points_on_triangles(np.array([p], float), a, b, c)[0], q, atol=1e-15)


def test_hausdorff_of_a_sphere_and_a_larger_copy():
    v, f = icosphere(2)
    assert max(bench.hausdorff(v, f, v, f)) < 1e-15
    a, b = bench.hausdorff(1.1 * v, f, v, f)
    # The polytope is inscribed in its sphere, so an outer vertex's nearest
    # point is the inner vertex on its ray, 0.1 away; edge midpoints and face
    # centres are nearer.
    assert a == pytest.approx(0.1, abs=1e-12)
    # Inner samples lie inside the outer (convex) polytope: their distance to
    # it is the smallest distance to its face planes.
    tri = 1.1 * v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    offsets = np.einsum("ij,ij->i", n, tri[:, 0])
    inner = bench.surface_samples(v, f)
    assert b == pytest.approx((offsets[None, :] - inner @ n.T).min(1).max(), abs=1e-12)
    assert 0.09 < b < 0.1


def test_topology_of_closed_open_and_higher_genus_meshes():
    v, f = icosphere(1)
    t = bench.topology(v, f)
    assert t["closed"] and t["oriented"] and (t["chi"], t["components"], t["genus"]) == (2, 1, 0)
    t = bench.topology(v, f[1:])
    assert not t["closed"] and t["boundary_edges"] == 3 and t["genus"] is None
    tv, tf = torus()
    t = bench.topology(np.concatenate([v, tv]), np.concatenate([f, tf + len(v)]))
    assert t["closed"] and (t["chi"], t["components"], t["genus"]) == (2, 2, 1)


def test_stage_rows_merge_the_seeds_stages_in_place():
    assert bench.stage_rows(["conforming", "fill", "strip", "boundary", "validity"]) == [
        "conforming", "find", "fill", "push", "strip", "boundary", "validity"]
    assert bench.stage_rows([]) == list(bench.SEED_ORDER)
    assert bench.stage_rows(["skeleton", "conforming", "fill", "push", "strip"])[:4] == [
        "skeleton", "conforming", "find", "fill"]


def test_the_bar_table_of_a_tiny_pair_holds_real_measures():
    """bench/morph_bar.py on icosphere(1) -> torus, the field method only, no peer, 4 frames:
    a row per method asked, the ends exact, no noise, and a row that raises is reported as
    an error row instead of stopping the table."""
    from helpers.shapes import torus as shapes_torus

    bar = bench.morph_bar
    pair = bar.Pair("sphere->torus", bar.normalised(icosphere(1)), bar.normalised(shapes_torus()))
    rows = bar.bar_rows(pair, ["field"], 4)
    assert [row.label for row in rows] == ["field"]
    row = rows[0]
    assert row.error is None, row.error
    assert row.ends <= bar.ENDS
    assert row.noise == 0
    assert row.frames == 4 and 0 <= row.crossing <= 4 and 0 <= row.bubble <= 4
    assert row.flat == 0 and row.seconds > 0 and row.quarter > 0 and row.pop >= 1
    assert np.isfinite(row.creases) and row.creases >= -1
    # the morph's own checks against their budget, and how crossings were covered
    assert any(n.startswith("checks ") and "% of the morph's own" in n and "budget" in n for n in row.notes), row.notes
    # (certified for every time and confirmed on a frame, or looked for on the spread frames: one of them)
    crossing_notes = [n for n in row.notes if n.startswith("crossings: ")]
    assert len(crossing_notes) == 1, row.notes
    assert (("space-time triangulation certified for every time (its sides' covers checked beside the fill"
             in crossing_notes[0] and "CGAL confirms on 1 frame(s)" in crossing_notes[0])
            or "checked on 24 frames (" in crossing_notes[0]), row.notes

    broken = bar.Pair("empty", pair.source, (pair.target[0], pair.target[1][:0]))
    failed = bar.bar_rows(broken, ["field"], 4)[0]
    assert failed.error and bar.misses(failed, None) == ["error"]

    table = bar.format_table(pair, rows + [failed], 4).splitlines()
    assert table[1].split() == ["row", "seconds", "ends", "noise", "creases+", "pop", "quarter", "crossing",
                                "bubble", "flat/inv", "bar"]
    assert table[2].split()[0] == "field" and table[2].split()[-1] == ("no" if bar.misses(row, None) else "yes")
    assert "error:" in table[3]
    assert any(line.startswith("  field: checks ") for line in table), table
    assert bar.summary_line(pair, rows).startswith("sphere->torus: meets the bar: ")


@pytest.mark.parametrize("start, end, showing", [(0.49, 0.51, "none"), (0.48, 0.52, "24, 25")])
def test_the_notes_say_which_of_48_frames_next_to_the_noise_show_it(start, end, showing):
    """At 48 frames over [0, 1], frames 24 and 25 are at 0.489 and 0.511: an island living from 0.49
    to 0.51 (noise the checks found at three times inside it) falls between them, one living from
    0.48 to 0.52 shows on both."""
    from helpers.noise_stand_in import TETRAHEDRON, swept_with_island

    bar = bench.morph_bar
    manifold = swept_with_island(start, end)
    manifold.metadata["validity"] = {"noise_frames": [0.4925, 0.5, 0.5075]}
    notes = bar.rendered_noise_notes(manifold, bar.Pair("stand-in", TETRAHEDRON, TETRAHEDRON))
    assert notes == [f"at 48 frames: frames next to the noise 24, 25; showing it: {showing}"]
    manifold.metadata["validity"] = {"noise_frames": []}
    assert bar.rendered_noise_notes(manifold, bar.Pair("stand-in", TETRAHEDRON, TETRAHEDRON)) == []


def test_pair_names_are_matched_without_punctuation():
    assert [p.name for p in bench.morph_bar.load_pairs(["icosphere-ring_of_holes"])] == ["icosphere->ring_of_holes"]
    with pytest.raises(SystemExit):
        bench.morph_bar.load_pairs(["no such pair"])
