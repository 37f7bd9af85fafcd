"""Frame files with their surface attributes: OBJ (with `vt`, `vn` and an .mtl) and PLY
(ASCII, with normal and UV vertex properties and a material index per face).

The core's CGAL writer (meshio.write_mesh) writes positions and faces only; a frame
for another package (a compositor, a game engine, a renderer reading sequences) also
needs its UV map, its normals and which material each face uses. The text is built
here, deterministically (the same frame gives the same bytes in any process, so chunks
baked on different machines can be compared), and returned as bytes so a caller can
write it as it needs (atomically on a render farm).
"""

from __future__ import annotations

import os
from typing import Sequence

import numpy as np
from ._core import InputError

_NUMBER = "%.9g"  # float32-exact; positions stay within 1e-9 relative of the slice


def _rows(prefix: str, table: np.ndarray) -> str:
    if len(table) == 0:
        return ""
    fmt = (prefix + " " if prefix else "") + " ".join([_NUMBER] * table.shape[1])
    return "\n".join(fmt % tuple(row) for row in table.tolist()) + "\n"


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) unit normals of the triangles (zero for degenerate ones)."""
    v = np.asarray(vertices, dtype=np.float64)[np.asarray(faces)]
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.divide(n, length, out=np.zeros_like(n), where=length > 0)


def _check(vertices, faces, uv, normals, material_index):
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise InputError(f"vertices must be (k, 3), got shape {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise InputError(f"faces must be (l, 3) triangles, got shape {faces.shape}")
    if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise InputError(f"faces index vertices 0..{len(vertices) - 1}, found {faces.min()}..{faces.max()}")
    for name, table, width in (("uv", uv, 2), ("normals", normals, 3)):
        if table is not None and np.shape(table) != (len(vertices), width):
            raise InputError(f"{name} must be one row per vertex ({len(vertices)}, {width}), got {np.shape(table)}")
    if material_index is not None and np.shape(material_index) != (len(faces),):
        raise InputError(f"material_index must be one per face ({len(faces)},), got {np.shape(material_index)}")
    return vertices, faces


def obj_bytes(vertices, faces, uv=None, normals=None, material_index=None,
              material_names: Sequence[str] = (), mtl_name: str | None = None) -> bytes:
    """An OBJ file: `v`, `vt` (per vertex), `vn` (per vertex, or per face when `normals` is
    None: flat shading), `usemtl` wherever the face's material changes (faces keep their order)."""
    vertices, faces = _check(vertices, faces, uv, normals, material_index)
    flat = normals is None
    normal_rows = face_normals(vertices, faces) if flat else np.asarray(normals, dtype=np.float64)
    parts = ["# animanifold frame\n"]
    if mtl_name and material_names:
        parts.append(f"mtllib {mtl_name}\n")
    parts += [_rows("v", vertices), _rows("vt", np.asarray(uv, dtype=np.float64)) if uv is not None else "",
              _rows("vn", normal_rows), "s off\n" if flat else "s 1\n"]
    corner = faces + 1
    normal_index = np.repeat(np.arange(1, len(faces) + 1)[:, None], 3, axis=1) if flat else corner
    if uv is not None:
        triples = np.stack([corner, corner, normal_index], axis=2)
        fmt = "f %d/%d/%d %d/%d/%d %d/%d/%d"
    else:
        triples = np.stack([corner, normal_index], axis=2)
        fmt = "f %d//%d %d//%d %d//%d"
    materials = np.zeros(len(faces), np.int64) if material_index is None else np.asarray(material_index, np.int64)
    current = None
    for row, material in zip(triples.reshape(len(faces), -1).tolist(), materials.tolist()):
        if material_names and material != current:
            parts.append(f"usemtl {material_names[min(max(material, 0), len(material_names) - 1)]}\n")
            current = material
        parts.append(fmt % tuple(row) + "\n")
    return "".join(parts).encode()


def mtl_bytes(material_names: Sequence[str], colours: Sequence[Sequence[float]] | None = None) -> bytes:
    """An .mtl with one diffuse material per name (colours (r, g, b), default light grey)."""
    parts = ["# animanifold materials\n"]
    for i, name in enumerate(material_names):
        r, g, b = colours[i][:3] if colours is not None else (0.8, 0.8, 0.8)
        parts.append(f"\nnewmtl {name}\nKd {r:.6g} {g:.6g} {b:.6g}\nKa 0 0 0\nKs 0 0 0\nd 1\nillum 1\n")
    return "".join(parts).encode()


def ply_bytes(vertices, faces, uv=None, normals=None, material_index=None,
              material_names: Sequence[str] = ()) -> bytes:
    """An ASCII PLY: vertex x y z, nx ny nz (the face normals averaged when `normals` is
    None), s t when there are UVs; faces with a material_index property (names as comments)."""
    vertices, faces = _check(vertices, faces, uv, normals, material_index)
    if normals is None:
        normals = _vertex_normals(vertices, faces)
    columns = [vertices, np.asarray(normals, dtype=np.float64)]
    header = ["ply", "format ascii 1.0", "comment animanifold frame"]
    header += [f"comment material {i} {name}" for i, name in enumerate(material_names)]
    header += [f"element vertex {len(vertices)}"] + [f"property double {p}" for p in ("x", "y", "z", "nx", "ny", "nz")]
    if uv is not None:
        columns.append(np.asarray(uv, dtype=np.float64))
        header += ["property double s", "property double t"]
    header += [f"element face {len(faces)}", "property list uchar int vertex_indices", "property int material_index",
               "end_header"]
    materials = np.zeros(len(faces), np.int64) if material_index is None else np.asarray(material_index, np.int64)
    body = _rows("", np.concatenate(columns, axis=1))
    face_rows = np.concatenate([np.full((len(faces), 1), 3), faces, materials[:, None]], axis=1)
    face_text = "".join("%d %d %d %d %d\n" % tuple(row) for row in face_rows.tolist())
    return ("\n".join(header) + "\n" + body + face_text).encode()


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    sums = np.zeros_like(vertices)
    n = face_normals(vertices, faces)
    for k in range(3):
        np.add.at(sums, faces[:, k], n)
    length = np.linalg.norm(sums, axis=1, keepdims=True)
    return np.divide(sums, length, out=np.zeros_like(sums), where=length > 0)


def write_frame(path: str | os.PathLike, vertices, faces, uv=None, normals=None, material_index=None,
                material_names: Sequence[str] = (), mtl_name: str | None = None) -> None:
    """Writes a frame as OBJ or PLY (by the extension); an OBJ's .mtl is the caller's (mtl_bytes)."""
    extension = os.path.splitext(os.fspath(path))[1].lower()
    if extension == ".obj":
        data = obj_bytes(vertices, faces, uv, normals, material_index, material_names, mtl_name)
    elif extension == ".ply":
        data = ply_bytes(vertices, faces, uv, normals, material_index, material_names)
    else:
        raise InputError(f"cannot write {os.fspath(path)}: frames with attributes are .obj or .ply")
    with open(path, "wb") as f:
        f.write(data)
