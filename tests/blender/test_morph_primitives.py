"""Blender's primitives placed as bench/bench_morph_primitives.py places them (bpy 4.5 makes them,
so the shapes are exactly Blender's), morphed with the default method."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "bench_morph_primitives", Path(__file__).resolve().parents[2] / "bench" / "bench_morph_primitives.py")
primitives = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(primitives)


def test_a_turned_cube_into_a_turned_cone_leaves_no_flat_cell_on_the_cones_side():
    """The survey's turned pair 9 (seed 1): after the conforming mesher's three rounds of mending flat
    cells (a planar quad's cocircular corners joined by a flat tet) one was left on the cone's side,
    and the prisms over it in the target's stack were flat, so the space-time triangulation had no
    certificate. Further rounds, while each leaves fewer flat cells, leave none."""
    (a, place_a), (b, place_b) = list(primitives.turned_pairs(12, 1))[9]
    assert (a, b) == ("cube", "cone")
    report = am.morph(primitives.primitive(a, **place_a), primitives.primitive(b, **place_b), 1.0, 48.0).validity
    assert report["flat_cells"] == 0, report
    assert report["crossings_certified"], report["certificate_failure"]
