"""The rows of bench/run_all.py's table, one function per bench script: each takes the
figures the script wrote (--json) and returns Rows of our figure, the peer's figure from the
same run, their ratio and issue 24's target where it names one."""

from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass
class Row:
    """One measure. ratio: how many times better ours is than the peer (> 1: ours is faster),
    whichever way the unit runs; met: whether the target is met (None: no target)."""

    measure: str
    unit: str
    ours: float | None = None
    peer: float | None = None
    peer_name: str = ""
    higher_is_better: bool = True
    target: str = ""
    met: bool | None = None
    note: str = ""

    @property
    def ratio(self) -> float | None:
        if self.ours is None or self.peer is None or self.ours <= 0 or self.peer <= 0:
            return None
        return self.ours / self.peer if self.higher_is_better else self.peer / self.ours

    def as_dict(self) -> dict:
        return {**asdict(self), "ratio": self.ratio}


def unavailable(measures: list[str], why: str) -> list[Row]:
    """Rows that say why a script or its peer gave no figures."""
    return [Row(measure, "", note=f"unavailable: {why}") for measure in measures]


def at_least(value: float | None, target: float) -> bool | None:
    return None if value is None else value >= target


def at_most(value: float | None, target: float) -> bool | None:
    return None if value is None else value <= target


def slice_stage_note(f: dict) -> str:
    """'; stages stab 1.2, cut 6.0, ... ms' from bench_stitch_slice's per-stage figures (empty without them)."""
    stages = [(name, f.get(f"slice_{name}_ms")) for name in ("stab", "cut", "weld", "output", "normals")]
    if any(ms is None for _, ms in stages):
        return ""
    return "; stages " + ", ".join(f"{name} {ms:.1f}" for name, ms in stages) + " ms"


def fresh_memory_note(f: dict) -> str:
    """How long faulting in fresh memory took just before the first call (bench/machine.py's
    fresh_memory_seconds): the first call itself runs on warm pages."""
    if "fresh_memory_s" not in f:
        return ""
    return f"on warm memory: 1 GiB of fresh memory faulted in {f['fresh_memory_s']:.2f} s just before"


def stitch_rows(f: dict) -> list[Row]:
    """bench_stitch_slice --mesh production (4.87 M tets): stitch and slice."""
    case = f"{f['tets'] / 1e6:.2f} M tets"
    copy_peer = "numpy copy of the output"
    e2e, first = f["stitch_mtets_per_s"], f["stitch_first_mtets_per_s"]
    frame_ms, bound_ms = f["slice_ms_per_frame"], f["memory_bound_slice_ms"]
    return [
        Row(f"stitch end to end, best ({case})", "M tets/s", e2e, f["output_copy_mtets_per_s"], copy_peer,
            target=">= 50", met=at_least(e2e, 50), note=f"C++ stitch alone {f['stitch_core_mtets_per_s']:.1f} M tets/s"),
        Row(f"stitch end to end, first call ({case})", "M tets/s", first, f["output_copy_mtets_per_s"], copy_peer,
            target=">= 50", met=at_least(first, 50), note=fresh_memory_note(f)),
        Row(f"stitch peak memory / output ({case})", "x", f["stitch_peak_over_output"], higher_is_better=False,
            target="<= 1.5", met=at_most(f["stitch_peak_over_output"], 1.5),
            note=f"peak {f['stitch_peak_bytes'] / 2**20:.0f} MiB, output {f['output_bytes'] / 2**20:.0f} MiB"),
        Row(f"slice per frame ({case})", "ms/frame", frame_ms, bound_ms, "memory bound (bytes touched / copy bandwidth)",
            higher_is_better=False, target="<= 20 (50 frames/s)", met=at_most(frame_ms, 20.0),
            note=f"{f['slice_frames_per_s']:.1f} frames/s, {f['faces_per_frame']:,} faces; "
                 f"index built in {f['index_s']:.2f} s" + slice_stage_note(f)),
        package_frame_row(f, case, "<= 20 (50 frames/s)", 20.0),
    ]


def package_frame_row(f: dict, case: str, target: str, limit: float) -> Row:
    """The frame users get from am.AnimationManifold.slice (with its normals), against the
    core's slice of the tets: for stitched keys, the prism frame (the source's faces)."""
    what = "prism frame (the keys' faces, a lerp)" if f.get("package_prism_frames") else "the core's slice"
    return Row(f"frame through the package ({case})", "ms/frame", f["package_slice_ms_per_frame"],
               f["slice_ms_per_frame"], "the tets' slice (the row above)", higher_is_better=False, target=target,
               met=at_most(f["package_slice_ms_per_frame"], limit),
               note=f"am.AnimationManifold.slice between keys: {what}, {f.get('package_faces_per_frame', 0):,} faces")


def slice_large_rows(f: dict) -> list[Row]:
    """bench_stitch_slice on its default case (16.8 M tets): slice speed and index memory."""
    case = f"{f['tets'] / 1e6:.1f} M tets"
    frame_ms, index_mib = f["slice_ms_per_frame"], f["index_bytes"] / 2**20
    return [
        Row(f"slice per frame ({case})", "ms/frame", frame_ms, f["memory_bound_slice_ms"],
            "memory bound (bytes touched / copy bandwidth)", higher_is_better=False,
            target="<= 9.65 (38.6 / 4)", met=at_most(frame_ms, 38.6 / 4),
            note=f"{f['slice_frames_per_s']:.1f} frames/s" + slice_stage_note(f)),
        package_frame_row(f, case, "<= 9.65 (38.6 / 4)", 38.6 / 4),
        Row(f"slice index memory ({case})", "MiB", index_mib, higher_is_better=False, target="< 300",
            met=index_mib < 300),
    ]


def playback_rows(f: dict) -> list[Row]:
    """bench_playback: frames/s of the live and the baked object against the source's shape keys."""
    fps = f["fps"]
    peer = "source object (shape keys)"
    note = f"{f['source_triangles']:,} triangles, {f['manifold_tets']:,} tets, Blender {f['blender']}"
    return [Row("playback, source (shape keys)", "frames/s", fps["a_source_shape_keys"], note=note),
            Row("playback, live manifold", "frames/s", fps["b_live_manifold"], fps["a_source_shape_keys"], peer),
            Row("playback, baked", "frames/s", fps["c_baked_node_group"], fps["a_source_shape_keys"], peer)]


def refine_rows(f: dict) -> list[Row]:
    return [Row(f"refine ({f['splits']:,} splits of {f['tets'] / 1e6:.2f} M tets)", "splits/s", f["splits_per_s"],
                note=f"no peer; peak {f['peak_mib']:.0f} MiB")]


def response_note(ours: dict) -> str:
    """A deform by a transform combines precomputed response columns: say what the first one
    (which solves them) and a fresh sparse solve (each restore iteration) cost."""
    if ours.get("first_deform_s") is None:
        return ""
    return (f"deform by a transform (affine response); first deform {ours['first_deform_s']:.2f} s, "
            f"fresh solve {ours['fresh_solve_s']:.2f} s")


def laplacian_rows(f: dict) -> list[Row]:
    """bench_laplacian: the ~94k surface (and the 2.5k block) against Blender's Laplacian Deform
    modifier, and the ~100k-vertex manifold in R^4 when it ran."""
    rows = []
    blender = f.get("blender_modifier", {})
    peer = f"Blender {blender.get('blender', '')} Laplacian Deform"
    for case, target in (("surface", 15.0), ("block", None)):
        ours = f.get(case, {}).get("cotangent")
        if ours is None:
            continue
        theirs = blender.get(case, {})
        vertices = f"{f[case]['vertices'] / 1000:.1f}k"
        why = "" if theirs else f"peer unavailable: {blender.get('skipped', 'not run')}"
        bind = Row(f"Laplacian bind, {case} {vertices} (cotangent)", "s", ours["initialise_s"],
                   theirs.get("bind_s"), peer, higher_is_better=False, note=why)
        solves = Row(f"Laplacian solves, {case} {vertices} (cotangent)", "solves/s", ours["solves_per_s"],
                     theirs.get("solves_per_s"), peer, note="; ".join(n for n in (why, response_note(ours)) if n))
        if target:
            for row in (bind, solves):
                row.target, row.met = f"ratio >= {target:g}", at_least(row.ratio, target)
        rows += [bind, solves]
    tets = f.get("tets", {}).get("dual")
    if tets is not None:
        vertices = f"{f['tets']['vertices'] / 1000:.0f}k"
        restore = (f"restore {tets['restore_s']:.1f} s, {tets['restore_iterations']} iterations, "
                   f"{'converged' if tets['restore_converged'] else 'NOT converged (cap)'}")
        rows += [Row(f"Laplacian setup, {vertices}-vertex manifold in R^4 (dual)", "s", tets["initialise_s"],
                     higher_is_better=False, target="<= 10", met=at_most(tets["initialise_s"], 10.0), note=restore),
                 Row(f"Laplacian solves, {vertices}-vertex manifold in R^4 (dual)", "solves/s", tets["solves_per_s"],
                     target=">= 10", met=at_least(tets["solves_per_s"], 10.0), note=response_note(tets))]
    return rows


def skeleton_rows(f: dict) -> list[Row]:
    """bench_skeleton: the Voronoi skeleton against CGAL's mean-curvature-flow skeleton."""
    return [Row(f"skeleton, {name} ({case['vertices']:,} vertices)", "s", case["ours_s"], case.get("mcf_s"),
                "CGAL Mean_curvature_flow_skeletonization", higher_is_better=False,
                note=f"peer unavailable: {case['mcf_unavailable']}" if "mcf_unavailable" in case else "")
            for name, case in f.items()]


def morph_rows(f: dict) -> list[Row]:
    """bench_morph --bar: each method's time against OpenVDB's level-set morph on each pair."""
    rows = []
    for pair, entries in f["pairs"].items():
        peers = [e for e in entries if e["label"].startswith("openvdb")]
        peer = peers[0] if peers else None
        peer_seconds = peer["seconds"] if peer and peer["error"] is None else None
        for entry in entries:
            if entry in peers:
                continue
            note = f"error: {entry['error']}" if entry["error"] else ""
            if peer is not None and peer["error"] is not None:
                note = (note + "; " if note else "") + f"peer: {peer['error']}"
            elif peer is None:
                note = (note + "; " if note else "") + f"peer unavailable: {f.get('peer_unavailable') or 'not run'}"
            rows.append(Row(f"morph {pair} ({entry['label']})", "s", entry["seconds"] if not entry["error"] else None,
                            peer_seconds, peer["label"] if peer else "OpenVDB level-set morph",
                            higher_is_better=False, note=note))
    return rows


def subdivide_rows(f: dict) -> list[Row]:
    rows = []
    manifold = f.get("manifold_keep_keyframe_times_False")
    if manifold:
        rows.append(Row(f"subdivide manifold, 1 level ({manifold['input_tets'] / 1e6:.2f} M tets in)", "M tets/s",
                        manifold["input_mtets_per_s"], note=f"{manifold['seconds']:.2f} s; no peer"))
    for key, label in (("loop_frame", "Loop"), ("catmull_clark_frame", "Catmull-Clark")):
        if key in f:
            frame = f[key]
            rows.append(Row(f"subdivide frame, {label} level 2 (OpenSubdiv)", "ms/frame", frame["ms_per_frame"],
                            frame.get("blender_ms"), frame.get("blender_peer", ""), higher_is_better=False))
    return rows


def hole_space_rows(f: dict) -> list[Row]:
    return [Row(f"hole space, torus-800 ({f['vertices']} vertices)", "s", f["seconds"], higher_is_better=False,
                note="no peer")]
