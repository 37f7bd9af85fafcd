"""Mesh files (OFF, OBJ, PLY, STL) through CGAL's IO in the core.

Writing is checked: the core writes a temporary file beside the target (atomic_file.py), which
is read back and compared with what was written before it replaces the target. CGAL's streams
report a failed final flush (a full disk) nowhere, so reading back is the check that the whole
mesh reached the file.
"""

from __future__ import annotations

import os

import numpy as np

from . import _core
from ._core import Error, InputError
from .atomic_file import replacing
from .indices import as_indices


EXTENSIONS = (".obj", ".ply", ".off", ".stl")


class MeshWriteError(Error, OSError):
    """A mesh file came out incomplete (a full disk, or a failing file system)."""


def read_mesh(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (k, 3) float64, triangles (l, 3) int32); polygons are fan-split."""
    vertices, faces, _ = _core.read_mesh(os.fspath(path))
    return vertices, faces


def write_mesh(path: str | os.PathLike, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Writes a triangle mesh; the format comes from the extension (.obj, .ply, .off, .stl)."""
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise InputError(f"vertices must be (k, 3), got shape {vertices.shape}")
    faces = as_indices(faces, "faces")
    if os.path.splitext(os.fspath(path))[1].lower() not in EXTENSIONS:
        raise InputError(f"cannot write mesh file {os.fspath(path)}: the extension must be one of {', '.join(EXTENSIONS)}")
    with replacing(path, keep_extension=True, many_per_folder=True) as temporary:
        try:
            _core.write_mesh(os.fspath(temporary), vertices, faces)
        except _core.FileError as e:
            raise MeshWriteError(str(e).replace(os.fspath(temporary), os.fspath(path))) from None
        if len(faces):  # a mesh without faces reads back as an error, whatever was written
            _check_written(path, temporary, vertices, faces)


def _check_written(path, temporary, vertices: np.ndarray, faces: np.ndarray) -> None:
    try:
        back_vertices, back_faces = read_mesh(temporary)
    except (Error, OSError, ValueError) as e:
        raise MeshWriteError(f"could not write mesh file {os.fspath(path)}: it does not read back ({e})") from None
    # STL keeps no shared vertices (the reader merges them by position): only the faces count
    same_vertices = os.fspath(path).lower().endswith(".stl") or len(back_vertices) == len(vertices)
    if len(back_faces) != len(faces) or not same_vertices:
        raise MeshWriteError(
            f"could not write mesh file {os.fspath(path)}: it reads back with {len(back_vertices)} vertices and "
            f"{len(back_faces)} faces of {len(vertices)} and {len(faces)} (is the disk full?)")
