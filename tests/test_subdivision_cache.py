"""The subdivisions kept per loaded manifold (subdivision_cache): computed once per settings,
stale with a new file version, failures remembered until a settings change, errors worded
for the object."""

from __future__ import annotations

import pytest

import animanifold as am
from animanifold import procedural, subdivision
from animanifold.subdivision_cache import SmoothingError, SubdivisionCache


def _manifold():
    v, f = procedural.icosphere(0)
    return am.stitch([v, 1.5 * v], f, [1.0, 5.0])


@pytest.fixture()
def calls(monkeypatch):
    """Counts the subdivisions the cache computes; `calls.fail` makes the next ones raise it."""
    real = subdivision.subdivide

    class Calls:
        n = 0
        fail: BaseException | None = None

    def counted(*args, **kwargs):
        Calls.n += 1
        if Calls.fail is not None:
            raise Calls.fail
        return real(*args, **kwargs)

    monkeypatch.setattr(subdivision, "subdivide", counted)
    return Calls


def test_each_subdivision_is_computed_once_per_settings_and_file_version(calls):
    base, cache = _manifold(), SubdivisionCache()
    one = cache.subdivided("a.amf", base, 1, True, "obj")
    assert one.simplices.shape[0] == am.subdivided_simplex_count(base, 1)
    assert cache.subdivided("a.amf", base, 1, True, "obj") is one and calls.n == 1
    assert cache.subdivided("a.amf", base, 1, False, "obj") is not one and calls.n == 2
    assert sorted(cache.kept("a.amf")) == [(1, False), (1, True)] and len(cache) == 1
    reloaded = _manifold()  # a new version of the file: what was kept is stale
    assert cache.subdivided("a.amf", reloaded, 1, True, "obj") is not one and calls.n == 3
    assert cache.kept("a.amf") == [(1, True)]
    cache.prune({("a.amf", 1, True)})
    assert cache.kept("a.amf") == [(1, True)]
    cache.prune(set())  # no object asks for it any more
    assert cache.kept("a.amf") == [] and len(cache) == 0


def test_a_failure_is_remembered_until_a_prune(calls):
    base, cache = _manifold(), SubdivisionCache()
    calls.fail = MemoryError()
    for _ in range(2):  # the second is the remembered failure: nothing computed again
        with pytest.raises(SmoothingError, match=r"out of memory subdividing 'obj' 2 levels \(.* tets\): use fewer levels"):
            cache.subdivided("a.amf", base, 2, True, "obj")
    assert calls.n == 1 and isinstance(SmoothingError("x"), am.Error)
    calls.fail = None
    cache.prune({("a.amf", 2, True)})  # a settings change forgets the failures
    assert cache.subdivided("a.amf", base, 2, True, "obj") is not None and calls.n == 2


def test_failures_are_worded_for_the_object(calls):
    base, cache = _manifold(), SubdivisionCache()
    calls.fail = ValueError("bad input")
    with pytest.raises(SmoothingError, match="cannot subdivide 'obj': bad input"):
        cache.subdivided("a.amf", base, 1, True, "obj")
    calls.fail = am.MemoryLimitError("over the limit")
    with pytest.raises(SmoothingError, match="1 subdivision levels of 'obj': over the limit; use fewer levels"):
        cache.subdivided("a.amf", base, 1, False, "obj")


def test_a_cancelled_subdivision_is_passed_on_and_not_remembered(calls):
    base, cache = _manifold(), SubdivisionCache()
    calls.fail = am.Cancelled("stopped")
    with pytest.raises(am.Cancelled):
        cache.subdivided("a.amf", base, 1, True, "obj")
    calls.fail = None
    assert cache.subdivided("a.amf", base, 1, True, "obj") is not None and calls.n == 2
