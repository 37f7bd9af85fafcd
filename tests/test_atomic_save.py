"""Saving a cache replaces only what it should: regular files (symbolic links followed), with
their mode kept or the umask honoured, never a device, FIFO or directory; a writer killed at
any point leaves the old or the new file under the final name, and its temporary is removed by
the next save."""

from __future__ import annotations

import os
import socket
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold import atomic_file
from helpers.cache_files import small_manifold
from helpers.keyframes import wobble
from helpers.shapes import icosphere

PACKAGE = Path(am.__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def manifold():
    return small_manifold()


def test_a_fifo_or_a_directory_at_the_path_is_refused_and_left_alone(manifold, tmp_path):
    os.mkfifo(tmp_path / "pipe.amf")
    (tmp_path / "folder.amf").mkdir()
    for name, kind in [("pipe.amf", "FIFO"), ("folder.amf", "directory")]:
        with pytest.raises(atomic_file.OutputPathError, match=f"{name}: it is .*{kind}"):
            am.save(manifold, tmp_path / name)
    assert stat.S_ISFIFO(os.lstat(tmp_path / "pipe.amf").st_mode)
    assert (tmp_path / "folder.amf").is_dir() and not any((tmp_path / "folder.amf").iterdir())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder.amf", "pipe.amf"]


def test_a_symbolic_link_is_followed_and_kept(manifold, tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "real" / "a.amf").write_bytes(b"old")
    (tmp_path / "link.amf").symlink_to(tmp_path / "real" / "a.amf")
    am.save(manifold, tmp_path / "link.amf")
    assert (tmp_path / "link.amf").is_symlink()
    assert am.load(tmp_path / "real" / "a.amf").points.tobytes() == manifold.points.tobytes()


def test_the_old_mode_is_kept_and_a_new_file_honours_the_umask(manifold, tmp_path):
    old = tmp_path / "old.amf"
    old.write_bytes(b"old")
    old.chmod(0o640)
    am.save(manifold, old)
    assert stat.S_IMODE(old.stat().st_mode) == 0o640
    mask = os.umask(0o027)
    try:
        am.save(manifold, tmp_path / "new.amf")
    finally:
        os.umask(mask)
    assert stat.S_IMODE((tmp_path / "new.amf").stat().st_mode) == 0o640


def test_the_directory_is_flushed_after_the_rename(manifold, tmp_path, monkeypatch):
    events = []
    real_fsync, real_replace = os.fsync, os.replace
    monkeypatch.setattr(atomic_file.os, "replace", lambda a, b: events.append("rename") or real_replace(a, b))
    monkeypatch.setattr(atomic_file.os, "fsync", lambda fd: events.append(
        "directory" if stat.S_ISDIR(os.fstat(fd).st_mode) else "file") or real_fsync(fd))
    am.save(manifold, tmp_path / "a.amf")
    assert events[-2:] == ["rename", "directory"]


def test_stale_temporaries_are_removed_and_live_ones_kept(manifold, tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    host = socket.gethostname()
    names = {
        "dead writer": f".a.amf.{host}.{int(dead.stdout)}.abcd1234.tmp",
        "live writer": f".a.amf.{host}.{os.getpid()}.abcd1234.tmp",
        "old unnamed": ".a.amf.x7k2p9q1.tmp",
        "fresh unnamed": ".a.amf.q1w2e3r4.tmp",
        "other file's": f".b.amf.{host}.{int(dead.stdout)}.abcd1234.tmp",
    }
    for name in names.values():
        (tmp_path / name).write_bytes(b"partial")
    hours_ago = time.time() - 2 * atomic_file.STALE_SECONDS
    os.utime(tmp_path / names["old unnamed"], (hours_ago, hours_ago))
    am.save(manifold, tmp_path / "a.amf")
    left = {p.name for p in tmp_path.iterdir()}
    assert left == {"a.amf", names["live writer"], names["fresh unnamed"], names["other file's"]}


def test_a_writer_of_many_meshes_searches_their_folder_once(tmp_path, monkeypatch):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = tmp_path / f".frame_0007.obj.{socket.gethostname()}.{int(dead.stdout)}.abcd1234.tmp.obj"
    stale.write_text("v 0 0 0\n")
    scans = []
    real_scandir = os.scandir
    monkeypatch.setattr(atomic_file.os, "scandir", lambda folder: scans.append(folder) or real_scandir(folder))
    monkeypatch.setattr(atomic_file, "_CLEANED_FOLDERS", set())
    v, f = icosphere(0)
    for i in range(5):
        am.write_mesh(tmp_path / f"frame_{i:04d}.obj", v, f)
    assert len(scans) == 1 and not stale.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"frame_{i:04d}.obj" for i in range(5)]


CHILD = textwrap.dedent("""
    import sys, os, zlib, types
    import animanifold as am
    from animanifold import cache, atomic_file
    point, target = sys.argv[1], sys.argv[2]
    manifold = am.load(sys.argv[3])

    def hold():  # tell the test where we are, then wait to be killed
        print("holding", flush=True)
        sys.stdin.read()

    if point.startswith("chunk"):
        chunks = [0]
        def crc32(data, value=0):
            chunks[0] += 1
            if chunks[0] == int(point[5:]):
                hold()
            return zlib.crc32(data, value)
        cache.zlib = types.SimpleNamespace(crc32=crc32)
    real_replace = os.replace
    def replace(a, b):
        if point == "before-rename":
            hold()
        real_replace(a, b)
        if point == "after-rename":
            hold()
    atomic_file.os = types.SimpleNamespace(**{**vars(os), "replace": replace})
    am.save(manifold, target)
""")


def big_manifold() -> am.AnimationManifold:
    v, f = icosphere(4)
    times = np.linspace(0.0, 1.0, 12)
    return am.stitch(wobble(v, times), f, times)  # 168,960 tets, about 4 MB on disk


@pytest.mark.parametrize("round_", range(2))
def test_kill_9_during_a_save_never_damages_the_file_and_the_next_save_cleans_up(manifold, tmp_path, round_):
    target, source = tmp_path / "out.amf", tmp_path / "source.amf"
    big = big_manifold()
    am.save(big, source)
    am.save(manifold, target)
    allowed = {manifold.points.tobytes(), big.points.tobytes()}
    for point in ["chunk2", "chunk3", "chunk4", "before-rename", "after-rename", "chunk2"]:
        kill_during_save(point, target, source)
        assert am.load(target).points.tobytes() in allowed, f"damaged after a kill at {point}"
        # the killed writer's temporary, if it made one; the earlier ones went with this save
        assert len(list(tmp_path.glob("*.tmp"))) == (0 if point == "after-rename" else 1)
    am.save(manifold, target)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.amf", "source.amf"]


def kill_during_save(point: str, target: Path, source: Path) -> None:
    """Runs a save in a child that holds at `point` (CHILD's hooks), and kills it there with SIGKILL."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(PACKAGE), os.environ.get("PYTHONPATH", "")])}
    with subprocess.Popen([sys.executable, "-c", CHILD, point, str(target), str(source)], env=env, text=True,
                          stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE) as child:
        line = child.stdout.readline()
        child.kill()
        _, errors = child.communicate()
    assert line == "holding\n", f"the child never reached {point}: {errors}"
