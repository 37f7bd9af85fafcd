"""Replacing an output file atomically and safely: the cache's and the mesh writers' one way to write.

:func:`replacing` yields a temporary file beside the target; when the block ends without an
exception the temporary is flushed to disk, given the target's mode and renamed over it, and
the directory is flushed so the rename itself survives a crash. A crash at any point leaves
either the old file or the new one under the target's name, never a mixture.

What sits at the output path is respected:

* a symbolic link is followed: its target is replaced and the link kept;
* anything that exists and is not a regular file (a device node such as /dev/null, a FIFO,
  a directory) is refused with :class:`OutputPathError`: renaming over it would replace it;
* the new file keeps the old file's permission bits, or gets ``0o666 & ~umask`` when new
  (the temporary file's own 0o600 would otherwise stick).

Stale temporaries. A writer killed mid-save leaves its temporary behind. Temporaries are
named ``.<target name>.<host>.<pid>.<random>.tmp`` (``.tmp<extension>`` for mesh files); before each save, the ones beside the
target are removed when their writer is gone — same host and no process with that pid — or,
whatever their name, when untouched for :data:`STALE_SECONDS` (a live writer touches its file
as it writes; another host's writer cannot be asked). A pid reused by an unrelated process
only delays the removal until that age. Writers of many files into one folder (mesh frames)
search it once per process instead, removing this host's temporaries of any target there
whose writer is gone.
"""

from __future__ import annotations

import contextlib
import os
import re
import socket
import stat
import tempfile
import time
from pathlib import Path
from typing import Iterator

from ._core import Error

STALE_SECONDS = 3600.0
_CLEANED_FOLDERS: set[Path] = set()  # folders a many-file writer has cleaned in this process


class OutputPathError(Error, OSError):
    """The output path names something that must not be replaced (a device, FIFO or directory)."""


@contextlib.contextmanager
def replacing(path: str | os.PathLike, keep_extension: bool = False, many_per_folder: bool = False) -> Iterator[Path]:
    """Yields a temporary path to write the new contents to; replaces `path` with it on success.
    With `keep_extension` the temporary ends in the target's extension too (``.tmp.obj``), for
    writers that pick the format from it. With `many_per_folder` (a writer of many files, such
    as a folder of frames) the folder is searched for stale temporaries once per process, for
    every target, instead of once per file for this one (which would cost n² for n files).

    Throws: OutputPathError for a target that is not a regular file; OSError from the file
    system (a full disk at flush time included), with the temporary removed.
    """
    target = output_target(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    if not many_per_folder:
        remove_stale_temporaries(target)
    elif target.parent not in _CLEANED_FOLDERS:
        remove_stale_temporaries(target, every_target=True)
        _CLEANED_FOLDERS.add(target.parent)
    mode = _mode_for(target)
    suffix = ".tmp" + (target.suffix if keep_extension else "")
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.{_host()}.{os.getpid()}.", suffix=suffix, dir=target.parent)
    os.close(fd)
    temporary = Path(name)
    try:
        yield temporary
        _flush_file(temporary, mode)
        os.replace(temporary, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)
        raise
    _flush_directory(target.parent)


def output_target(path: str | os.PathLike) -> Path:
    """The file a write to `path` must replace: symbolic links followed; refused unless it is a
    regular file or does not exist yet."""
    target = Path(os.path.realpath(os.fspath(path)))
    try:
        info = os.stat(target)
    except FileNotFoundError:
        return target
    if not stat.S_ISREG(info.st_mode):
        raise OutputPathError(f"refusing to write {os.fspath(path)}: it is {describe_mode(info.st_mode)}, "
                              "not a regular file")
    return target


def describe_mode(mode: int) -> str:
    kinds = [(stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
             (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISSOCK, "a socket")]
    return next((text for test, text in kinds if test(mode)), "a special file")


def remove_stale_temporaries(target: Path, every_target: bool = False) -> list[Path]:
    """Removes temporaries of earlier saves of `target` whose writer is gone (rule in the module
    doc); with `every_target`, also this host's temporaries of any other file in its folder whose
    writer is gone. Returns what it removed."""
    removed = []
    prefix = f".{target.name}."
    suffixes = (".tmp", ".tmp" + target.suffix)
    others = _this_hosts_temporary() if every_target else None
    with contextlib.suppress(OSError), os.scandir(target.parent) as entries:
        for entry in entries:
            suffix = next((s for s in suffixes if entry.name.endswith(s)), None)
            if entry.name.startswith(prefix) and suffix is not None:
                stale = lambda mtime: _is_stale(entry.name[len(prefix):-len(suffix)], mtime)
            elif others is not None and (match := others.match(entry.name)):
                stale = lambda mtime: not _process_exists(int(match["pid"]))
            else:
                continue
            with contextlib.suppress(OSError):
                info = entry.stat(follow_symlinks=False)
                if stat.S_ISREG(info.st_mode) and stale(info.st_mtime):
                    os.unlink(entry.path)
                    removed.append(Path(entry.path))
    return removed


def _this_hosts_temporary() -> re.Pattern:
    """A temporary this module names on this host, whatever its target: .<name>.<host>.<pid>.<random>.tmp[.ext]."""
    return re.compile(rf"^\..+\.{re.escape(_host())}\.(?P<pid>\d+)\.\w+\.tmp(\.\w+)?$")


def _is_stale(middle: str, mtime: float) -> bool:
    if time.time() - mtime > STALE_SECONDS:
        return True
    parts = middle.rsplit(".", 2)  # host (may hold dots), pid, mkstemp's random part
    if len(parts) != 3 or parts[0] != _host() or not parts[1].isdigit():
        return False
    return not _process_exists(int(parts[1]))


def _process_exists(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True  # someone else's process (or a pid no process can have): leave it to the age rule
    return True


def _host() -> str:
    return socket.gethostname().replace("/", "_") or "localhost"


def _mode_for(target: Path) -> int:
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        return 0o666 & ~current_umask()


def current_umask() -> int:
    """The process's umask, read without changing it (os.umask would, racing other threads)."""
    with contextlib.suppress(OSError, ValueError), open("/proc/self/status") as status:
        for line in status:
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o022)  # no /proc: the set-and-restore fallback
    os.umask(mask)
    return mask


def _flush_file(path: Path, mode: int) -> None:
    os.chmod(path, mode)
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _flush_directory(folder: Path) -> None:
    if not hasattr(os, "O_DIRECTORY"):  # Windows: directories cannot be opened, and NTFS journals renames
        return
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
