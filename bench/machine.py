"""The machine a benchmark table was measured on: cores, the BLAS CHOLMOD loads, the
thread count, and the Python, numpy and bpy versions (bench/run_all.py states them at the
top of its table, its JSON and its chart)."""

from __future__ import annotations

import os
import platform
import subprocess
import time
from pathlib import Path

import numpy as np


def loaded_blas() -> str:
    """The BLAS library this process has mapped after a small Laplacian solve (CHOLMOD's
    supernodal factorisation calls it), resolved through Debian's alternatives symlinks;
    else what `update-alternatives` selects for libblas.so.3, saying so."""
    try:
        import animanifold as am
        from animanifold.procedural import icosphere

        vertices, faces = icosphere(3)
        deformer = am.Deformer(vertices, faces, [0, 1, 2], [len(vertices) - 1], "uniform")
        deformer.deform(am.handle_transform(translation=[0.0, 0.0, 0.1], dimension=3))
    except Exception as error:  # noqa: BLE001  (the machine line says why instead)
        return f"unknown ({type(error).__name__} in the Laplacian probe: {error})"
    mapped = sorted({line.split()[-1] for line in Path("/proc/self/maps").read_text().splitlines()
                     if "blas" in line.rsplit("/", 1)[-1].lower() and "/" in line})
    # numpy's wheel maps its own OpenBLAS; CHOLMOD's is the system's libblas.so.3.
    system = [str(Path(p).resolve()) for p in mapped if "numpy" not in p]
    if system:
        return ", ".join(system)
    return f"none mapped; update-alternatives selects {alternative_blas()}"


def alternative_blas() -> str:
    try:
        done = subprocess.run(["update-alternatives", "--query", "libblas.so.3-x86_64-linux-gnu"],
                              capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired) as error:
        return f"unknown ({error})"
    values = [line.split(":", 1)[1].strip() for line in done.stdout.splitlines() if line.startswith("Value:")]
    return values[0] if values else "unknown"


def thread_count() -> tuple[int, str]:
    """(threads, where the figure comes from): am.threads() when the core has it, else
    OMP_NUM_THREADS, else os.cpu_count()."""
    import animanifold as am

    if callable(getattr(am, "threads", None)):
        return int(am.threads()), "am.threads()"
    if os.environ.get("OMP_NUM_THREADS", "").strip().isdigit():
        return int(os.environ["OMP_NUM_THREADS"]), "OMP_NUM_THREADS (animanifold has no threads() yet)"
    return os.cpu_count() or 1, "os.cpu_count(): OMP_NUM_THREADS unset, animanifold has no threads() yet"


def bpy_version() -> str:
    try:
        import bpy
    except ImportError as error:
        return f"not importable ({error})"
    return bpy.app.version_string


def fresh_memory_seconds(gib: float = 1.0) -> float:
    """Seconds to fault in `gib` GiB of fresh memory (a numpy array of ones), freed at once.

    On this kind of virtual machine the guest hands memory that stayed free for a while back
    to its host (virtio-balloon free page reporting), and faulting it in again costs many
    times a warm page fault: measured here, 512 MiB took 1,165 ms after 25 s idle and 55 ms
    right after. A benchmark's first large allocation then runs at the host's pace, not the
    code's: the slow processes of earlier runs, where even the C++ stitch alone ran at half
    speed. Touching a buffer this size and freeing it leaves the pages warm (in the guest's
    free lists, not yet reported) for the allocations that follow within seconds, and the
    time it took says whether the process started cold.
    """
    start = time.perf_counter()
    buffer = np.ones(int(gib * 2**30) // 8)
    seconds = time.perf_counter() - start
    del buffer
    return seconds


def describe_machine() -> dict:
    threads, source = thread_count()
    return {"cores": os.cpu_count(), "blas": loaded_blas(), "threads": threads, "threads_from": source,
            "python": platform.python_version(), "numpy": np.__version__, "bpy": bpy_version(),
            "load_average": list(os.getloadavg())}


def machine_line(machine: dict) -> str:
    load = ", ".join(f"{x:.1f}" for x in machine["load_average"])
    return (f"cores {machine['cores']}; threads {machine['threads']} ({machine['threads_from']}); "
            f"BLAS {machine['blas']}; Python {machine['python']}, numpy {machine['numpy']}, bpy {machine['bpy']}; "
            f"load average at start {load}")
