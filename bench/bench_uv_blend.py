"""Playback cost of a 100k-vertex / ~200k-triangle / ~600k-corner mesh whose positions
and corner UVs blend linearly with s = (frame - 1) / 47, bpy 4.5.

    python3 bench/bench_uv_blend.py CANDIDATE [--loops 3] [--check]

Issue 3's question: can the live frame's UV map (it changes at every frame: the slice's
vertices on the prisms' diagonals slide between keyframe vertices with different UVs) be
produced faster than the add-on's copy path, with exact UVs? Run each candidate in a fresh
process on an idle machine (the figures of the session-4 note: none with exact UVs under
~0.64 ms a frame, against ~0.5 ms for the source and the baked object).

Candidates:
  sk_static     shape key (driven, simple expression) positions, static UVs (reference)
  copy          frame_change_pre handler: foreach_set precomputed positions + UVs (reference)
  sk_dt_mix     shape key + Data Transfer (UV, TOPOLOGY, mix_mode REPLACE (the only one 4.5 offers for UV), mix_factor driven = s)
  sk_dt_add     shape key + Data Transfer (helper UV = UV1-UV0, mix_mode ADD forced via COLOR_CORNER, factor = s)
  sk_dt_forcemix  as sk_dt_add with helper UV = UV1 and mix_mode MIX forced
  sk_gn_mix     shape key + GN: Store FLOAT2 CORNER UVMap = mix(uv0, uv1, s) (float3 corner attrs)
  sk_gn_fma     shape key + GN: UVMap = uv0 + s * duv (float3 corner attrs), Multiply Add
  sk_gn_2d      shape key + GN: Named Attribute FLOAT_VECTOR reads of FLOAT2 attrs (conversion)
  sk_gn_mixrm   as sk_gn_mix, the old UVMap removed (Remove Named Attribute) before the store
  gn_pos        GN only: Set Position offset = s * (B - A) (point float3 attr), static UVs
  gn_pos_mix    one GN modifier: positions as gn_pos and UVs as sk_gn_mix (no shape key)
  gn_pos_mixrm  as gn_pos_mix with the old UVMap removed first
  gn_pos_fmarm  positions as gn_pos, UVs as sk_gn_fma with the old UVMap removed first
  copy_gnpass   copy + a pass-through geometry-nodes modifier
  copy_live     copy + the add-on's "Animanifold Live" group (live_nodes._build, read-only import), Frame set
                by the handler each frame as live_nodes.set_frame does (the group passes through)
  sk_gn_only    shape key + GN that stores nothing (GN modifier overhead alone)
  sk_gn_pt      shape key + GN: UVMap (CORNER) = mix(uv0, uv1, s) of POINT float3 attrs, the old
                UVMap removed first (the slice gives every vertex one UV, so the blend runs on the
                100k points and Blender spreads it to the 600k corners)
  gn_pos_pt     one GN modifier: positions as gn_pos and UVs as sk_gn_pt (no shape key)

Each run: 48 frames x loops frame_set, after each frame the evaluated mesh is read
(len(polygons)) as bench/bench_playback.py does; per-frame seconds of the loops after the
first are kept, the median is reported. --check compares evaluated positions and UVs with
(1-s)A + sB and (1-s)UV0 + sUV1 at a few frames.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

import bpy
import numpy as np

from bench_playback import playback_fps  # noqa: E402  (bench/ is the script's folder)

NX, NY = 250, 400  # 100,000 vertices, 2*249*399 = 198,702 triangles, 596,106 corners
F0, F1 = 1, 48
EXPR = f"(frame - {F0}) / {F1 - F0}"


def s_of(frame):
    return (frame - F0) / (F1 - F0)


def build_mesh(name="live"):
    rng = np.random.default_rng(1)
    xs, ys = np.meshgrid(np.arange(NX, dtype=np.float32), np.arange(NY, dtype=np.float32), indexing="xy")
    A = np.stack([xs.ravel() / NX, ys.ravel() / NY, np.zeros(NX * NY, np.float32)], 1).astype(np.float32)
    A += rng.standard_normal(A.shape).astype(np.float32) * 1e-3
    B = (A + rng.standard_normal(A.shape).astype(np.float32) * 0.01).astype(np.float32)
    idx = np.arange(NX * NY).reshape(NY, NX)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    T = len(tris)
    me = bpy.data.meshes.new(name)
    me.vertices.add(NX * NY)
    me.vertices.foreach_set("co", A.ravel())
    me.loops.add(3 * T)
    me.loops.foreach_set("vertex_index", tris.ravel())
    me.polygons.add(T)
    me.polygons.foreach_set("loop_start", np.arange(0, 3 * T, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(T, 3, np.int32))
    me.update(calc_edges=True)
    me.validate()
    assert len(me.vertices) == NX * NY and len(me.polygons) == T
    UV0 = rng.random((3 * T, 2), dtype=np.float32)
    UV1 = rng.random((3 * T, 2), dtype=np.float32)
    layer = me.uv_layers.new(name="UVMap")
    layer.uv.foreach_set("vector", UV0.ravel())
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj, A, B, UV0, UV1


def add_shape_key(obj, B):
    obj.shape_key_add(name="Basis", from_mix=False)
    key = obj.shape_key_add(name="B", from_mix=False)
    key.data.foreach_set("co", B.ravel())
    key.value = 0.0
    fc = key.driver_add("value")
    fc.driver.type = "SCRIPTED"
    fc.driver.expression = EXPR
    while fc.modifiers:
        fc.modifiers.remove(fc.modifiers[0])
    return fc.driver


def drive(id_, path, expr=EXPR):
    fc = id_.driver_add(path)
    fc.driver.type = "SCRIPTED"
    fc.driver.expression = expr
    while fc.modifiers:
        fc.modifiers.remove(fc.modifiers[0])
    return fc.driver


def helper_object(obj, uv):
    me = obj.data.copy()
    if me.shape_keys is not None:
        pass  # copy() of a mesh shares the Key? make sure the helper has none
    h = bpy.data.objects.new(obj.name + "_uvsrc", me)
    bpy.context.scene.collection.objects.link(h)
    if h.data.shape_keys is not None:
        h.shape_key_clear()
    h.data.uv_layers["UVMap"].uv.foreach_set("vector", uv.ravel())
    h.hide_viewport = False  # evaluated (the modifier needs its evaluated mesh)
    h.hide_render = True
    return h


def data_transfer(obj, helper, mix_mode):
    m = obj.modifiers.new("UVBlend", "DATA_TRANSFER")
    m.object = helper
    m.use_object_transform = False
    m.use_loop_data = True
    if mix_mode != "REPLACE":  # 4.5 offers only REPLACE for UV: set it while another type is chosen
        m.data_types_loops = {"COLOR_CORNER"}
        m.mix_mode = mix_mode
    m.data_types_loops = {"UV"}
    m.loop_mapping = "TOPOLOGY"
    m.layers_uv_select_src = "ALL"  # or name-based
    m.layers_uv_select_dst = "NAME"
    if mix_mode == "REPLACE":
        m.mix_mode = mix_mode
    m.mix_factor = 0.0
    drv = drive(m, "mix_factor")
    return m, drv


def gn_group(kind):
    g = bpy.data.node_groups.new("UVBlend_" + kind, "GeometryNodeTree")
    g.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    sock = g.interface.new_socket("S", in_out="INPUT", socket_type="NodeSocketFloat")
    sock.default_value = 0.0
    g.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    N, L = g.nodes, g.links
    inp, out = N.new("NodeGroupInput"), N.new("NodeGroupOutput")
    if kind == "only":
        L.new(inp.outputs["Geometry"], out.inputs["Geometry"])
        return g
    geo = inp.outputs["Geometry"]
    if kind.startswith("pos"):  # positions: Set Position offset = s * am_d (am_d = B - A, point float3)
        d = N.new("GeometryNodeInputNamedAttribute")
        d.data_type = "FLOAT_VECTOR"
        d.inputs["Name"].default_value = "am_d"
        sc = N.new("ShaderNodeVectorMath")
        sc.operation = "SCALE"
        L.new(d.outputs["Attribute"], sc.inputs[0])
        L.new(inp.outputs["S"], sc.inputs["Scale"])
        sp = N.new("GeometryNodeSetPosition")
        L.new(geo, sp.inputs["Geometry"])
        L.new(sc.outputs[0], sp.inputs["Offset"])
        geo = sp.outputs[0]
        kind = kind[len("pos"):].lstrip("_")
        if not kind:
            L.new(geo, out.inputs["Geometry"])
            return g
    if kind == "pt":  # point-domain blend: the mix of "mix", the removal of "rm"
        kind = "mixrm"
    if kind.endswith("rm"):  # remove the old UV map first (no copy of its values into the new one)
        rm = N.new("GeometryNodeRemoveAttribute")
        rm.inputs["Name"].default_value = "UVMap"
        L.new(geo, rm.inputs["Geometry"])
        geo = rm.outputs[0]
        kind = kind[:-2]

    def named(name):
        n = N.new("GeometryNodeInputNamedAttribute")
        n.data_type = "FLOAT_VECTOR"
        n.inputs["Name"].default_value = name
        return n.outputs["Attribute"]

    store = N.new("GeometryNodeStoreNamedAttribute")
    store.data_type = "FLOAT2"
    store.domain = "CORNER"
    store.inputs["Name"].default_value = "UVMap"
    L.new(geo, store.inputs["Geometry"])
    if kind in ("mix", "2d"):
        mix = N.new("ShaderNodeMix")
        mix.data_type = "VECTOR"
        mix.clamp_factor = False
        L.new(inp.outputs["S"], mix.inputs[0])  # Factor (float)
        a, b = ("am_uv0", "am_uv1") if kind == "mix" else ("UVMap", "am_uv1_2d")
        L.new(named(a), mix.inputs[4])  # A (vector)
        L.new(named(b), mix.inputs[5])  # B (vector)
        value = mix.outputs[1]  # Result (vector)
    elif kind == "fma":
        fma = N.new("ShaderNodeVectorMath")
        fma.operation = "MULTIPLY_ADD"
        L.new(named("am_duv"), fma.inputs[0])
        L.new(inp.outputs["S"], fma.inputs[1])  # float -> vector (s, s, s)
        L.new(named("am_uv0"), fma.inputs[2])
        value = fma.outputs[0]
    L.new(value, store.inputs["Value"])
    L.new(store.outputs[0], out.inputs["Geometry"])
    return g


def gn_modifier(obj, kind):
    m = obj.modifiers.new("UVBlend", "NODES")
    m.node_group = gn_group(kind)
    ident = m.node_group.interface.items_tree["S"].identifier
    drv = drive(m, f'["{ident}"]')
    return m, drv


def vec3(a2):
    return np.concatenate([a2, np.zeros((len(a2), 1), np.float32)], 1).astype(np.float32)


def setup(candidate):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = F0, F1
    obj, A, B, UV0, UV1 = build_mesh()
    if candidate.endswith("_pt"):  # one UV per vertex (as in a slice): corners take their vertex's
        rng = np.random.default_rng(2)
        PUV0, PUV1 = (rng.random((len(A), 2), dtype=np.float32) for _ in range(2))
        corner_vertex = np.empty(len(obj.data.loops), np.int32)
        obj.data.loops.foreach_get("vertex_index", corner_vertex)
        UV0, UV1 = PUV0[corner_vertex], PUV1[corner_vertex]
        obj.data.uv_layers["UVMap"].uv.foreach_set("vector", UV0.ravel())
    drivers = []
    info = {}
    if not candidate.startswith(("copy", "gn_")):
        drivers.append(add_shape_key(obj, B))
    if candidate in ("sk_dt_mix", "sk_dt_add", "sk_dt_forcemix"):
        h = helper_object(obj, (UV1 - UV0) if candidate == "sk_dt_add" else UV1)
        m, d = data_transfer(obj, h, {"sk_dt_mix": "REPLACE", "sk_dt_add": "ADD", "sk_dt_forcemix": "MIX"}[candidate])
        drivers.append(d)
        info["mix_mode"] = m.mix_mode or "(not a UV enum item: forced)"
    elif candidate.startswith(("sk_gn_", "gn_")):
        kind = candidate.split("gn_", 1)[1]
        me = obj.data
        if kind.startswith("pos"):
            me.attributes.new("am_d", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", (B - A).ravel())
        if kind.endswith("pt"):
            me.attributes.new("am_uv0", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", vec3(PUV0).ravel())
            me.attributes.new("am_uv1", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", vec3(PUV1).ravel())
        if kind.rstrip("rm").endswith(("mix", "fma")):
            kind = kind.rstrip("rm")
        if kind.endswith(("mix", "fma")):
            kind = kind[-3:]
        if kind in ("mix", "fma"):
            me.attributes.new("am_uv0", "FLOAT_VECTOR", "CORNER").data.foreach_set("vector", vec3(UV0).ravel())
        if kind == "mix":
            me.attributes.new("am_uv1", "FLOAT_VECTOR", "CORNER").data.foreach_set("vector", vec3(UV1).ravel())
        if kind == "fma":
            me.attributes.new("am_duv", "FLOAT_VECTOR", "CORNER").data.foreach_set("vector", vec3(UV1 - UV0).ravel())
        if kind == "2d":
            me.attributes.new("am_uv1_2d", "FLOAT2", "CORNER").data.foreach_set("vector", UV1.ravel())
        m, d = gn_modifier(obj, candidate.split("gn_", 1)[1])
        drivers.append(d)
    elif candidate in ("copy", "copy_gnpass", "copy_live"):
        frames = range(F0, F1 + 1)
        pos = {f: np.ascontiguousarray(((1 - s_of(f)) * A + s_of(f) * B).astype(np.float32).ravel()) for f in frames}
        uvs = {f: np.ascontiguousarray(((1 - s_of(f)) * UV0 + s_of(f) * UV1).astype(np.float32).ravel()) for f in frames}
        me = obj.data

        def handler(scene_, depsgraph=None):
            f = scene_.frame_current
            if f not in pos:
                return
            me.attributes["position"].data.foreach_set("vector", pos[f])
            me.uv_layers["UVMap"].uv.foreach_set("vector", uvs[f])
            v = me.vertices[0]
            v.co = v.co  # positions-changed tag (as live.tag_positions_changed)
            me.update_tag()

        set_frame = None
        if candidate == "copy_gnpass":  # + a pass-through geometry-nodes modifier
            obj.modifiers.new("Pass", "NODES").node_group = gn_group("only")
        elif candidate == "copy_live":  # + the add-on's "Animanifold Live" group, at Frame (passes through)
            root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
            sys.path[:0] = [os.path.join(root, "python"), os.path.join(root, "addon")]
            from animanifold_blender import live_nodes
            mod = obj.modifiers.new(live_nodes.MODIFIER_NAME, "NODES")
            mod.node_group = live_nodes._build()
            ids = live_nodes._identifiers(mod.node_group)
            for k, v in {"Active": True, "Frame": float(F0), "Cut Frame": float(F0), "Start": float(F0),
                         "End": float(F1), "Animate UV": True, "UV Map": "UVMap"}.items():
                mod[ids[k]] = v
            # am_uv / am_uv_rate / am_rate point attributes as the add-on keeps them (zero rates)
            for name in live_nodes.ATTRIBUTES:
                me.attributes.new(name, "FLOAT_VECTOR", "POINT")

            def set_frame(f):
                if mod[ids["Frame"]] != float(f):
                    mod[ids["Frame"]] = float(f)
                    obj.update_tag()

        def handler_full(scene_, depsgraph=None):
            handler(scene_, depsgraph)
            if set_frame is not None and scene_.frame_current in pos:
                set_frame(scene_.frame_current)

        # frame_change_pre, as the add-on writes (handlers.py): one evaluation per frame
        bpy.app.handlers.frame_change_pre.append(handler_full)
        info["handler"] = True
    for d in drivers:
        d.expression = d.expression  # re-validate
    info["simple_expression"] = [bool(d.is_simple_expression) for d in drivers]
    info["drivers_valid"] = [bool(d.is_valid) for d in drivers]
    return scene, obj, A, B, UV0, UV1, info


def evaluated(obj):
    dg = bpy.context.evaluated_depsgraph_get()
    return obj.evaluated_get(dg).data


def check(scene, obj, A, B, UV0, UV1):
    out = {}
    for f in (F0, 7, 24, 31, F1):
        scene.frame_set(f)
        me = evaluated(obj)
        s = s_of(f)
        n = len(me.vertices)
        co = np.empty(3 * n, np.float32)
        me.attributes["position"].data.foreach_get("vector", co)
        layer = me.uv_layers.get("UVMap")
        res = {"uv_maps": [l.name for l in me.uv_layers], "loops": len(me.loops)}
        if layer is None:
            res["uv"] = "no UVMap"
        else:
            uv = np.empty(2 * len(me.loops), np.float32)
            layer.uv.foreach_get("vector", uv)
            want = ((1 - s) * UV0.astype(np.float64) + s * UV1).ravel()
            err = np.abs(uv - want)
            res["uv_max_err"] = float(err.max())
            # what it is instead: least-squares fit uv = alpha*UV0 + beta*UV1
            M = np.stack([UV0.ravel().astype(np.float64), UV1.ravel().astype(np.float64)], 1)
            coef, *_ = np.linalg.lstsq(M, uv.astype(np.float64), rcond=None)
            res["uv_fit_alpha_beta"] = [round(float(c), 6) for c in coef]
        wantp = ((1 - s) * A.astype(np.float64) + s * B).ravel()
        res["pos_max_err"] = float(np.abs(co - wantp).max())
        res["s"] = round(s, 6)
        out[f] = res
    return out


def play(scene, obj, loops):
    """Per-frame seconds of the warm loops and the fps of every loop (the first one cold),
    timed as bench_playback.py times its objects."""
    frames = list(range(F0, F1 + 1))
    probe = lambda: len(evaluated(obj).polygons)  # noqa: E731
    cold = playback_fps(scene, frames, 1, probe)
    per = []
    warm = playback_fps(scene, frames, max(loops - 1, 1), probe, per)
    return per, cold + warm


def main():
    p = argparse.ArgumentParser()
    p.add_argument("candidate")
    p.add_argument("--loops", type=int, default=3)
    p.add_argument("--check", action="store_true")
    args = p.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    scene, obj, A, B, UV0, UV1, info = setup(args.candidate)
    load0 = os.getloadavg()[0]
    per, loop_fps = play(scene, obj, args.loops)
    med = statistics.median(per)
    result = {
        "candidate": args.candidate,
        "blender": bpy.app.version_string,
        "verts": len(obj.data.vertices), "tris": len(obj.data.polygons), "corners": len(obj.data.loops),
        "median_ms": round(1000 * med, 3), "fps_median": round(1 / med, 1),
        "warm_loop_fps": [round(x, 1) for x in loop_fps[1:]], "cold_loop_fps": round(loop_fps[0], 1),
        "p10_p90_ms": [round(1000 * float(np.percentile(per, q)), 3) for q in (10, 90)],
        "load_before": round(load0, 2), "load_after": round(os.getloadavg()[0], 2),
        **info,
    }
    if args.check:
        result["check"] = check(scene, obj, A, B, UV0, UV1)
    print("RESULT " + json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
    sys.stdout.flush()
    os._exit(0)  # bpy can hang in its exit handlers (seen with a frame_change_post handler registered)
