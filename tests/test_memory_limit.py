"""The memory limit (issue 23): stitch, subdivide, refine and frame subdivision estimate their
peak memory before allocating and refuse beyond the limit with a MemoryLimitError naming the
call, the estimate and the limit. Every limit here is set by the test (small): no test
allocates more than a few megabytes, whatever the machine's memory."""

from __future__ import annotations

import os
import re

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from animanifold.cli import main
from helpers.keyframes import TIMES, wobble
from helpers.shapes import icosphere

MiB = 2**20


@pytest.fixture
def limit():
    """Sets the limit for one test (limit(bytes)); the default again afterwards."""
    yield am.set_memory_limit
    am.set_memory_limit(None)


@pytest.fixture
def manifold() -> am.AnimationManifold:
    v, f = icosphere(1)  # 42 vertices, 80 faces: 5 keyframes give 960 tets
    return am.stitch(wobble(v, TIMES), f, TIMES)


def refusal(call, *args, **kwargs) -> str:
    with pytest.raises(am.MemoryLimitError) as caught:
        call(*args, **kwargs)
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, MemoryError)
    return str(caught.value)


def meminfo_available() -> int:
    with open("/proc/meminfo") as meminfo:
        for line in meminfo:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    raise AssertionError("/proc/meminfo has no MemAvailable")


@pytest.mark.skipif(not os.path.exists("/proc/meminfo"), reason="reads MemAvailable from /proc/meminfo (Linux)")
def test_the_default_limit_is_half_the_available_memory(limit):
    # Available memory is MemAvailable, or less where the process's cgroups allow less (their
    # files are stood in for by the C++ tests). It moves between two reads: a quarter either
    # way is plenty.
    available = _core.available_memory()
    assert 0 < available < meminfo_available() * 1.25
    assert abs(am.memory_limit() - available / 2) < available / 8
    limit(12345)
    assert am.memory_limit() == 12345 and am.memory_limits.memory_limit_is_set()
    limit(None)
    assert not am.memory_limits.memory_limit_is_set()
    assert abs(am.memory_limit() - available / 2) < available / 8


@pytest.mark.parametrize("bad", [0, -1, 2**64, 1.5, "1GB", True])
def test_a_limit_that_is_not_a_positive_whole_number_of_bytes_is_refused(limit, bad):
    with pytest.raises(ValueError, match="memory limit must be"):
        limit(bad)
    assert not am.memory_limits.memory_limit_is_set()


def test_stitch_beyond_the_limit_is_refused_naming_the_keyframes_the_estimate_and_the_limit(limit):
    v, f = icosphere(1)
    frames = wobble(v, TIMES)
    limit(10_000)
    message = refusal(am.stitch, frames, f, TIMES)
    assert re.fullmatch(r"stitching 5 keyframes of 42 vertices and 80 faces \(960 simplices\) needs about "
                        r"[\d,]+ bytes \([\d.]+ KiB\), more than the memory limit of 10,000 bytes \(9.77 KiB\) "
                        r"\(set by animanifold.set_memory_limit\)", message), message
    estimate = int(re.search(r"needs about ([\d,]+) bytes", message).group(1).replace(",", ""))
    output = 5 * 42 * 4 * 8 + 960 * 4 * 4  # the manifold's points and tets alone
    assert output <= estimate <= 4 * output
    limit(estimate)
    assert len(am.stitch(frames, f, TIMES).simplices) == 960


def test_each_level_of_subdivision_is_judged_before_it_is_made(limit, manifold):
    limit(16 * MiB)
    assert len(am.subdivide(manifold, levels=1).simplices) == 8 * 960
    message = refusal(am.subdivide, manifold, levels=4)  # 3.9 million tets
    assert message.startswith("subdividing 960 simplices 4 times (3932160 simplices) needs about ")
    assert "more than the memory limit of 16,777,216 bytes (16 MiB)" in message
    # The call that would take the most, levels=40, is refused as readily (no overflow).
    assert "subdividing 960 simplices 40 times" in refusal(_core.subdivide_manifold, manifold.core_complex, 40)


def test_frame_subdivision_and_smoothed_slices_are_judged_too(limit, manifold):
    v, f = icosphere(1)
    limit(16 * MiB)
    assert len(am.subdivide_frame(v, f, levels=2).faces) == 80 * 16
    assert refusal(am.subdivide_frame, v, f, levels=7).startswith("subdividing a frame of 80 faces 7 times (1310720 faces)")
    assert refusal(manifold.slice, 0.5, smooth_levels=7).startswith("subdividing a frame of ")
    segments = np.array([[i, (i + 1) % 8] for i in range(8)], np.int32)
    circle = np.c_[np.cos(np.arange(8)), np.sin(np.arange(8))]
    assert "8 segments 16 times" in refusal(_core.subdivide_polyline, circle, segments, levels=16)


def test_refine_is_judged_by_the_simplices_its_splits_cut(limit, manifold):
    edges = np.unique(np.sort(manifold.simplices[:, [0, 1]], axis=1), axis=0)
    splits = (edges.astype(np.int32), np.full(edges.shape, 0.5))
    limit(4 * MiB)
    refined, r = am.refine(manifold, (splits[0][:10], splits[1][:10]))
    assert len(refined.points) == len(manifold.points) + 10
    limit(64 * 1024)
    message = refusal(am.refine, manifold, splits)
    assert message.startswith(f"refining 960 simplices with {len(edges)} splits (about ")


def test_the_command_line_reports_the_refusal_not_a_lack_of_memory(limit, tmp_path, capsys):
    v, f = icosphere(1)
    files = []
    for i, frame in enumerate(wobble(v, TIMES[:2])):
        files.append(str(tmp_path / f"k{i}.obj"))
        am.write_mesh(files[-1], frame, f)
    limit(1000)
    capsys.readouterr()
    assert main(["stitch", *files, "-o", str(tmp_path / "out.amf")]) != 0
    err = capsys.readouterr().err
    assert "stitching 2 keyframes of 42 vertices and 80 faces" in err and "memory limit of 1,000 bytes" in err
    assert not (tmp_path / "out.amf").exists()
