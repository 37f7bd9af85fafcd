"""Every bench/ script at a size that finishes in about ten minutes on two cores, and ONE
table: our figure, the peer's figure measured in the same run, their ratio and issue 24's
target where it names one.

    python3 bench/run_all.py [--only stitch,laplacian,...] [--full] [--threads N] [--out out/bench] [--redraw]

Each script runs in its own process with --json PATH (bench/figures.py) and its output goes
to OUT/logs/NAME.log; a script that fails, times out or has no peer (OpenVDB's bench not
built, no ../shared/data, no bpy) gives rows that say why. Writes OUT/table.txt,
OUT/table.json and OUT/table.png (ratio per measure, log scale), the machine (cores, the
BLAS CHOLMOD loads, threads, Python, numpy and bpy) at the top of each.

--full adds the ~100k-vertex manifold in R^4 to the Laplacian (minutes); --threads N sets
OMP_NUM_THREADS and OPENBLAS_NUM_THREADS for the scripts. Not run: bench_uv_blend.py (it
compares design candidates of issue 3 one per fresh process), bench_morph.py
--seed-report (the §8.7.1 report; the bar mode is the table's morph row) and
bench_morph_primitives.py (a survey of the morph's own checks on Blender's primitives, with no
peer and no figure to compare) and bench_noise_scan.py (the field morph's noise at hundreds of
times per pair, for work on the noise; no peer).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
sys.path[:0] = [str(ROOT / "python"), str(BENCH)]

import table_rows  # noqa: E402
from machine import describe_machine  # noqa: E402
from table_output import format_table, write_chart, write_json  # noqa: E402
from table_rows import Row  # noqa: E402


@dataclass
class Job:
    """One bench script run: its arguments (besides --json), the rows made of its figures,
    and the measures it stands for (the rows that say why, when it gives no figures)."""

    name: str
    script: str
    arguments: list[str]
    rows: Callable[[dict], list[Row]]
    measures: list[str]
    timeout: float = 300.0
    full_arguments: list[str] = field(default_factory=list)


def peer_build() -> Path:
    """The CMake build holding bench_mcf_skeleton: build/ or build-bench/ (where bench_morph.py builds
    OpenVDB's peer), whichever has it; else build/, where bench_skeleton.py builds it."""
    for build in (ROOT / "build", ROOT / "build-bench"):
        if (build / "bench_mcf_skeleton").exists():
            return build
    return ROOT / "build"


def jobs() -> list[Job]:
    build = str(peer_build())
    return [
        Job("stitch", "bench_stitch_slice.py",
            ["--mesh", "production", "--keyframes", "20", "--frames", "10", "--repeat", "3", "--bandwidth-gib", "0.5"],
            table_rows.stitch_rows, ["stitch", "slice (4.9 M tets)"]),
        Job("slice_large", "bench_stitch_slice.py",
            ["--keyframes", "100", "--frames", "5", "--repeat", "1", "--bandwidth-gib", "0.5"],
            table_rows.slice_large_rows, ["slice (16.8 M tets)", "slice index memory"]),
        Job("playback", "bench_playback.py",  # the demo at ~12.6k triangles: 50k takes over 5 minutes
            ["--segments", "90", "--rings", "70", "--loops", "2", "--no-handler-path"], table_rows.playback_rows,
            ["playback source / live / baked"], timeout=360),
        Job("refine", "bench_refine.py", [], table_rows.refine_rows, ["refine"]),
        Job("laplacian", "bench_laplacian.py", ["--no-tets", "--surface-methods", "cotangent"],
            table_rows.laplacian_rows, ["Laplacian vs Blender's Laplacian Deform"], timeout=480,
            full_arguments=["--surface-methods", "cotangent", "--tets-methods", "dual"]),
        Job("skeleton", "bench_skeleton.py", ["--repeat", "1", "--cases", "3holes.off,torus-5000.off",
                                              "--build", build],
            table_rows.skeleton_rows, ["skeleton vs CGAL MCF"]),
        Job("morph", "bench_morph.py", ["--bar", "--pairs", "icosphere->ring_of_holes", "--methods", "skeleton",
                                        "--frames", "4", "--vdb-resolution", "64"],
            table_rows.morph_rows, ["morph vs OpenVDB"], timeout=360),
        Job("subdivide", "bench_subdivide.py", [], table_rows.subdivide_rows, ["subdivision"]),
        Job("hole_space", "bench_hole_space.py", ["--repeat", "1"], table_rows.hole_space_rows, ["hole space"]),
    ]


def last_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1][:300] if lines else ""


def run_job(job: Job, out: Path, env: dict, full: bool) -> tuple[list[Row], dict]:
    """Runs one script; (its rows, what happened: seconds, exit status, log path)."""
    figures_path, log_path = out / "figures" / f"{job.name}.json", out / "logs" / f"{job.name}.log"
    figures_path.unlink(missing_ok=True)
    arguments = job.full_arguments if full and job.full_arguments else job.arguments
    command = [sys.executable, str(BENCH / job.script), *arguments, "--json", str(figures_path)]
    print(f"run_all: {job.name}: {' '.join(command[1:])}", flush=True)
    start = time.perf_counter()
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=job.timeout, env=env, cwd=ROOT)
        output, status = done.stdout + done.stderr, done.returncode
    except subprocess.TimeoutExpired as timeout:
        output = (timeout.stdout or b"").decode(errors="replace") + (timeout.stderr or b"").decode(errors="replace")
        status = f"timed out after {job.timeout:g} s"
    seconds = time.perf_counter() - start
    log_path.write_text(output)
    run = {"seconds": seconds, "status": status, "log": str(log_path), "command": command[1:]}
    print(f"run_all: {job.name}: {'exit status ' + str(status) if isinstance(status, int) else status} "
          f"({seconds:.0f} s)", flush=True)
    if status != 0 or not figures_path.exists():
        why = status if isinstance(status, str) else f"{job.script} exited with {status}: {last_line(output)}"
        return table_rows.unavailable(job.measures, why), run
    try:
        return job.rows(json.loads(figures_path.read_text())), run
    except (KeyError, TypeError, ValueError) as error:
        return table_rows.unavailable(job.measures, f"{job.script}'s figures lack {error!r}"), run


def redraw(out: Path) -> int:
    """The table and the chart again from `out`/table.json (after a change to their layout)."""
    saved = json.loads((out / "table.json").read_text())
    rows = [Row(**{k: v for k, v in row.items() if k != "ratio"}) for row in saved["rows"]]
    table = format_table(rows, saved["machine"])
    print(table)
    (out / "table.txt").write_text(table + "\n")
    write_chart(out / "table.png", rows, saved["machine"])
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", default=None, help="comma-separated job names: "
                        + ", ".join(job.name for job in jobs()))
    parser.add_argument("--full", action="store_true", help="the Laplacian on the ~100k manifold in R^4 too")
    parser.add_argument("--threads", type=int, default=None, help="OMP_NUM_THREADS / OPENBLAS_NUM_THREADS")
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "bench")
    parser.add_argument("--redraw", action="store_true", help="no runs: the table and chart again from OUT/table.json")
    args = parser.parse_args()
    if args.redraw:
        return redraw(args.out)
    chosen = jobs()
    if args.only:
        names = {name.strip() for name in args.only.split(",")}
        unknown = names - {job.name for job in chosen}
        if unknown:
            parser.error(f"unknown job(s) {', '.join(sorted(unknown))}")
        chosen = [job for job in chosen if job.name in names]
    if args.threads is not None:
        os.environ["OMP_NUM_THREADS"] = os.environ["OPENBLAS_NUM_THREADS"] = str(args.threads)
    for folder in ("figures", "logs"):
        (args.out / folder).mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(str(ROOT / p) for p in ("python", "tests", "bench")))
    machine = describe_machine()
    rows, runs = [], {}
    rows.append(Row("bench_uv_blend.py", "", note="not run: it compares issue 3's design candidates, one per fresh "
                                                    "process on an idle machine (see its docstring)"))
    rows.append(Row("bench_morph_primitives.py", "", note="not run: a survey of the morph's own checks on Blender's "
                                                            "primitives, with no peer and no figure to compare"))
    rows.append(Row("bench_noise_scan.py", "", note="not run: the field morph's noise at hundreds of times per pair, "
                                                      "for work on the noise, with no peer"))
    start = time.perf_counter()
    for job in chosen:
        job_rows, runs[job.name] = run_job(job, args.out, env, args.full)
        rows[-1:-1] = job_rows
    machine["run_all_seconds"] = time.perf_counter() - start
    table = format_table(rows, machine)
    print("\n" + table)
    (args.out / "table.txt").write_text(table + "\n")
    write_json(args.out / "table.json", rows, machine, runs)
    write_chart(args.out / "table.png", rows, machine)
    print(f"\nrun_all: {machine['run_all_seconds']:.0f} s; wrote {args.out}/table.txt, table.json, table.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
