"""What every sub-command of the command line shares: the user's-mistake error, bounded
counts, and the progress lines a long call prints on stderr.

Long calls (subdivide, deform, skeleton, morph) report their steps through the core's one
interrupter (cpp/include/animanifold/progress.hpp); :class:`StepPrinter` turns those reports
into a few lines on stderr. Ctrl-C stops such a call at its next step: the core polls Python's
signals there, so the command ends with "interrupted" and exit code 130, having written
nothing.
"""

from __future__ import annotations

import argparse
import inspect
import sys
from typing import Callable, TextIO

from ._core import Error

PROG = "animanifold"
MAX_FRAMES = 100_000  # frames -n, morph --frames, demo --frames: one file each


class UserError(Error):
    """A problem with the user's input that the command line detects itself."""


def check_count(option: str, value: int, low: int, high: int = MAX_FRAMES) -> None:
    if not low <= value <= high:
        raise UserError(f"{option} must be from {low} to {high:,}, got {value:,}")


def command_help(run: Callable[[argparse.Namespace], int]) -> tuple[str, str]:
    """A sub-command's help, written once as the docstring of its `run`: the first line is its
    summary in ``animanifold --help``, the rest its description in ``animanifold NAME --help``
    (argparse folds the lines)."""
    summary, _, description = inspect.cleandoc(run.__doc__ or "").partition("\n")
    return summary, description.strip()


def add_command(commands, name: str, run: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """A sub-command's parser, dispatching to `run(args)` (its exit code), its help from `run`'s docstring."""
    summary, description = command_help(run)
    sub = commands.add_parser(name, help=summary, description=description)
    sub.set_defaults(run=run)
    return sub


def add_manifold_command(commands, name: str, run: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """A long call from one cache file to another: MANIFOLD -o OUTPUT, its steps on stderr unless -q."""
    sub = add_command(commands, name, run)
    sub.add_argument("manifold", help="cache file (.amf)")
    sub.add_argument("-o", "--output", required=True, help="the cache file to write (.amf)")
    sub.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    return sub


class StepPrinter:
    """A ``progress(step, fraction)`` callback that prints ``  <step> (<percent>)`` on
    `stream` when the step changes or the call is another tenth further, so a long loop
    reporting thousands of chunks prints a few lines. Never cancels (Ctrl-C does).

    The core's calls report a step as it starts; the morph reports each stage as it ends,
    which ``ended=True`` says: ``  <stage> done (<percent>)``. The "checks" step (the input's
    validation, which takes no time) is not printed, so an input refused there ends in the one
    error line the command line promises for bad input."""

    def __init__(self, quiet: bool = False, stream: TextIO | None = None, ended: bool = False):
        self.quiet = quiet
        self.stream = stream
        self.suffix = " done" if ended else ""
        self.printed: list[tuple[str, float]] = []

    def __call__(self, step: str, fraction: float) -> bool:
        tenth = int(fraction * 10)
        if step == "checks" and not self.suffix:
            return True
        if not self.printed or self.printed[-1][0] != step or tenth > int(self.printed[-1][1] * 10):
            self.printed.append((step, fraction))
            if not self.quiet:
                print(f"  {step}{self.suffix} ({fraction:.0%})", file=self.stream or sys.stderr)
        return True
