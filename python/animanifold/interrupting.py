"""The core's interrupter (cpp/include/animanifold/progress.hpp) for the package's own long
calls, which chain several core calls: laplacian_deform (factorise, deform, restore),
regularise (a solve per refinement round) and deform.

Each core call or step gets a span of the caller's [0, 1], so the fractions the caller
sees only grow across the whole chain; every step calls ``progress(step, fraction)``
and then polls ``interrupted()``, as the core's Interrupter::step does, and False from
the one or True from the other raises :class:`animanifold.Cancelled`.
"""

from __future__ import annotations

from typing import Callable

from . import _core

ProgressCallback = Callable[[str, float], bool]
InterruptedCallback = Callable[[], bool]


class Span:
    """The part [low, high] of a call's progress, for one of its steps or sub-calls."""

    def __init__(self, progress: ProgressCallback | None = None, interrupted: InterruptedCallback | None = None,
                 low: float = 0.0, high: float = 1.0):
        self.progress, self.interrupted = progress, interrupted
        self.low, self.high = float(low), float(high)

    def _at(self, fraction: float) -> float:
        return self.low + (self.high - self.low) * min(max(float(fraction), 0.0), 1.0)

    def part(self, low: float, high: float) -> "Span":
        """The fractions [low, high] of this span, as a span of its own."""
        return Span(self.progress, self.interrupted, self._at(low), self._at(high))

    def step(self, name: str, fraction: float) -> None:
        """Reports step `name` at `fraction` of this span. Raises Cancelled when the caller says stop."""
        if self.progress is not None and not self.progress(name, self._at(fraction)):
            raise _core.Cancelled(f"cancelled at the {name} step")
        if self.interrupted is not None and self.interrupted():
            raise _core.Cancelled(f"cancelled at the {name} step")

    def core_progress(self) -> ProgressCallback | None:
        """The `progress` of a core call covering this span (None when the caller gave none)."""
        if self.progress is None:
            return None
        return lambda name, fraction: self.progress(name, self._at(fraction))
