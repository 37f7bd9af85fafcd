"""Options objects that may also be given field by field: ``subdivide(m, options=SubdivideOptions(
scheme="linear"))`` and ``subdivide(m, scheme="linear")`` are the same call."""

from __future__ import annotations

from typing import TypeVar
from ._core import InputError

T = TypeVar("T")


def options_from(cls: type[T], options: T | None, **keywords) -> T:
    """`options`, or a `cls` made of the keywords that were given (not None).

    Raises ValueError when both are given (which would win is not obvious) or when
    `options` is not a `cls`; the dataclass's own checks word a bad field."""
    given = {name: value for name, value in keywords.items() if value is not None}
    if options is None:
        return cls(**given)
    if not isinstance(options, cls):
        raise InputError(f"options must be a {cls.__name__}, got {options!r}")
    if given:
        raise InputError(f"give options or the keywords {', '.join(sorted(given))}, not both")
    return options
