"""A batch of morphs, as a render farm runs it: a list of (source, target, frames, method)
pairs, each morphed into a folder of its own with a validity report, and a summary table.

The list is JSON (a list of objects) or CSV with a header, each pair having `source`, `target`,
`frames` and `method` (and optionally `name`, and `field_resolution` for the field method's
lattice); relative paths are relative to the list's folder.
A pair's results go to OUT/<name>/ (morph.amf, frames/, contact_sheet.png) and its report,
written last, to OUT/<name>/report.json. Every file is written under a temporary name and
renamed, so a preempted task leaves no half-written file, and a pair whose report is there with
all its files is not morphed again. cli_farm.py puts these on the command line.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import time
from pathlib import Path

import numpy as np

from ._core import Error
from .cache import save
from .contact_sheet import render_contact_sheet
from .meshio import read_mesh
from .mesh_export import obj_bytes, ply_bytes
from .morph_pipeline import METHODS, morph

REPORT = "report.json"
SUMMARY = "summary.md"


class PairListError(Error, ValueError):
    """A pair list that cannot be read (the message names the file, the pair and the field)."""


def write_atomic(path: Path, data: bytes) -> None:
    """`data` to `path` under a temporary name in the same folder, then renamed (umask honoured)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _pair_name(row: dict, index: int) -> str:
    name = row.get("name") or f"{index:03d}_{Path(row['source']).stem}_to_{Path(row['target']).stem}"
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", str(name))


def read_pairs(path: str | os.PathLike) -> list[dict]:
    """The pairs of a JSON or CSV list, checked: (name, source, target, frames, method) each."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise PairListError(f"cannot read the pair list {path}: {e.strerror or e}") from e
    try:
        rows = json.loads(text) if path.suffix.lower() == ".json" else list(csv.DictReader(text.splitlines()))
    except ValueError as e:
        raise PairListError(f"{path} is not a valid {path.suffix.lstrip('.').upper() or 'CSV'} pair list: {e}") from e
    if not isinstance(rows, list) or not rows:
        raise PairListError(f"{path} holds no pairs (a list of source, target, frames, method)")
    return [_checked_pair(path, row, i) for i, row in enumerate(rows, start=1)]


def _checked_pair(path: Path, row, index: int) -> dict:
    where = f"{path}, pair {index}"
    if not isinstance(row, dict):
        raise PairListError(f"{where}: expected an object with source, target, frames, method; got {row!r}")
    missing = [k for k in ("source", "target") if not row.get(k)]
    if missing:
        raise PairListError(f"{where}: no {' or '.join(missing)}")
    try:
        frames = int(row.get("frames") or 8)
    except (TypeError, ValueError):
        raise PairListError(f"{where}: frames must be a whole number, got {row.get('frames')!r}") from None
    if frames < 2:
        raise PairListError(f"{where}: frames must be at least 2, got {frames}")
    method = str(row.get("method") or METHODS[0])
    if method not in METHODS:
        raise PairListError(f"{where}: unknown method {method!r} (choose from {', '.join(METHODS)})")
    resolve = lambda p: str(p if os.path.isabs(p) else (path.parent / p))  # noqa: E731
    pair = {"name": _pair_name(row, index), "source": resolve(row["source"]), "target": resolve(row["target"]),
            "frames": frames, "method": method}
    resolution = _field_resolution(row, method, where)
    if resolution is not None:  # absent from pairs without it, so their finished reports still match
        pair["field_resolution"] = resolution
    return pair


def _field_resolution(row: dict, method: str, where: str) -> float | None:
    """The pair's optional `field_resolution` (an empty CSV cell is no value), checked here so that
    a bad list fails before the farm starts rather than pair by pair."""
    value = row.get("field_resolution")
    if value is None or value == "":
        return None
    if method != "field":
        raise PairListError(f"{where}: field_resolution applies to the field method only, not {method!r}")
    try:
        resolution = float(value) if not isinstance(value, bool) else math.nan
    except (TypeError, ValueError):
        resolution = math.nan
    if not resolution >= 2 or not math.isfinite(resolution):
        raise PairListError(f"{where}: field_resolution must be a number of lattice cells >= 2, got {value!r}")
    return resolution


def json_safe(value):
    """Plain JSON values (numpy scalars and arrays, tuples) for a report."""
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [json_safe(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _report_complete(folder: Path, pair: dict) -> bool:
    try:
        report = json.loads((folder / REPORT).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return report.get("pair") == pair and all((folder / f).is_file() for f in report.get("files", []))


def _morph_pair(pair: dict, folder: Path, fmt: str) -> dict:
    """Morphs one pair into `folder`; the report (validity, timings, files)."""
    seconds, files = {}, []
    start = time.perf_counter()
    options = {"field_resolution": pair["field_resolution"]} if "field_resolution" in pair else {}
    manifold = morph(read_mesh(pair["source"]), read_mesh(pair["target"]), method=pair["method"], **options)
    seconds["morph"] = time.perf_counter() - start
    save(manifold, folder / "morph.amf")
    files.append("morph.amf")
    start = time.perf_counter()
    (folder / "frames").mkdir(exist_ok=True)
    times = np.linspace(*manifold.time_range, pair["frames"])
    slices = [manifold.slice(float(t)) for t in times]
    for i, s in enumerate(slices):
        name = f"frames/frame_{i:04d}.{fmt}"
        write_atomic(folder / name, frame_bytes(s, fmt))
        files.append(name)
    seconds["frames"] = time.perf_counter() - start
    start = time.perf_counter()
    sheet = folder / "contact_sheet.png"
    tmp = sheet.with_name(f".{sheet.name}.{os.getpid()}.tmp.png")
    render_contact_sheet(slices[:: max(1, len(slices) // 8)][:8], tmp, manifold.bounding_box)
    os.replace(tmp, sheet)
    files.append(sheet.name)
    seconds["contact_sheet"] = time.perf_counter() - start
    return {"status": "ok", "tets": int(len(manifold.simplices)),
            "is_oriented_manifold": bool(manifold.check().is_oriented_manifold),
            "validity": json_safe(manifold.validity), "seconds": seconds, "files": files}


def frame_bytes(s, fmt: str) -> bytes:
    uv = s.vertex_attributes.get("uv")
    uv = uv if uv is not None and np.shape(uv) == (len(s.vertices), 2) else None
    materials = s.face_attributes.get("material_index")
    names = [f"material_{i}" for i in range(int(materials.max()) + 1)] if materials is not None and len(materials) else []
    args = (s.vertices, s.faces, uv, s.normals if len(s.normals) == len(s.vertices) else None, materials, names)
    return obj_bytes(*args) if fmt == "obj" else ply_bytes(*args)


def summary_rows(pairs: list[dict], output: Path) -> list[dict]:
    """One row per pair from its report (status `missing` when the report is not there)."""
    rows = []
    for pair in pairs:
        try:
            report = json.loads((output / pair["name"] / REPORT).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            report = {"status": "missing"}
        v = report.get("validity", {})
        rows.append({
            "pair": pair["name"], "method": _method_cell(pair), "status": report["status"],
            "ends_reproduced": v.get("ends_reproduced"), "inverted_simplices": v.get("inverted_simplices"),
            "frames_cross_themselves": v.get("frames_cross_themselves"),
            "bubble_frames": len(v.get("bubble_frames") or []) if v else None,
            "is_oriented_manifold": report.get("is_oriented_manifold"), "tets": report.get("tets"),
            "morph_seconds": report.get("seconds", {}).get("morph"), "total_seconds": report.get("total_seconds"),
            "contact_sheet": f"{pair['name']}/contact_sheet.png" if report["status"] == "ok" else None,
            "error": report.get("error"),
        })
    return rows


def _method_cell(pair: dict) -> str:
    resolution = pair.get("field_resolution")
    return pair["method"] if resolution is None else f"{pair['method']} ({resolution:g} cells)"


COLUMNS = ("pair", "method", "status", "ends_reproduced", "inverted_simplices", "frames_cross_themselves",
           "bubble_frames", "is_oriented_manifold", "tets", "morph_seconds", "total_seconds", "contact_sheet")


def _cell(key: str, value) -> str:
    if value is None:
        return "–"
    if key == "contact_sheet":
        return f"![{value}]({value})"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.2f}"
    return str(value).replace("|", "\\|")


def summary_markdown(rows: list[dict]) -> str:
    ok = sum(r["status"] == "ok" for r in rows)
    lines = [f"# Morph batch: {ok} of {len(rows)} pairs morphed", "",
             "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_cell(k, r[k]) for k in COLUMNS) + " |" for r in rows]
    errors = [r for r in rows if r["error"]]
    if errors:
        lines += ["", "## Failures", ""] + [f"- **{r['pair']}**: {r['error']}" for r in errors]
    return "\n".join(lines) + "\n"


def morph_pair(pair: dict, output: Path, fmt: str = "obj") -> dict | None:
    """Morphs `pair` into output/<name>/ (see the module); its report, or None when a complete
    report was there already. A morph the geometry refuses is recorded as `failed`."""
    folder = Path(output) / pair["name"]
    if _report_complete(folder, pair):
        return None
    folder.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    try:
        report = _morph_pair(pair, folder, fmt)
    except (Error, ValueError, OSError) as error:  # the pair's result: shown in the summary
        reason = " ".join(str(error).split()) or type(error).__name__
        inputs = f"{os.path.basename(pair['source'])} -> {os.path.basename(pair['target'])}"
        report = {"status": "failed", "error": f"{inputs}: {reason}", "files": []}
    report = dict(report, pair=pair, total_seconds=time.perf_counter() - start)
    write_atomic(folder / REPORT, (json.dumps(report, indent=1, sort_keys=True) + "\n").encode())
    return report
