"""Objects shared between Python threads (docs/ARCHITECTURE.md, "Threads"): calls that
release the GIL give the results they give one after the other, and nothing crashes."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere, torus


def rotation(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:3, 3] = [0.1 * angle, 0.0, 0.3]
    return t


def test_one_deformer_deformed_from_four_threads_gives_the_sequential_results():
    v, f = icosphere(3)
    v = np.ascontiguousarray(v * [1.0, 0.8, 2.5])
    anchors = np.flatnonzero(v[:, 2] < -2.0).astype(np.int32)
    handles = np.flatnonzero(v[:, 2] > 2.0).astype(np.int32)
    deformer = _core.Deformer(v, np.ascontiguousarray(f, np.int32), anchors, handles)
    # steps > 1 restores between the steps: each call runs long enough for others to overlap it.
    transforms = [rotation(0.2 * (i + 1)) for i in range(8)]
    expected = [deformer.deform(t, 3) for t in transforms]

    def run(i: int) -> list[np.ndarray]:
        return [deformer.deform(transforms[(i + j) % 8], 3) for j in range(8)]

    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(run, range(4)))
    for i, got in enumerate(results):
        for j, points in enumerate(got):
            np.testing.assert_array_equal(points, expected[(i + j) % 8])
    restored = [deformer.restore(5, 1e-9) for _ in range(2)]
    assert all(status.iterations >= 1 for status in restored)


def morph_pairs():
    v, f = icosphere(1)
    return [
        ((v, f), (v * [1.3, 1.0, 0.8], f), "skeleton"),  # convex to convex
        ((v, f), torus(), "skeleton"),  # genus 0 to genus 1: skeleton, TetGen, hole space
        ((v, f), (v * [1.3, 1.0, 0.8], f), "field"),
    ]


def test_morphs_in_threads_give_the_results_they_give_one_after_the_other():
    pairs = morph_pairs()

    def run(pair) -> am.AnimationManifold:
        source, target, method = pair
        return am.morph(source, target, method=method)

    sequential = [run(pair) for pair in pairs]
    with ThreadPoolExecutor(len(pairs)) as pool:
        threaded = list(pool.map(run, pairs))
    for one, other in zip(sequential, threaded):
        np.testing.assert_array_equal(other.points, one.points)
        np.testing.assert_array_equal(other.simplices, one.simplices)
