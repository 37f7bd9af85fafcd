"""Figures a bench script reports, also written as JSON (`--json PATH`) for
bench/run_all.py, which reads them instead of scraping the printed text."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_json_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", type=Path, default=None, metavar="PATH",
                        help="also write the figures as JSON to PATH (bench/run_all.py reads it)")


def write_json(path: Path | None, figures: dict) -> None:
    """Writes `figures` to `path` (nothing when `path` is None); numpy scalars become numbers."""
    if path is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(figures, indent=2, default=lambda value: value.item()))
