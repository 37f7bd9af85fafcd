"""Files of the project's shared test data (../shared/data/), for tests that take the
`shared_data` fixture (conftest.py): a missing file skips the test and names it."""

from __future__ import annotations

from pathlib import Path

import pytest


def shared_mesh(shared_data: Path, name: str) -> Path:
    """The path of meshes/<name> in the shared data, or a skip naming the missing file."""
    path = shared_data / "meshes" / name
    if not path.is_file():
        pytest.skip(f"{path} is not in the shared data folder")
    return path
