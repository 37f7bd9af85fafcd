"""Replays the cache fuzzer's corpora on every run: its seeds (tests/fuzz/corpus/cache) and
every input a fuzzing run found (tests/fuzz/regressions/cache), through the same target
(tests/fuzz/cache_target.py). Each must load or raise CacheError; the valid seeds must load."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

FUZZ = Path(__file__).resolve().parent / "fuzz"
sys.path.insert(0, str(FUZZ))

from cache_target import load_input  # noqa: E402

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
