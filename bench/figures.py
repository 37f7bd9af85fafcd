"""Figures a bench script reports, also written as JSON (`--json PATH`) for
bench/run_all.py, which reads them instead of scraping the printed text."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", type=Path, default=None, metavar="PATH",
                        help="also write the figures as JSON to PATH (bench/run_all.py reads it)")


def bench_parser(doc: str, **sizes: int) -> argparse.ArgumentParser:
    """A bench script's parser: the first paragraph of its docstring `doc` as description,
    --json, and an integer option per keyword of `sizes`, the sizes of what it measures
    (``u=100`` is ``--u``, default 100; ``frames_per_gap`` is ``--frames-per-gap``)."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    for name, default in sizes.items():
        parser.add_argument("--" + name.replace("_", "-"), type=int, default=default, help=f"default {default}")
    add_json_option(parser)
    return parser


def write_json(path: Path | None, figures: dict) -> None:
    """Writes `figures` to `path` (nothing when `path` is None); numpy scalars become numbers."""
    if path is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(figures, indent=2, default=lambda value: value.item()))
