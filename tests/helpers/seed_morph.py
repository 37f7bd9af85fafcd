"""am.morph with the seed's skeleton method (§8.6) unless a test names another method: for the
tests of the seed's methods, since am.morph takes the field method for surfaces by default
(tests/test_morph_field.py tests that one)."""

from __future__ import annotations

import functools

import animanifold as am

skeleton_morph = functools.partial(am.morph, method="skeleton")
