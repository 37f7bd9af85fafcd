"""The bar table of bench/bench_morph.py (its default mode, --bar): every morph method asked for
and OpenVDB's level-set morph, side by side on the same pairs of shapes, held to the morph
issue's bar with the same definitions for all.

What is compared
----------------
Pairs: the shared models bunny.off, spot.obj, torus-800.off and 3holes.off
(../shared/data/meshes) as bunny->torus-800, spot->3holes, torus-800->spot and 3holes->bunny,
and the two speed pairs from animanifold.procedural, icosphere(4)->ring_of_holes() (genus 4)
and blob()->thick_genus() (genus 3); then pairs of our own from animanifold.procedural:
icosphere(4)->smooth_genus(2), smooth_genus(5)->limbs() (thin limbs), flat_box(3)->icosphere(4)
(flat sides, genus 3) and limbs()->flat_box(). Every shape is normalised as in tests/test_morph_field.py:
bounding-box centre at the origin, diagonal 2 (the procedural ones too, so one yardstick serves
every pair); "diagonal" below is the larger input diagonal, 2.

Rows, per pair:
* each method of ``am.morph(source, target, method=...)`` asked for (--methods): its time is the
  wall time of the call (building the manifold; slicing the frames is not counted). Any
  exception (BooleanError, RuntimeError, ...) becomes the row's error and the bench goes on.
* "openvdb 1/N": bench/bench_vdb_morph.cpp (C++, OpenVDB's LevelSetMorphing, HJWENO5 + TVD-RK2,
  voxel = diagonal / N with N from --vdb-resolution) with frames=F: both inputs as narrow-band
  level sets, the source advected toward the target until the front is within 0.05 voxel of the
  target's (or stalls), then the advection replayed from the start to write F + 2 frames at
  k/(F+1) of the morph's time and the one at a quarter (see the .cpp). Its time is level sets +
  the first advection (not the replay, not the meshing); it runs TBB on all cores, ours on one.
  volumeToMesh gives inward-facing triangles, so every peer frame is flipped, once and the same
  way for all, to face outward as the inputs do.

Measures, on F spread frames plus the two ends (F = --frames, 24 for the bar), for every row:
* seconds: as above; the bar asks <= 10 s on the two speed pairs only.
* ends: the larger of the two-sided Hausdorff distances between the end frames and the inputs
  (exact point-to-triangle distances from the vertices, edge midpoints and face centres of each
  surface to the other), over the diagonal. Bar: <= 1e-9.
* noise, creases+, pop, quarter: animanifold.frame_quality.measure_frames on the frames
  (its topology_noise count, excess_creases, pop_ratio and quarter_motion; the quarter frame is
  the one at 1/4 of the range). Bar: no noise frame, creases+ <= 0.03, pop <= 3, quarter >= 0.10.
* crossing: in-between frames that run through themselves (``_core.self_intersections`` with a
  tolerance of 1e-9 diagonal finds a pair, or refuses the frame with ValueError). Bar: none.
* bubble: in-between frames with more negative-volume shells (``cavities.shell_volumes``) than
  the input that has more. Bar: none.
* flat: inverted + degenerate simplices of the manifold (the core's validity report; n/a for the
  peer, which has no simplices). Bar: 0.
"""

from __future__ import annotations

import json
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

import animanifold as am
from animanifold import _core, procedural
from animanifold.cavities import shell_volumes
from animanifold.frame_quality import measure_frames, unique_edges

ENDS = 1e-9  # of the diagonal
CREASE_ALLOWANCE = 0.03
POP_RATIO = 3.0
QUARTER_MOTION = 0.10
SPEED_SECONDS = 10.0  # on the speed pairs
SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes"

Mesh = tuple[np.ndarray, np.ndarray]


# -- the pairs -------------------------------------------------------------------
def normalised(mesh: Mesh) -> Mesh:
    """The mesh centred at the origin with a bounding-box diagonal of 2 (as tests/test_morph_field.py)."""
    v = np.asarray(mesh[0], dtype=np.float64)
    low, high = v.min(axis=0), v.max(axis=0)
    v = (v - (low + high) / 2) * (2 / np.linalg.norm(high - low))
    return np.ascontiguousarray(v), np.ascontiguousarray(mesh[1], dtype=np.int32)


@dataclass
class Pair:
    """Two shapes to morph between; `seconds_limit` is the bar's time limit (speed pairs only)."""

    name: str
    source: Mesh
    target: Mesh
    seconds_limit: float | None = None

    @property
    def diagonal(self) -> float:
        return max(float(np.linalg.norm(np.ptp(m[0], axis=0))) for m in (self.source, self.target))


def _shared(source: str, target: str) -> Callable[[], tuple[Mesh, Mesh]]:
    return lambda: (normalised(am.read_mesh(SHARED / source)), normalised(am.read_mesh(SHARED / target)))


def _procedural(source: Callable[[], Mesh], target: Callable[[], Mesh]) -> Callable[[], tuple[Mesh, Mesh]]:
    return lambda: (normalised(source()), normalised(target()))


# name -> (loader of (source, target), time limit); the names are what --pairs takes.
PAIRS: dict[str, tuple[Callable[[], tuple[Mesh, Mesh]], float | None]] = {
    "bunny->torus-800": (_shared("bunny.off", "torus-800.off"), None),
    "spot->3holes": (_shared("spot.obj", "3holes.off"), None),
    "torus-800->spot": (_shared("torus-800.off", "spot.obj"), None),
    "3holes->bunny": (_shared("3holes.off", "bunny.off"), None),
    "icosphere->ring_of_holes": (lambda: (normalised(procedural.icosphere(4)),
                                          normalised(procedural.ring_of_holes())), SPEED_SECONDS),
    "blob->thick_genus": (lambda: (normalised(procedural.blob()), normalised(procedural.thick_genus())),
                          SPEED_SECONDS),
    # Pairs of our own (the survey): a genus-2 and a genus-5 shape, thin limbs, flat sides.
    "icosphere->genus_2": (_procedural(lambda: procedural.icosphere(4), lambda: procedural.smooth_genus(2)), None),
    "genus_5->limbs": (_procedural(lambda: procedural.smooth_genus(5), procedural.limbs), None),
    "flat_box_3->icosphere": (_procedural(lambda: procedural.flat_box(3), lambda: procedural.icosphere(4)), None),
    "limbs->flat_box": (_procedural(procedural.limbs, procedural.flat_box), None),
}


def load_pairs(names: list[str] | None = None) -> list[Pair]:
    """The named pairs (all by default), loaded and normalised. A name may be given without
    punctuation or case ("bunnytorus800")."""
    simple = lambda s: "".join(c for c in s.lower() if c.isalnum())  # noqa: E731
    chosen = list(PAIRS) if not names else []
    for name in names or []:
        found = [p for p in PAIRS if simple(p) == simple(name)]
        if not found:
            raise SystemExit(f"bench_morph: unknown pair {name!r}; the pairs are: {', '.join(PAIRS)}")
        chosen += found
    pairs = []
    for name in chosen:
        load, limit = PAIRS[name]
        source, target = load()
        pairs.append(Pair(name, source, target, limit))
    return pairs


# -- measures --------------------------------------------------------------------
@dataclass
class Row:
    """One line of a pair's table: a method or the peer, with its measures (or its error)."""

    label: str
    seconds: float | None = None
    ends: float | None = None
    noise: int | None = None
    creases: float | None = None
    pop: float | None = None
    quarter: float | None = None
    crossing: int | None = None
    bubble: int | None = None
    flat: int | None = None  # None: not applicable (the peer)
    frames: int = 0  # in-between frames checked for crossing and bubbles
    error: str | None = None
    notes: list[str] = field(default_factory=list)


def as_mesh(vertices, faces) -> Mesh:
    return (np.ascontiguousarray(vertices, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int32))


def samples(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Every used vertex, edge midpoint and face centre of a triangle mesh."""
    edges, _ = unique_edges(faces)
    return np.ascontiguousarray(np.concatenate([vertices[np.unique(faces)], vertices[edges].mean(1),
                                                vertices[faces].mean(1)]))


def end_distance(frame: Mesh, mesh: Mesh, diagonal: float) -> float:
    """Two-sided Hausdorff distance between an end frame and its input, over the diagonal."""
    if len(frame[1]) == 0 or len(mesh[1]) == 0:
        return float("inf")
    one = _core.distances_to_surface(samples(*frame), *mesh).max()
    two = _core.distances_to_surface(samples(*mesh), *frame).max()
    return float(max(one, two)) / diagonal


def crosses_itself(mesh: Mesh, diagonal: float) -> bool:
    """A pair of faces passing through each other by more than 1e-9 diagonal (a frame the
    check refuses, ValueError, counts as crossing)."""
    try:
        return bool(_core.self_intersections(*mesh, 1, ENDS * diagonal))
    except ValueError:
        return True


def cavity_count(mesh: Mesh) -> int:
    return int((shell_volumes(*mesh) < 0).sum()) if len(mesh[1]) else 0


def measure_row(label: str, seconds: float, frames: list[Mesh], times, quarter: Mesh, pair: Pair,
                flat: int | None) -> Row:
    """The bar's measures of one row's frames (the ends first and last) against the pair."""
    diagonal = pair.diagonal
    m = measure_frames(frames, list(times), quarter)
    inside = frames[1:-1]
    allowed = max(cavity_count(pair.source), cavity_count(pair.target))
    return Row(label=label, seconds=seconds,
               ends=max(end_distance(frames[0], pair.source, diagonal), end_distance(frames[-1], pair.target, diagonal)),
               noise=len(m.topology_noise), creases=m.excess_creases, pop=m.pop_ratio, quarter=m.quarter_motion,
               crossing=sum(crosses_itself(f, diagonal) for f in inside),
               bubble=sum(cavity_count(f) > allowed for f in inside), flat=flat, frames=len(inside))


# -- the rows ----------------------------------------------------------------------
def ours_frames(manifold, count: int) -> tuple[np.ndarray, list[Mesh], Mesh]:
    """(times, frames, quarter): `count` frames spread over the manifold's range plus the ends,
    and the frame at a quarter of the range."""
    t0, t1 = manifold.time_range
    times = np.linspace(t0, t1, count + 2)
    slice_ = lambda t: as_mesh((s := manifold.slice(float(t))).vertices, s.faces)  # noqa: E731
    return times, [slice_(t) for t in times], slice_(t0 + 0.25 * (t1 - t0))


CHECKS_BUDGET = 0.25  # the morph's checks may take this share of its own time (the other stages')


def checks_notes(report: dict) -> list[str]:
    """What the morph's own checks cost against their budget, what its own frames showed (they
    bisect towards changes of topology, so they see frames between the bar's), and how they
    covered crossings."""
    seconds = dict(report.get("stage_seconds", []))
    if "validity" not in seconds:
        return []
    checks = seconds["validity"]
    own = sum(seconds.values()) - checks
    share = checks / own if own > 0 else float("inf")
    met = "within" if share <= CHECKS_BUDGET else "over"
    notes = [f"checks {checks:.2f} s = {100 * share:.0f} % of the morph's own {own:.2f} s "
             f"({met} the {100 * CHECKS_BUDGET:.0f} % budget)"]
    if "frames_checked" in report:  # its own frames: 24 spread, the field's 7 in its fill slab, the bisections
        noise, bubbles = report["noise_frames"], report["bubble_frames"]
        shown = ", ".join(f"{t:.4g}" for t in noise[:6]) + (", ..." if len(noise) > 6 else "")
        notes.append(f"own frame checks: {report['frames_checked']} frames; topological noise at {len(noise)}"
                     + (f" (t = {shown})" if noise else "") + f", bubbles at {len(bubbles)}")
    if report.get("crossings_certified"):
        # The field method checks each side's covers for the certificate as soon as the side is
        # extracted, on the thread the fill leaves free: their time is in the fill stage's, not here.
        notes.append(f"crossings: space-time triangulation certified for every time (its sides' covers "
                     f"checked beside the fill, in that stage's seconds); "
                     f"CGAL confirms on {report.get('crossing_frames_checked', 0)} frame(s)")
    elif "crossing_frames_checked" in report:
        failure = report.get("certificate_failure") or "not a field morph"
        notes.append(f"crossings: checked on {report['crossing_frames_checked']} frames ({failure})")
    return notes


RENDERED_FRAMES = 48  # Morph Selected's default range: frames 1-48


def rendered_noise_notes(manifold, pair: Pair) -> list[str]:
    """Of RENDERED_FRAMES frames spread over the range (as Morph Selected's default 1-48 renders
    them), those next to the topological noise the morph's own checks found, and those of them
    that show it (am.morph_noise): the checks look between frames too, where noise may last less
    than a frame."""
    noise = (manifold.validity or {}).get("noise_frames") or []
    if not noise:
        return []
    t0, t1 = manifold.time_range
    found = am.morph_noise.noise_on_frames(manifold, noise, np.linspace(t0, t1, RENDERED_FRAMES), pair.source,
                                           pair.target)
    frame = lambda t: str(int(round((t - t0) / (t1 - t0) * (RENDERED_FRAMES - 1))) + 1)  # noqa: E731
    return [f"at {RENDERED_FRAMES} frames: frames next to the noise {', '.join(map(frame, found.near))}; "
            f"showing it: {', '.join(map(frame, found.noisy)) or 'none'}"]


def run_method(pair: Pair, method: str, count: int, options: dict | None = None) -> Row:
    """One method's row (am.morph with `options` as keywords); an exception anywhere (the morph or
    its frames) is the row's error."""
    start = time.perf_counter()
    try:
        manifold = am.morph(pair.source, pair.target, method=method, **(options or {}))
        seconds = time.perf_counter() - start
        times, frames, quarter = ours_frames(manifold, count)
        report = manifold.validity
        flat = int(report.get("inverted_simplices", 0)) + int(report.get("degenerate_simplices", 0))
        row = measure_row(method, seconds, frames, times, quarter, pair, flat)
        row.notes += checks_notes(report) + rendered_noise_notes(manifold, pair)
        return row
    except Exception as error:  # noqa: BLE001  (the bench goes on with the next row)
        message = str(error).strip().splitlines()[0] if str(error).strip() else ""
        return Row(label=method, seconds=time.perf_counter() - start, error=f"{type(error).__name__}: {message}")


def read_peer_mesh(path: Path) -> Mesh:
    """A peer frame, flipped to face outward (volumeToMesh's triangles face inward)."""
    v, f = am.read_mesh(path)
    return as_mesh(v, np.asarray(f)[:, ::-1])


def run_peer(exe: Path | None, pair: Pair, resolution: float, count: int, work: Path,
             unavailable: str | None = None, timeout: float = 3600) -> Row:
    """The OpenVDB peer's row (its frames written by bench_vdb_morph frames=count)."""
    label = f"openvdb 1/{resolution:g}"
    if exe is None:
        return Row(label=label, error=f"n/a: {unavailable}")
    out = work / f"{''.join(c if c.isalnum() else '_' for c in pair.name)}-vdb-{resolution:g}"
    out.mkdir(parents=True, exist_ok=True)
    paths = (out / "source.off", out / "target.off")
    for path, mesh in zip(paths, (pair.source, pair.target)):
        am.write_mesh(path, *mesh)
    try:
        done = subprocess.run([str(exe), *map(str, paths), str(out), str(resolution), f"frames={count}"],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return Row(label=label, error=f"timed out after {timeout:g} s")
    if done.returncode != 0:
        return Row(label=label, error=done.stderr.strip() or f"exit code {done.returncode}")
    result = json.loads(done.stdout)
    frames = [read_peer_mesh(out / f"vdb_frame_{k:03d}.off") for k in range(count + 2)]
    times = np.asarray(result["frame_times"]) / max(result["morph_time"], 1e-300)
    row = measure_row(label, result["levelset_seconds"] + result["morph_seconds"], frames, times,
                      read_peer_mesh(out / "vdb_quarter.off"), pair, None)
    if not result["converged"]:
        row.notes.append(f"not converged by time {result['morph_time']:g}")
    row.notes.append(f"morph time {result['morph_time']:g}, {result['cfl_steps']} CFL steps, "
                     f"{result['threads']} threads; replay {result['replay_seconds']:.1f} s not counted")
    return row


# -- the table -----------------------------------------------------------------------
def misses(row: Row, seconds_limit: float | None) -> list[str]:
    """The bar's criteria the row misses (empty: it meets the bar); an error misses everything."""
    if row.error is not None:
        return ["error"]
    checks = [("time", seconds_limit is None or row.seconds <= seconds_limit), ("ends", row.ends <= ENDS),
              ("noise", row.noise == 0), ("creases", row.creases <= CREASE_ALLOWANCE), ("pop", row.pop <= POP_RATIO),
              ("quarter", row.quarter >= QUARTER_MOTION), ("crossing", row.crossing == 0),
              ("bubble", row.bubble == 0), ("flat", row.flat is None or row.flat == 0)]
    return [name for name, ok in checks if not ok]


COLUMNS = (("row", 16), ("seconds", 9), ("ends", 9), ("noise", 6), ("creases+", 9), ("pop", 7), ("quarter", 8),
           ("crossing", 9), ("bubble", 7), ("flat/inv", 9), ("bar", 5))


def cells(row: Row, seconds_limit: float | None) -> list[str]:
    flat = "n/a" if row.flat is None else str(row.flat)
    return [row.label, f"{row.seconds:.1f}", f"{row.ends:.1e}", str(row.noise), f"{row.creases:+.3f}",
            f"{row.pop:.2f}", f"{row.quarter:.3f}", str(row.crossing), str(row.bubble), flat,
            "no" if misses(row, seconds_limit) else "yes"]


def format_table(pair: Pair, rows: list[Row], count: int) -> str:
    """The pair's table: a header, one line per row (an error in place of the measures), and
    the notes under it."""
    limit = f"; bar: <= {pair.seconds_limit:g} s" if pair.seconds_limit else ""
    lines = [f"--- {pair.name}: {len(pair.source[0])} -> {len(pair.target[0])} vertices, {count} frames + ends "
             f"(crossing/bubble of {count} in-between frames){limit} ---",
             "".join(f"{name:<{w}}" if i == 0 else f"{name:>{w}}" for i, (name, w) in enumerate(COLUMNS))]
    for row in rows:
        if row.error is not None:
            seconds = f"{row.seconds:.1f}" if row.seconds is not None else "—"
            lines.append(f"{row.label:<16}{seconds:>9}  error: {row.error}{'':>3}bar: no")
            continue
        lines.append("".join(f"{c:<{w}}" if i == 0 else f"{c:>{w}}"
                             for i, (c, (_, w)) in enumerate(zip(cells(row, pair.seconds_limit), COLUMNS))))
    lines += [f"  {row.label}: {note}" for row in rows for note in row.notes]
    return "\n".join(lines)


def summary_line(pair: Pair, rows: list[Row]) -> str:
    """Which rows meet the bar and what the others miss, on one line."""
    meet = [r.label for r in rows if not misses(r, pair.seconds_limit)]
    miss = [f"{r.label} ({', '.join(misses(r, pair.seconds_limit))})" for r in rows if misses(r, pair.seconds_limit)]
    return (f"{pair.name}: meets the bar: {', '.join(meet) or 'none'}"
            f"{'; misses: ' + '; '.join(miss) if miss else ''}")


def bar_rows(pair: Pair, methods: list[str], count: int, peer: Callable[[Pair], Row] | None = None,
             progress: Callable[[str], None] = lambda line: None,
             options: dict[str, dict] | None = None) -> list[Row]:
    """The rows of one pair: each method (am.morph with options.get(method) as keywords), then the
    peer (when given)."""
    rows = []
    for method in methods:
        chosen = (options or {}).get(method, {})
        shown = "".join(f", {key}={value!r}" for key, value in chosen.items())
        progress(f"{pair.name}: am.morph(method={method!r}{shown}) ...")
        rows.append(run_method(pair, method, count, chosen))
        progress(f"{pair.name}: {method} {'raised' if rows[-1].error else 'done'} after {rows[-1].seconds:.1f} s")
    if peer is not None:
        progress(f"{pair.name}: OpenVDB peer ...")
        rows.append(peer(pair))
    return rows


def run_bar(pairs: list[str] | None, methods: list[str], count: int, work: Path, peer_exe: Path | None = None,
            peer_unavailable: str | None = None, resolution: float | None = 128,
            options: dict[str, dict] | None = None) -> list[tuple[Pair, list[Row]]]:
    """Every pair's rows, each pair's table printed as soon as it is measured and all of them
    again at the end with a summary line each. resolution=None: no peer row. options: per
    method, keywords for its am.morph."""
    say = lambda line: print(f"bench_morph: {line}", flush=True)  # noqa: E731
    peer = None
    if resolution is not None:
        peer = lambda pair: run_peer(peer_exe, pair, resolution, count, work, peer_unavailable)  # noqa: E731
    results = []
    for pair in load_pairs(pairs):
        rows = bar_rows(pair, methods, count, peer, say, options)
        results.append((pair, rows))
        print("\n" + format_table(pair, rows, count) + "\n", flush=True)
    print(f"\n=== the bar, {count} frames + ends: ours ({', '.join(methods)})"
          f"{'' if resolution is None else f' and OpenVDB 1/{resolution:g}'} ===")
    for pair, rows in results:
        print("\n" + format_table(pair, rows, count))
    print("\nsummary:")
    for pair, rows in results:
        print("  " + summary_line(pair, rows))
    return results
