"""The names of the core's enumerations, as users type them.

Each choice users make (Laplacian method, boundary rule, manifold and frame
subdivision schemes, refine order, skeleton side, wrap shape, morph method) is declared once, as a
C++ ``enum class`` with its table of names, and bound as a ``_core`` enum whose
members are those names. The option checks, the CLI's ``choices=`` and the
add-on's EnumProperty items all come from :func:`names`, so no other list of
them exists.
"""

from __future__ import annotations
from ._core import InputError


def names(enum) -> tuple[str, ...]:
    """The member names of a bound ``_core`` enum, in the order the core lists them
    (the default first where there is one)."""
    return tuple(enum.__members__)


def checked(value, enum, what: str) -> str:
    """The name of `value`, a member of `enum` or one of its names.

    Raises ValueError naming the value and the choices otherwise.
    """
    if isinstance(value, enum):
        return value.name
    choices = names(enum)
    if not isinstance(value, str) or value not in choices:
        raise InputError(f"unknown {what} {value!r}: use one of {', '.join(choices)}")
    return value
