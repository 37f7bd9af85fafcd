"""Replays the fuzzers' corpora on every run, through the fuzzers' own targets: the cache
reader's seeds and regressions (tests/fuzz/{corpus,regressions}/cache, cache_target.py) must
load or raise CacheError; the mesh reader's (…/mesh, mesh_target.py) must read or raise an
animanifold.Error, its regressions in a child process with a bounded address space; the array
entry points' (…/arrays, arrays_target.py) must return or raise an allowed refusal."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import animanifold as am

FUZZ = Path(__file__).resolve().parent / "fuzz"
sys.path.insert(0, str(FUZZ))

from cache_target import load_input  # noqa: E402
from mesh_target import read_input  # noqa: E402

INPUTS = sorted(p for folder in ("corpus", "regressions") for p in (FUZZ / folder / "cache").iterdir()
                if not p.name.endswith(".md"))


def test_the_corpora_are_there():
    assert len(list((FUZZ / "corpus" / "cache").iterdir())) >= 10


@pytest.mark.parametrize("entry", INPUTS, ids=[f"{p.parent.parent.name}/{p.name}" for p in INPUTS])
def test_an_input_loads_or_gives_a_cache_error(entry, tmp_path):
    load_input(entry.read_bytes(), str(tmp_path / "input.amf"))  # any other exception fails the test


def test_the_valid_seeds_load_so_the_fuzzer_starts_past_the_checks(tmp_path):
    loaded = [p for p in sorted((FUZZ / "corpus" / "cache").iterdir())
              if load_input(p.read_bytes(), str(tmp_path / "seed.amf")) is not None]
    assert len(loaded) >= 5  # four shapes of cache and an older unpadded file


MESH_SEEDS = sorted((FUZZ / "corpus" / "mesh").iterdir())
MESH_REGRESSIONS = sorted(p for p in (FUZZ / "regressions" / "mesh").iterdir() if not p.name.endswith(".md"))
# Findings whose fix is not in this tree yet; strict, so a fix makes the mark fail until it is removed.
OPEN: dict[str, str] = {}


@pytest.mark.parametrize("entry", MESH_SEEDS, ids=[p.name for p in MESH_SEEDS])
def test_a_mesh_seed_reads_or_gives_an_animanifold_error(entry, tmp_path):
    read_input(entry.read_bytes(), str(tmp_path))


def test_most_mesh_seeds_read(tmp_path):
    assert sum(read_input(p.read_bytes(), str(tmp_path)) is not None for p in MESH_SEEDS) >= 5


BOUNDED_CHILD = textwrap.dedent("""
    import resource, sys
    sys.path[:0] = sys.argv[3:]
    with open("/proc/self/statm") as statm:
        size = int(statm.read().split()[0]) * resource.getpagesize()
    limit = size + 512 * 2**20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    import animanifold as am
    from mesh_target import read_input
    try:
        read_input(open(sys.argv[1], "rb").read(), sys.argv[2])
    except am.Error as e:  # read_input lets no other error through; this one ran out of the bound
        sys.exit(f"refused only for lack of memory: {e}")
""")


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="measures the address space in /proc (Linux)")
@pytest.mark.parametrize("entry", [pytest.param(p, id=p.name, marks=[pytest.mark.xfail(reason=OPEN[p.name], strict=True)]
                                                if p.name in OPEN else []) for p in MESH_REGRESSIONS])
def test_a_mesh_regression_reads_or_gives_an_animanifold_error_in_bounded_memory(entry, tmp_path):
    paths = [str(FUZZ.parents[1] / "python"), str(FUZZ)]
    done = subprocess.run([sys.executable, "-c", BOUNDED_CHILD, str(entry), str(tmp_path), *paths],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]


ARRAY_INPUTS = sorted(p for folder in ("corpus", "regressions") for p in (FUZZ / folder / "arrays").iterdir()
                      if not p.name.endswith(".md"))


@pytest.mark.parametrize("entry", ARRAY_INPUTS, ids=[f"{p.parent.parent.name}/{p.name}" for p in ARRAY_INPUTS])
def test_an_array_input_gives_a_result_or_an_allowed_refusal(entry):
    pytest.importorskip("atheris", reason="the array inputs are decoded by atheris.FuzzedDataProvider (pip install atheris)")
    from arrays_target import run_input

    assert run_input(entry.read_bytes()) is not None  # anything but an allowed refusal propagates and fails


def test_the_array_seeds_reach_every_entry_point_and_most_get_past_the_checks():
    pytest.importorskip("atheris", reason="the array inputs are decoded by atheris.FuzzedDataProvider (pip install atheris)")
    import atheris
    from arrays_target import TARGETS

    seeds = sorted((FUZZ / "corpus" / "arrays").iterdir())
    assert {TARGETS[p.read_bytes()[0] % len(TARGETS)] for p in seeds} == set(TARGETS)
    passed = 0
    for p in seeds:
        data = p.read_bytes()
        try:
            TARGETS[data[0] % len(TARGETS)](atheris.FuzzedDataProvider(data[1:]))
            passed += 1
        except (am.Error, ValueError, TypeError):
            pass
    assert passed >= len(seeds) // 2
