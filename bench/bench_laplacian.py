"""Laplacian deformation benchmark (chapter 4, Figure 4.11 / 4.12).

    python3 bench/bench_laplacian.py            # everything (the 100k tet manifold takes minutes)
    python3 bench/bench_laplacian.py --quick    # the 2.5k block only
    python3 bench/bench_laplacian.py --no-tets --no-blender
    python3 bench/bench_laplacian.py --json out.json   # the figures also as JSON (bench/run_all.py)

Cases:
  block      the Figure 4.11 block (2,450 vertices, triangles in R^3): bottom cap
             anchored, top cap rotated by π/4, π/2, 3π/4; averages as in Figure 4.12
  surface    the block refined to ~94k vertices (triangles in R^3), top cap rotated π/2
  tets       a ~100k-vertex animation manifold (icosphere(4) x 40 keyframes, 599k tets in R^4),
             anchored at both ends, a patch in the middle dragged back in time
  blender    Blender's own Laplacian Deform modifier (bpy) on the block and surface,
             handles driven by a Hook to an Empty: bind time and per-frame evaluation

Initialise = weights + L + factorisation of LᵀL (CHOLMOD supernodal); First = the first
deform by a transform, which also solves the 2D+1 response columns (the solution is affine
in the transform); Deform = each later deform by a new transform (mean of several), the
response's dense combination; Solve = one fresh sparse solve (deform to handle positions,
what every restore iteration costs); Restore = the dual method's feature restoration from
a one-step deform until motion < 1e-6 (cap 50; 30 for tets). The tets case also prints the
initialise breakdown from Deformer.info (weights and L, normal matrix, CHOLMOD analyse and
factorise), the factorisation's flops, and how many of its BLAS calls ran by tiles on every
thread (cpp/src/tiled_blas.hpp; 0 where CHOLMOD binds to another BLAS).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "tests")]

import animanifold as am  # noqa: E402
from animanifold import _core  # noqa: E402
from helpers.laplacian_shapes import block, face_normals, folded_edges  # noqa: E402
from helpers.shapes import icosphere  # noqa: E402

sys.path.insert(0, str(ROOT / "bench"))
from figures import add_json_option, write_json  # noqa: E402

SEED_TABLE = {  # Figure 4.12 (the dissertation's block, ~2500 vertices, 2008 hardware)
    "uniform": ("0.11 s", "0.01 s", "---"),
    "graph": ("55.41 s", "0.01 s", "---"),
    "dual": ("0.27 s", "0.01 s", "5.01 s"),
    "cotangent": ("(not in table)", "", ""),
}


def caps(V):
    z = V[:, 2]
    return np.flatnonzero(z < z.min() + 1e-9), np.flatnonzero(z > z.max() - 1e-9)


def twist(V, angle):
    z = V[:, 2].max()
    return am.handle_transform(rotation=am.rotation_matrix([0, 0, 1], angle), center=[0, 0, z], dimension=3)


def inverted_faces(V, F, out, angle):
    n0 = face_normals(V, F)
    a = angle * V[F].mean(1)[:, 2] / V[:, 2].max()
    c, s = np.cos(a), np.sin(a)
    expected = np.stack([c * n0[:, 0] - s * n0[:, 1], s * n0[:, 0] + c * n0[:, 1], n0[:, 2]], 1)
    return int(((face_normals(out, F) * expected).sum(1) <= 0).sum())


def time_method(V, F, anchors, handles, method, transforms, solves=10, restore_cap=50, steps=None):
    """(init s, deform s per solve, restore s or None, restore status, points after restore/deform,
    the Deformer, the first deform's s, one fresh sparse solve's s)."""
    t0 = time.perf_counter()
    d = am.Deformer(V, F, anchors, handles, method)
    init = time.perf_counter() - t0
    t0 = time.perf_counter()
    d.deform(transforms[0])
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    d.deform(handle_positions=d.points[handles])
    fresh = time.perf_counter() - t0
    deform_times, restore_times, statuses, outs = [], [], [], []
    for T in transforms:
        t0 = time.perf_counter()
        for i in range(solves):
            # A slightly different transform each time: nothing may be cached per transform.
            out = d.deform(T @ am.handle_transform(translation=[1e-6 * i] * (len(T) - 1), dimension=len(T) - 1))
        deform_times.append((time.perf_counter() - t0) / solves)
        if method == "dual":
            t0 = time.perf_counter()
            out = d.restore(max_iterations=restore_cap, tolerance=1e-6)
            restore_times.append(time.perf_counter() - t0)
            statuses.append(d.status)
        outs.append(out)
    restore = float(np.mean(restore_times)) if restore_times else None
    return init, float(np.mean(deform_times)), restore, statuses, outs, d, first, fresh


def method_figures(init, deform, restore, statuses, first=None, fresh=None) -> dict:
    figures = {"initialise_s": init, "deform_s": deform, "solves_per_s": 1 / deform, "restore_s": restore,
               "first_deform_s": first, "fresh_solve_s": fresh}
    if statuses:
        figures["restore_iterations"] = statuses[0].iterations
        figures["restore_converged"] = bool(statuses[0].converged)
    return figures


def bench_block():
    V, F = block()
    bottom, top = caps(V)
    angles = [np.pi / 4, np.pi / 2, 3 * np.pi / 4]
    transforms = [twist(V, a) for a in angles]
    print(f"\n== Figure 4.11 block: {len(V)} vertices, {len(F)} triangles; bottom cap {len(bottom)} anchors, "
          f"top cap {len(top)} handles; rotations π/4, π/2, 3π/4 ==")
    t0 = time.perf_counter()
    _core._testing.primal_weights(V, F, "graph")
    qp = time.perf_counter() - t0
    print(f"graph-Laplacian weights alone (one QP per vertex, eq. 4.2): {qp * 1e3:.1f} ms "
          f"= {qp / len(V) * 1e6:.1f} µs/vertex (seed: 55.41 s for the whole initialise, CGAL QP)")
    print(f"{'method':10s} {'initialise':>11s} {'deform':>9s} {'solves/s':>9s} {'restore':>9s} "
          f"{'restore its':>12s} {'inverted π/4,π/2,3π/4':>22s} | seed (Fig 4.12): init, deform, restore")
    figures = {"vertices": len(V)}
    for method in ("uniform", "cotangent", "graph", "dual"):
        init, deform, restore, statuses, outs, _, first, fresh = time_method(V, F, bottom, top, method, transforms,
                                                                             solves=20)
        figures[method] = method_figures(init, deform, restore, statuses, first, fresh)
        inv = ",".join(str(inverted_faces(V, F, o, a)) for o, a in zip(outs, angles))
        its = ",".join(f"{s.iterations}{'' if s.converged else '!'}" for s in statuses) or "---"
        seed = SEED_TABLE[method]
        print(f"{method:10s} {init:10.3f}s {deform * 1e3:7.2f}ms {1 / deform:9.0f} "
              f"{(f'{restore:.3f}s' if restore is not None else '---'):>9s} {its:>12s} {inv:>22s} | "
              f"{seed[0]}, {seed[1]}, {seed[2]}")
    # Dual dragged in π/4 increments (the way the tests run Figure 4.11).
    d = am.Deformer(V, F, bottom, top, "dual")
    row = []
    t0 = time.perf_counter()
    for k, a in enumerate(angles, start=1):
        d.deform(twist(V, a), steps=k)
        out = d.restore(max_iterations=100)
        row.append(f"{inverted_faces(V, F, out, a)} inverted/{folded_edges(V, out, F)} folded ({d.status.iterations} its)")
    print(f"dual, deform(steps = angle/(π/4)) + restore: {'; '.join(row)}; total {time.perf_counter() - t0:.3f}s")
    print("('!' after an iteration count: restore hit its cap before motion < 1e-6)")
    return figures


def bench_surface(methods=("uniform", "cotangent", "graph", "dual")):
    V, F = block(70, 70, 300, (1.0, 1.0, 4.3))
    bottom, top = caps(V)
    T = twist(V, np.pi / 2)
    print(f"\n== ~100k surface: the block refined, {len(V)} vertices, {len(F)} triangles; top cap rotated π/2 ==")
    print(f"{'method':10s} {'initialise':>11s} {'first':>8s} {'deform':>9s} {'solves/s':>9s} {'solve':>8s} "
          f"{'restore':>9s} {'its':>5s} {'factor nnz':>11s}")
    figures = {"vertices": len(V)}
    for method in methods:
        init, deform, restore, statuses, _, d, first, fresh = time_method(V, F, bottom, top, method, [T], solves=5)
        figures[method] = method_figures(init, deform, restore, statuses, first, fresh)
        its = f"{statuses[0].iterations}{'' if statuses[0].converged else '!'}" if statuses else "---"
        print(f"{method:10s} {init:10.2f}s {first:7.2f}s {deform * 1e3:7.1f}ms {1 / deform:9.1f} {fresh:7.2f}s "
              f"{(f'{restore:.2f}s' if restore is not None else '---'):>9s} {its:>5s} {d.info.factor_nonzeros:11d}")
    return figures


def bench_tets(methods=("uniform", "graph", "dual")):
    v, f = icosphere(4)
    m = 40
    times = np.linspace(0, 4, m)
    frames = [v * (1 + 0.2 * np.sin(t)) + [0.5 * t, 0, 0] for t in times]
    man = am.stitch(frames, f, times)
    P, S = np.ascontiguousarray(man.points), np.ascontiguousarray(man.simplices)
    k = len(v)
    anchors = np.r_[np.arange(0, 3 * k), np.arange((m - 3) * k, m * k)]
    mid = np.arange(18 * k, 22 * k)
    handles = mid[P[mid, 0] - P[mid, 0].mean() > 0.7]
    T = am.handle_transform(translation=[0, 0, 0, -1.0], dimension=4)
    print(f"\n== ~100k animation manifold: {len(P)} vertices, {len(S)} tets in R^4; "
          f"{len(anchors)} anchors (3 keyframes at each end), {len(handles)} handles dragged back 1.0 in time ==")
    t0 = time.perf_counter()
    _core._testing.primal_weights(P, S, "graph")
    print(f"graph-Laplacian weights alone: {time.perf_counter() - t0:.2f} s")
    print(f"{'method':10s} {'initialise':>11s} {'first':>8s} {'deform':>9s} {'solves/s':>9s} {'solve':>8s} "
          f"{'restore':>9s} {'its':>5s} {'factor nnz':>11s} | initialise = L + normal + analyse + factorise + rest")
    figures = {"vertices": len(P), "tets": len(S)}
    for method in methods:
        init, deform, restore, statuses, _, d, first, fresh = time_method(P, S, anchors, handles, method, [T],
                                                                          solves=10, restore_cap=30)
        figures[method] = method_figures(init, deform, restore, statuses, first, fresh)
        i = d.info
        phases = [i.laplacian_seconds, i.normal_seconds, i.analyse_seconds, i.factorise_seconds]
        figures[method].update(laplacian_s=phases[0], normal_s=phases[1], analyse_s=phases[2], factorise_s=phases[3],
                               factor_flops=i.factor_flops, factor_nonzeros=i.factor_nonzeros,
                               factor_tiled_blas_calls=i.factor_tiled_blas_calls,
                               factor_openmp_teams_capped=i.factor_openmp_teams_capped)
        its = f"{statuses[0].iterations}{'' if statuses[0].converged else '!'}" if statuses else "---"
        breakdown = " + ".join(f"{p:.2f}" for p in phases + [init - sum(phases)])
        print(f"{method:10s} {init:10.2f}s {first:7.2f}s {deform * 1e3:7.1f}ms {1 / deform:9.1f} {fresh:7.2f}s "
              f"{(f'{restore:.1f}s' if restore is not None else '---'):>9s} {its:>5s} {i.factor_nonzeros:11d} | "
              f"{breakdown} s; {i.factor_flops / 1e9:.0f} GFlop; {i.factor_tiled_blas_calls} BLAS calls by tiles "
              f"on {am.threads()} threads; {i.factor_openmp_teams_capped} CHOLMOD OpenMP teams held to "
              f"{am.threads()} threads", flush=True)
    return figures


def bench_blender(cases):
    try:
        import bpy
    except ImportError:
        print("\n== Blender peer: bpy is not importable here; skipped ==")
        return {"skipped": "bpy is not importable"}

    print(f"\n== Blender {bpy.app.version_string} Laplacian Deform modifier (peer): Hook(handles → Empty) + "
          f"LaplacianDeform(anchors ∪ handles), same mesh and motion ==")
    print(f"{'mesh':10s} {'vertices':>9s} {'bind':>9s} {'per frame':>10s} {'frames/s':>9s} {'inverted 3π/4':>14s}")
    figures = {"blender": bpy.app.version_string}
    for name, (V, F) in cases.items():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bottom, top = caps(V)
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata(V.tolist(), [], F.tolist())
        mesh.update()
        obj = bpy.data.objects.new(name, mesh)
        bpy.context.scene.collection.objects.link(obj)
        empty = bpy.data.objects.new("handle", None)
        bpy.context.scene.collection.objects.link(empty)
        empty.location = (0.0, 0.0, float(V[:, 2].max()))
        constrained = obj.vertex_groups.new(name="constrained")
        constrained.add(np.r_[bottom, top].tolist(), 1.0, "REPLACE")
        handle = obj.vertex_groups.new(name="handle")
        handle.add(top.tolist(), 1.0, "REPLACE")
        hook = obj.modifiers.new("Hook", "HOOK")
        hook.object = empty
        hook.vertex_group = "handle"
        bpy.context.view_layer.update()
        hook.matrix_inverse = empty.matrix_world.inverted()
        lap = obj.modifiers.new("Laplacian", "LAPLACIANDEFORM")
        lap.vertex_group = "constrained"
        bpy.context.view_layer.objects.active = obj
        obj.select_set(True)

        def evaluate():
            depsgraph = bpy.context.evaluated_depsgraph_get()
            depsgraph.update()
            ev = obj.evaluated_get(depsgraph)
            me = ev.to_mesh()
            out = np.empty(len(me.vertices) * 3)
            me.vertices.foreach_get("co", out)
            ev.to_mesh_clear()
            return out.reshape(-1, 3)

        t0 = time.perf_counter()
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.laplaciandeform_bind(modifier=lap.name)
        evaluate()
        bind = time.perf_counter() - t0
        frames = 5
        t0 = time.perf_counter()
        for i in range(1, frames + 1):
            empty.rotation_euler = (0.0, 0.0, 3 * np.pi / 4 * i / frames)
            out = evaluate()
        per_frame = (time.perf_counter() - t0) / frames
        inv = inverted_faces(V, F, out, 3 * np.pi / 4) if out.shape == V.shape else -1
        print(f"{name:10s} {len(V):9d} {bind:8.3f}s {per_frame * 1e3:8.1f}ms {1 / per_frame:9.1f} {inv:14d}")
        figures[name] = {"vertices": len(V), "bind_s": bind, "frame_s": per_frame, "solves_per_s": 1 / per_frame}
    return figures


def machine() -> str:
    """Cores, BLAS and the thread count the core runs on."""
    import os

    blas = _core._testing.openblas_threads()
    blas_text = (f"OpenBLAS (set to {blas} threads; under CHOLMOD one thread per tile, cpp/src/tiled_blas.hpp)"
                 if blas else "BLAS: not OpenBLAS (reference?)")
    return f"{os.cpu_count()} cores, {am.threads()} threads (am.threads()), {blas_text}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="the 2.5k block only")
    parser.add_argument("--no-surface", action="store_true")
    parser.add_argument("--no-tets", action="store_true")
    parser.add_argument("--no-blender", action="store_true")
    parser.add_argument("--surface-methods", default="uniform,cotangent,graph,dual",
                        help="comma-separated methods timed on the ~100k surface")
    parser.add_argument("--tets-methods", default="uniform,graph,dual",
                        help="comma-separated methods timed on the ~100k animation manifold")
    parser.add_argument("--threads", type=int, default=0, help="the core's threads (am.set_threads; 0: every core)")
    add_json_option(parser)
    args = parser.parse_args()
    am.set_threads(args.threads)
    print(f"animanifold Laplacian benchmark; numpy {np.__version__}; {machine()}")
    figures = {"block": bench_block()}
    if not args.quick and not args.no_surface:
        figures["surface"] = bench_surface(args.surface_methods.split(","))
    if not args.no_blender:
        cases = {"block": block()}
        if not args.quick and not args.no_surface:
            cases["surface"] = block(70, 70, 300, (1.0, 1.0, 4.3))
        figures["blender_modifier"] = bench_blender(cases)
    if not args.quick and not args.no_tets:
        figures["tets"] = bench_tets(args.tets_methods.split(","))
    write_json(args.json, figures)


if __name__ == "__main__":
    main()
