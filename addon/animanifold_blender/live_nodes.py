"""The geometry-nodes modifier that plays a topology interval without the add-on's help.

The graph mirrors one core function, ``Slicer::interval_frame`` (slice.hpp;
am.AnimationManifold.interval_frame): between two vertex times of a manifold
every frame has the same faces and each vertex slides along one manifold edge,
so its position (and UV) is affine in the frame: p(t) = p(t0) + (t - t0) * rate,
with the rates the core gives. playback.py writes the cut once per interval (its
frame t0, the interval's middle; am.interval_cuts.interval_cut) with `am_rate` (and
`am_uv` / `am_uv_rate`) point attributes; the node group "Animanifold Live"
reads the Scene Time and evaluates that formula for the vertices and the UV
map, so the object plays without the handler. It lives in Blender's graph, not
in Python, because Blender 4.2+ then plays, renders and exports the frames with
no Python call per frame; tests/blender/test_live_modifier.py checks it against
the core's interval frame.

With the handler, integer frames cost it less: rebuilding the UV map here is
most of a frame's cost (600k corners for a 50k-triangle source, six per vertex;
the fields are evaluated on the corners, and Named Attribute reads no float2, so
the values pass through float3 conversions), and moving 100k vertices most of
the rest. So on integer frames the handler copies the frame, kept per frame
(am.cut_cache), into the mesh's positions and UV map and sets Frame to it; at Frame
the group passes the mesh through. On other frames (subframes, motion blur, no
add-on) it moves the vertices from Frame and rebuilds the UV map from Cut Frame.

Modifier inputs (set by playback.py only):
  Active      off while the mesh holds a frame as it is (vertex times, sweeps,
              smoothing, custom normals): the geometry passes through;
  Frame       the frame the mesh's positions and UV map hold: at it, the mesh
              passes through (less the attributes below);
  Cut Frame   the frame `am_uv` holds (t0, the cut's);
  Start, End  the interval: the scene frame is clamped to it, so without the
              handler (add-on missing) the object holds the interval's ends
              instead of extrapolating;
  Animate UV  whether the UV map moves (the manifold has UVs);
  UV Map      its name;
  Animate Normals  whether the smooth normals are set from `am_normal` and
              `am_normal_rate` (Blender 4.5+: Set Mesh Normal), as the bake sets them;
  Shown From, Shown To  the scene frames the output is right for; more than SLACK
              frames outside them (a file played without the add-on) the text
              WARNING is shown instead of a wrong pose.

Only playback.py writes the inputs, and every other writer of a manifold object's
mesh turns Active off (release): the UV map is rebuilt from `am_uv`, so Animate
UV on a mesh without it would zero the UVs.

Used from Blender 4.2 (the add-on's target; the group is built with the 4.0+
interface API and tested with bpy 4.5); older Blenders (Debian's 3.4) keep
writing every frame from the handler (playback.py checks SUPPORTED).
"""

from __future__ import annotations

import struct

import bpy

from . import messages

SUPPORTED = bpy.app.version >= (4, 2, 0)
# Blender 4.5+: the modifier sets the smooth normals too (Set Mesh Normal); before, an
# object that shows them is written by the handler.
NORMALS_SUPPORTED = SUPPORTED and hasattr(bpy.types, "GeometryNodeSetMeshNormal")

GROUP_NAME = MODIFIER_NAME = "Animanifold Live"
# Custom property marking the node group as ours (and its layout version), so a
# user's group that happens to have the name is never used or changed.
GROUP_TAG = "animanifold_live"
# 2: Cut Frame, and the mesh passes through at Frame. 3: Animate Normals, Shown From/To
# and the warning. A group of an
# older version is not ours any more: the modifier is pointed at a new one the next time
# a cut is written.
GROUP_VERSION = 3

RATE = "am_rate"  # point, float vector: d position / d frame
UV = "am_uv"  # point, float vector (u, v, 0): the UV at Frame
UV_RATE = "am_uv_rate"  # point, float vector: d UV / d frame
NORMAL = "am_normal"  # point, float vector: the smooth normal at Cut Frame (not normalised)
NORMAL_RATE = "am_normal_rate"  # point, float vector: d normal / d frame
_UV_NOW = "am_uv_now"  # point, inside the group only
ATTRIBUTES = (RATE, UV, UV_RATE, NORMAL, NORMAL_RATE)

# Shown From/To when the mesh is right at every scene time (sweep views, bakes, previews).
ALWAYS = 1e30
# Frames beyond Shown From/To the mesh is still shown (held at the interval's end): a
# render's motion blur steps reach up to a frame away without a frame change.
SLACK = 1.0
WARNING = "animanifold add-on required"
# Point attribute (boolean) of the warning's geometry: how a script tells it from a frame.
WARNING_ATTRIBUTE = "animanifold_add_on_required"

_INPUTS = (  # name, socket type, default
    ("Active", "NodeSocketBool", False),
    ("Frame", "NodeSocketFloat", 0.0),
    ("Cut Frame", "NodeSocketFloat", 0.0),
    ("Start", "NodeSocketFloat", 0.0),
    ("End", "NodeSocketFloat", 0.0),
    ("Animate UV", "NodeSocketBool", False),
    ("UV Map", "NodeSocketString", "UVMap"),
    ("Animate Normals", "NodeSocketBool", False),
    ("Shown From", "NodeSocketFloat", -ALWAYS),
    ("Shown To", "NodeSocketFloat", ALWAYS),
)


def _is_ours(group) -> bool:
    return group is not None and group.get(GROUP_TAG) == GROUP_VERSION


def node_group(create: bool = True):
    """Our node group (shared by every manifold object), built on first use."""
    for group in bpy.data.node_groups:
        if _is_ours(group) and group.library is None:  # by its tag: the user may rename it
            return group
    return _build() if create else None


_IDS: dict = {}


def _identifiers(group) -> dict[str, str]:
    """Input name -> the modifier's property key (walking the interface costs more
    than the rest of a frame's check, so it is kept per group)."""
    key = (group.as_pointer(), group.name_full)
    ids = _IDS.get(key)
    if ids is None:
        ids = _IDS[key] = {item.name: item.identifier for item in group.interface.items_tree
                           if getattr(item, "in_out", None) == "INPUT" and item.socket_type != "NodeSocketGeometry"}
    return ids


def _build():
    """The node group: the graph of the core's interval frame (Slicer::interval_frame),
    p(t) = p(Frame) + (t - Frame) * am_rate and uv(t) = am_uv + (t - Cut Frame) * am_uv_rate
    with t the scene frame clamped to (Start, End); see the module's docstring."""
    group = bpy.data.node_groups.new(GROUP_NAME, "GeometryNodeTree")
    group[GROUP_TAG] = GROUP_VERSION
    iface = group.interface
    iface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    for name, socket_type, default in _INPUTS:
        socket = iface.new_socket(name, in_out="INPUT", socket_type=socket_type)
        socket.default_value = default
    iface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links

    def node(kind, x, y, **props):
        n = nodes.new(kind)
        n.location = (x, y)
        for key, value in props.items():
            setattr(n, key, value)
        return n

    def named(name, x, y):
        n = node("GeometryNodeInputNamedAttribute", x, y, data_type="FLOAT_VECTOR")
        n.inputs["Name"].default_value = name
        return n

    def scale(vector, factor, x, y):
        n = node("ShaderNodeVectorMath", x, y, operation="SCALE")
        links.new(vector, n.inputs[0])
        links.new(factor, n.inputs["Scale"])
        return n.outputs[0]

    inp = node("NodeGroupInput", -1400, 0)
    out = node("NodeGroupOutput", 900, 0)

    # t = clamp(scene frame, Start, End); positions move by rate * (t - Frame), UVs
    # are rebuilt as am_uv + am_uv_rate * (t - Cut Frame).
    time = node("GeometryNodeInputSceneTime", -1400, -400)
    clamp = node("ShaderNodeClamp", -1200, -400, clamp_type="MINMAX")
    links.new(time.outputs["Frame"], clamp.inputs["Value"])
    links.new(inp.outputs["Start"], clamp.inputs["Min"])
    links.new(inp.outputs["End"], clamp.inputs["Max"])

    def since(name, x, y):
        n = node("ShaderNodeMath", x, y, operation="SUBTRACT")
        links.new(clamp.outputs[0], n.inputs[0])
        links.new(inp.outputs[name], n.inputs[1])
        return n.outputs[0]

    # UV: evaluated on the points (a sixth of the corners), then copied to the
    # corners of the UV map. The old UV map is removed first: storing over it would
    # copy its values before overwriting them (a third of the frame's cost).
    uv_now = node("ShaderNodeVectorMath", -600, 300, operation="ADD")
    links.new(named(UV, -1000, 450).outputs["Attribute"], uv_now.inputs[0])
    links.new(scale(named(UV_RATE, -1000, 300).outputs["Attribute"], since("Cut Frame", -1000, 150), -800, 250),
              uv_now.inputs[1])
    on_points = node("GeometryNodeStoreNamedAttribute", -400, 200, data_type="FLOAT_VECTOR", domain="POINT")
    on_points.inputs["Name"].default_value = _UV_NOW
    links.new(inp.outputs["Geometry"], on_points.inputs["Geometry"])
    links.new(uv_now.outputs[0], on_points.inputs["Value"])
    old_uv = node("GeometryNodeRemoveAttribute", -250, 200)
    links.new(on_points.outputs[0], old_uv.inputs["Geometry"])
    links.new(inp.outputs["UV Map"], old_uv.inputs["Name"])
    on_corners = node("GeometryNodeStoreNamedAttribute", -100, 200, data_type="FLOAT2", domain="CORNER")
    links.new(old_uv.outputs[0], on_corners.inputs["Geometry"])
    links.new(inp.outputs["UV Map"], on_corners.inputs["Name"])
    links.new(named(_UV_NOW, -400, 0).outputs["Attribute"], on_corners.inputs["Value"])
    uv_switch = node("GeometryNodeSwitch", 50, 100, input_type="GEOMETRY")
    links.new(inp.outputs["Animate UV"], uv_switch.inputs["Switch"])
    links.new(inp.outputs["Geometry"], uv_switch.inputs["False"])
    links.new(on_corners.outputs[0], uv_switch.inputs["True"])

    # Positions: offset by rate * dt (a mesh without the rate reads zero: no offset).
    move = node("GeometryNodeSetPosition", 200, 0)
    links.new(uv_switch.outputs[0], move.inputs["Geometry"])
    links.new(scale(named(RATE, -400, -250).outputs["Attribute"], since("Frame", -1000, -250), -200, -300),
              move.inputs["Offset"])

    # At Frame the mesh holds the frame (the handler wrote it): it passes through, and
    # the switch's other branch is not evaluated.
    elsewhere = node("FunctionNodeCompare", 200, -350, data_type="FLOAT", operation="NOT_EQUAL")
    links.new(clamp.outputs[0], elsewhere.inputs[0])
    links.new(inp.outputs["Frame"], elsewhere.inputs[1])
    elsewhere.inputs["Epsilon"].default_value = 0.0
    moved = node("GeometryNodeSwitch", 300, 0, input_type="GEOMETRY")
    links.new(elsewhere.outputs[0], moved.inputs["Switch"])
    links.new(inp.outputs["Geometry"], moved.inputs["False"])
    links.new(move.outputs[0], moved.inputs["True"])

    geometry = _normals(nodes, links, node, named, scale, since, inp, moved.outputs[0])

    # The evaluated mesh (render, export, Apply) carries none of our attributes.
    for i, name in enumerate(ATTRIBUTES + (_UV_NOW,)):
        remove = node("GeometryNodeRemoveAttribute", 350 + 100 * i, -150)
        remove.inputs["Name"].default_value = name
        links.new(geometry, remove.inputs["Geometry"])
        geometry = remove.outputs[0]

    active = node("GeometryNodeSwitch", 750, 0, input_type="GEOMETRY")
    links.new(inp.outputs["Active"], active.inputs["Switch"])
    links.new(inp.outputs["Geometry"], active.inputs["False"])
    links.new(geometry, active.inputs["True"])
    links.new(_warning(node, links, inp, time, active.outputs[0]), out.inputs[0])
    return group


def _warning(node, links, inp, time, geometry):
    """Outside Shown From - SLACK .. Shown To + SLACK (a file played without the add-on,
    which writes every frame's cut before it is evaluated), the mesh would hold a frame
    that is not the scene's: the text WARNING is shown in its place instead."""
    low = node("ShaderNodeMath", 400, -1000, operation="SUBTRACT")
    links.new(inp.outputs["Shown From"], low.inputs[0])
    low.inputs[1].default_value = SLACK
    high = node("ShaderNodeMath", 400, -1150, operation="ADD")
    links.new(inp.outputs["Shown To"], high.inputs[0])
    high.inputs[1].default_value = SLACK
    before = node("ShaderNodeMath", 550, -1000, operation="LESS_THAN")
    links.new(time.outputs["Frame"], before.inputs[0])
    links.new(low.outputs[0], before.inputs[1])
    after = node("ShaderNodeMath", 550, -1150, operation="GREATER_THAN")
    links.new(time.outputs["Frame"], after.inputs[0])
    links.new(high.outputs[0], after.inputs[1])
    outside = node("ShaderNodeMath", 700, -1050, operation="MAXIMUM")
    links.new(before.outputs[0], outside.inputs[0])
    links.new(after.outputs[0], outside.inputs[1])
    text = node("GeometryNodeStringToCurves", 400, -1300)
    text.inputs["String"].default_value = WARNING
    text.inputs["Size"].default_value = 0.25
    fill = node("GeometryNodeFillCurve", 550, -1300)
    links.new(text.outputs["Curve Instances"], fill.inputs["Curve"])
    realize = node("GeometryNodeRealizeInstances", 700, -1300)
    links.new(fill.outputs[0], realize.inputs[0])
    tag = node("GeometryNodeStoreNamedAttribute", 850, -1300, data_type="BOOLEAN", domain="POINT")
    tag.inputs["Name"].default_value = WARNING_ATTRIBUTE
    tag.inputs["Value"].default_value = True
    links.new(realize.outputs[0], tag.inputs["Geometry"])
    switch = node("GeometryNodeSwitch", 1000, -300, input_type="GEOMETRY")
    links.new(outside.outputs[0], switch.inputs["Switch"])
    links.new(geometry, switch.inputs["False"])
    links.new(tag.outputs[0], switch.inputs["True"])
    return switch.outputs[0]


def _normals(nodes, links, node, named, scale, since, inp, geometry):
    """The smooth normals, as the bake sets them: normalize(am_normal + am_normal_rate *
    (t - Cut Frame)) per point, set as free custom normals when Animate Normals is on
    (on every frame: the mesh holds positions only at Frame). Blender before 4.5 has no
    node for it: the geometry passes (playback.can_drive keeps such objects)."""
    if not NORMALS_SUPPORTED:
        return geometry
    now = node("ShaderNodeVectorMath", 400, -600, operation="ADD")
    links.new(named(NORMAL, 0, -550).outputs["Attribute"], now.inputs[0])
    links.new(scale(named(NORMAL_RATE, 0, -700).outputs["Attribute"], since("Cut Frame", 0, -850), 200, -750),
              now.inputs[1])
    unit = node("ShaderNodeVectorMath", 550, -600, operation="NORMALIZE")
    links.new(now.outputs[0], unit.inputs[0])
    set_normal = node("GeometryNodeSetMeshNormal", 700, -450, mode="FREE", domain="POINT")
    links.new(geometry, set_normal.inputs["Mesh"])
    links.new(unit.outputs[0], set_normal.inputs["Custom Normal"])
    switch = node("GeometryNodeSwitch", 850, -300, input_type="GEOMETRY")
    links.new(inp.outputs["Animate Normals"], switch.inputs["Switch"])
    links.new(geometry, switch.inputs["False"])
    links.new(set_normal.outputs[0], switch.inputs["True"])
    return switch.outputs[0]


def usable(obj) -> bool:
    """False when the user switched the object's live modifier off (viewport or
    render) or gave the name to another modifier: the handler then writes every
    frame itself."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    return mod is None or (mod.type == "NODES" and mod.show_viewport and mod.show_render)


def ensure_modifier(obj):
    """The object's live modifier, added first in the stack (before anything the user
    stacks on the slice) and pointed at our node group if it lost it."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None or mod.type != "NODES":
        if mod is not None:  # a modifier of another kind with our name: not ours to change
            raise RuntimeError(f"'{obj.name}' has {messages.with_article(mod.type.lower().replace('_', ' '))} modifier named '{MODIFIER_NAME}'")
        mod = obj.modifiers.new(MODIFIER_NAME, "NODES")
        if len(obj.modifiers) > 1:
            obj.modifiers.move(len(obj.modifiers) - 1, 0)
        mod.show_expanded = False
        # Edit Mode draws the cage where the frame is (the mesh holds another frame of the interval).
        mod.show_in_editmode = mod.show_on_cage = True
    if not _is_ours(mod.node_group):
        mod.node_group = node_group()
    return mod


def _same(stored, value) -> bool:
    # Float sockets keep single precision: compare as the modifier stores them.
    if isinstance(value, float):
        return isinstance(stored, float) and struct.pack("f", stored) == struct.pack("f", value)
    return stored == value


def _set(obj, mod, values: dict) -> None:
    """Writes the inputs that differ (an unchanged modifier is not re-evaluated)."""
    ids = _identifiers(mod.node_group)
    changed = False
    for name, value in values.items():
        key = ids[name]
        if not _same(mod.get(key), value):
            mod[key] = value
            changed = True
    if changed:
        obj.update_tag()


def drive(obj, frame: float, cut_frame: float, start: float, end: float, uv_name: str | None,
          normals: bool = False) -> None:
    """Turns the modifier on for the cut of the interval (start, end) at `cut_frame` just
    written, the mesh showing `frame`; `uv_name` names its UV map (None without UVs);
    `normals`: the cut carries smooth normals and their rates (NORMAL, NORMAL_RATE)."""
    mod = ensure_modifier(obj)
    _set(obj, mod, {"Active": True, "Frame": float(frame), "Cut Frame": float(cut_frame), "Start": float(start),
                    "End": float(end), "Animate UV": uv_name is not None, "UV Map": uv_name or "",
                    "Animate Normals": bool(normals), "Shown From": float(start), "Shown To": float(end)})


def set_frame(obj, frame: float) -> None:
    """The mesh now holds `frame` (the handler copied it in)."""
    _set(obj, obj.modifiers.get(MODIFIER_NAME), {"Frame": float(frame)})


def release(obj, shown: tuple[float, float] | None = None) -> None:
    """The mesh holds its frame as written: the modifier passes it through. `shown`: the
    scene frames (from, to) at which that frame is right (None: at every frame); given,
    the modifier is added where there is none, so that a file opened without the add-on
    shows the WARNING rather than this frame at another time."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if shown is not None and SUPPORTED and (mod is None or mod.type == "NODES"):
        mod = ensure_modifier(obj)
    if mod is not None and _is_ours(mod.node_group):
        low, high = shown if shown is not None else (-ALWAYS, ALWAYS)
        _set(obj, mod, {"Active": False, "Shown From": float(low), "Shown To": float(high)})


# What release() changes: a bake rolled back must leave them as they were (setting the
# object's mode back to LIVE drives the modifier again).
RELEASED_INPUTS = ("Active", "Shown From", "Shown To")


def released_inputs(obj) -> dict | None:
    """The inputs release() would change, as they are now; None where the object has no
    live modifier of ours."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None or mod.type != "NODES" or not _is_ours(mod.node_group):
        return None
    ids = _identifiers(mod.node_group)
    return {name: mod.get(ids[name]) for name in RELEASED_INPUTS}


def drives(obj, start: float, end: float, frame: float | None = None, cut_frame: float | None = None) -> bool:
    """Whether the object's modifier is on, ours, enabled, and plays the interval (start, end)
    from the cut at `cut_frame` with the mesh at `frame` (when given)."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None or not mod.show_viewport or not _is_ours(mod.node_group):
        return False
    ids = _identifiers(mod.node_group)
    return (bool(mod.get(ids["Active"])) and _same(mod.get(ids["Start"]), float(start))
            and _same(mod.get(ids["End"]), float(end))
            and (frame is None or _same(mod.get(ids["Frame"]), float(frame)))
            and (cut_frame is None or _same(mod.get(ids["Cut Frame"]), float(cut_frame))))


def remove_unused_group() -> None:
    """Drops our node group when nothing uses it (after a failed Convert made it)."""
    group = node_group(create=False)
    if group is not None and group.users == 0:
        bpy.data.node_groups.remove(group)
