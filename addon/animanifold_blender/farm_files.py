"""Files a render-farm task writes into a folder it shares with other tasks.

* Atomic: every file is written under a temporary name in the same folder
  (`.<name>.<pid>.tmp<ext>`, created with the umask like any file) and renamed over
  the final name, so a preempted or killed task leaves no half-written output, only a
  hidden temporary that the task's next run removes (`remove_stale`).
* Complete: a chunk's manifest (`<chunk>.done.json`, written last) lists every file the
  chunk wrote with its size and SHA-256; a re-run whose manifest still matches its files
  skips the chunk (`completed`), so a re-queued job costs nothing.

A test hook stands in for a preempted worker: with ANIMANIFOLD_FARM_KILL_AFTER_FILES=k the
process writes k files, half of the next one, and exits at once (os._exit) as a kill would.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os

KILL_AFTER_FILES = "ANIMANIFOLD_FARM_KILL_AFTER_FILES"
KILLED_EXIT_CODE = 137  # what a shell reports for a SIGKILLed process
_written = {"files": 0}


def temporary_path(path: str) -> str:
    folder, name = os.path.split(path)
    ext = os.path.splitext(name)[1]
    return os.path.join(folder, f".{name}.{os.getpid()}.tmp{ext}")


def write_bytes(path: str, data: bytes) -> None:
    """Writes `data` to `path` atomically (see the module)."""
    tmp = temporary_path(path)
    try:
        with open(tmp, "wb") as f:
            limit = os.environ.get(KILL_AFTER_FILES)
            if limit is not None and _written["files"] >= int(limit):
                f.write(data[: len(data) // 2])
                f.flush()
                os._exit(KILLED_EXIT_CODE)
            f.write(data)
        os.replace(tmp, path)
    except BaseException:  # a full disk, an interrupt: no temporary left (a kill leaves one: remove_stale)
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    _written["files"] += 1


def write_with(path: str, writer) -> None:
    """Runs `writer(temporary path)` (a Blender exporter or save) and renames its file to `path`;
    on a failure the temporary is removed."""
    tmp = temporary_path(path)
    try:
        writer(tmp)
        if not os.path.isfile(tmp):
            raise OSError(f"nothing was written to {tmp} (for {path})")
        os.replace(tmp, path)
    finally:
        for leftover in glob.glob(glob.escape(tmp) + "*"):  # Blender's own `<file>@` temporaries too
            os.unlink(leftover)


def remove_stale(folder: str, names) -> list[str]:
    """Removes the temporaries left for `names` (final file names in `folder`) by an earlier,
    interrupted run of the same task; the files removed."""
    removed = []
    for name in names:
        for path in glob.glob(os.path.join(glob.escape(folder), f".{glob.escape(name)}.*.tmp*")):
            os.unlink(path)
            removed.append(path)
    return removed


def digest(path: str) -> dict:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return {"bytes": os.path.getsize(path), "sha256": h.hexdigest()}


def write_manifest(path: str, description: dict, files: list[str]) -> None:
    """The chunk's manifest: `description` (what was asked) and every file's digest, by name."""
    entry = dict(description, files={os.path.basename(f): digest(f) for f in files})
    write_bytes(path, (json.dumps(entry, indent=1, sort_keys=True) + "\n").encode())


def read_manifest(path: str) -> dict | None:
    try:
        with open(path, encoding="utf-8") as f:
            entry = json.load(f)
    except (OSError, ValueError):
        return None
    return entry if isinstance(entry, dict) and isinstance(entry.get("files"), dict) else None


def completed(path: str, description: dict) -> bool:
    """True when the manifest at `path` was written for the same request and every file it
    lists is still there with the same size and digest."""
    entry = read_manifest(path)
    if entry is None or any(entry.get(k) != v for k, v in description.items()):
        return False
    folder = os.path.dirname(path)
    for name, expected in entry["files"].items():
        file = os.path.join(folder, name)
        if not os.path.isfile(file) or os.path.getsize(file) != expected.get("bytes") or digest(file) != expected:
            return False
    return True
