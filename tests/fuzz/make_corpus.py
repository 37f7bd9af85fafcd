"""Writes the cache fuzzer's seed corpus (tests/fuzz/corpus/cache): small valid caches of
each shape the format has (4D, 3D, with attributes, with a hole space, version 1 and 2,
padded and unpadded headers) and a few hostile headers. Run from the repository root."""

from __future__ import annotations

import hashlib
import json
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parents[1] / "python"), str(HERE.parent), str(HERE)]

import numpy as np  # noqa: E402

import animanifold as am  # noqa: E402
from cache_target import seed  # noqa: E402
from helpers.cache_files import assemble, split  # noqa: E402
from animanifold.procedural import icosphere  # noqa: E402


def caches(folder: Path) -> list[bytes]:
    v, f = icosphere(0)
    times = [0.0, 1.0]
    plain = am.stitch([v, v * 1.5], f, times)
    attributed = am.stitch([v, v * 1.5], f, times, vertex_attributes={"uv": v[:, :2]},
                           face_attributes={"material_index": np.arange(len(f)) % 2})
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    edges = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    contour = am.stitch([square, square * 2.0], edges, times)
    holed = am.AnimationManifold.from_arrays(plain.points, plain.simplices, metadata={"note": "holes"},
                                             hole_space=(v * 0.1, f))
    out = []
    for i, manifold in enumerate([plain, attributed, contour, holed]):
        out.append(am.save(manifold, folder / f"seed{i}.amf").read_bytes())
    return out


def hostile(valid: bytes) -> list[bytes]:
    version, header, payload = split(valid)
    unpadded = json.dumps(header).encode()
    return [
        assemble(version, unpadded + (b"" if len(unpadded) % 2 else b" "), payload),  # an older, unpadded file
        assemble(version, {**header, "points": 10**15}, payload),
        assemble(version, {**header, "metadata": [[[[]]]]}, payload),
        assemble(2, {**header, "arrays": [["hole_faces", "<i4", 1, 3]]}, payload),
        assemble(1, b"[" * 70 + b"]" * 70, payload),
    ]


def main() -> None:
    target = HERE / "corpus" / "cache"
    target.mkdir(parents=True, exist_ok=True)
    files = caches(target)
    for p in target.glob("seed*.amf"):
        p.unlink()
    for data in files + hostile(files[0]):
        for fixed in (True, False):
            entry = seed(data, fixed)
            (target / hashlib.sha1(entry).hexdigest()[:16]).write_bytes(entry)
    print(f"{len(os.listdir(target))} seeds in {target}")


if __name__ == "__main__":
    main()
