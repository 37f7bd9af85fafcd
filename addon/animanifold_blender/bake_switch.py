"""The node-group bake's frame picker for Blender before 3.5, where UV maps do not survive
Realize Instances.

Before 3.5 a UV map is its own kind of layer, not a generic attribute: Realize Instances
builds a new mesh whose UV maps come out as plain FLOAT2 corner attributes, which the
renderers do not take for UV maps (textures sample one texel), and geometry nodes there
cannot store a UV map. So, instead of realising the frame's instance, the group picks the
frame object's own mesh with an Object Info node per frame under a balanced tree of
geometry Switch nodes on the frame index; Object Info hands the mesh through unchanged, UV
maps included. Only the picked branch is evaluated.
"""

from __future__ import annotations

import bpy

# UV maps are generic FLOAT2 attributes from 3.5 on (Realize Instances keeps them).
NEEDS_SWITCH = bpy.app.version < (3, 5, 0)


def _enabled(sockets) -> list:
    return [s for s in sockets if s.enabled]


def link_frames(group, frame_index, objects: list, output) -> None:
    """Links into `group` a tree choosing objects[i]'s mesh where the float socket
    `frame_index` is i (an integer in [0, len(objects))), into the input socket `output`."""
    nodes, links = group.nodes, group.links

    def branch(lo: int, hi: int, depth: int):
        if hi - lo == 1:
            info = nodes.new("GeometryNodeObjectInfo")
            info.location = (-300 - 200 * depth, -400 - 150 * lo)
            info.transform_space = "ORIGINAL"
            info.inputs["Object"].default_value = objects[lo]
            return info.outputs["Geometry"]
        mid = (lo + hi) // 2
        later = nodes.new("ShaderNodeMath")
        later.operation = "GREATER_THAN"
        later.location = (-100 - 200 * depth, -300 - 150 * mid)
        links.new(frame_index, later.inputs[0])
        later.inputs[1].default_value = mid - 0.5
        switch = nodes.new("GeometryNodeSwitch")
        switch.input_type = "GEOMETRY"
        switch.location = (100 - 200 * depth, -300 - 150 * mid)
        choice, if_false, if_true = _enabled(switch.inputs)[:3]
        links.new(later.outputs[0], choice)
        links.new(branch(lo, mid, depth + 1), if_false)
        links.new(branch(mid, hi, depth + 1), if_true)
        return _enabled(switch.outputs)[0]

    links.new(branch(0, len(objects), 0), output)
