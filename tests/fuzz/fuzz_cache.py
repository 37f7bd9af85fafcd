"""Fuzzes the cache reader (animanifold.load) with atheris (libFuzzer for Python).

Run from the repository root, for example::

    python3 tests/fuzz/fuzz_cache.py tests/fuzz/corpus/cache -atheris_runs=1000000 -rss_limit_mb=1024
    python3 tests/fuzz/fuzz_cache.py tests/fuzz/corpus/cache -max_total_time=60    # CI's budget

Any input that raises something other than CacheError, exceeds the memory limit or runs past
-timeout is written by libFuzzer as crash-*/oom-*/timeout-*; copy it into
tests/fuzz/regressions/cache/ (named for what it found) so pytest replays it on every run.
Seeds: ``python3 tests/fuzz/make_corpus.py``. See tests/fuzz/README.md.
"""

from __future__ import annotations

import os
import sys

sys.path[:0] = [os.path.join(os.path.dirname(__file__), "..", "..", "python"), os.path.dirname(__file__)]

import atheris  # noqa: E402

with atheris.instrument_imports(include=["animanifold"]):
    import animanifold  # noqa: E402,F401

from cache_target import load_input, scratch_path  # noqa: E402

PATH = scratch_path()


def test_one_input(data: bytes) -> None:
    load_input(data, PATH)


if __name__ == "__main__":
    atheris.Setup(sys.argv, test_one_input)
    try:
        atheris.Fuzz()
    finally:
        if os.path.exists(PATH):
            os.unlink(PATH)
