"""The mesh reader's fuzz target (animanifold.read_mesh, CGAL's OBJ/OFF/PLY/STL readers in the
core), shared by fuzz_mesh.py and the pytest replay. An input's first byte picks the file's
extension (its value modulo 4: .obj, .off, .ply, .stl), the rest is the file. The only allowed
outcomes are a mesh or an animanifold.Error (FileError names the file); anything else — another
exception, a crash, a hang, an allocation out of proportion to the file — is a finding."""

from __future__ import annotations

import os

import animanifold as am

EXTENSIONS = (".obj", ".off", ".ply", ".stl")


def read_input(data: bytes, folder: str):
    """(vertices, faces) of the input's file, or None when the reader refuses it with animanifold.Error
    (re-raised when the refusal is a failed allocation: under a memory limit, that is the finding)."""
    if not data:
        return None
    path = os.path.join(folder, f"input{EXTENSIONS[data[0] % 4]}")
    with open(path, "wb") as f:
        f.write(data[1:])
    try:
        return am.read_mesh(path)
    except am.Error as e:
        if "bad_alloc" in str(e):  # the reader caught its own failed allocation: out of proportion to the file
            raise
        return None


def seed(extension: str, text: bytes) -> bytes:
    return bytes([EXTENSIONS.index(extension)]) + text
