"""Operator: Morph Selected (chapters 5 and 8).

Two selected mesh objects (the active one is the target) become one manifold
object that is the source at the start frame and the target at the end
frame, in world space (the objects' transforms align them), played live and
baked like a converted action. Validity (§8.3) is checked and reported; the
sources are hidden, never changed; on failure nothing is added.
"""

from __future__ import annotations

import os
import tempfile
import uuid

import bpy
import numpy as np
from bpy.props import BoolProperty, IntProperty
from bpy.types import Operator

from . import live
from ._lib import am
from .ops_skeleton import closed_triangle_mesh
from .operators import _unique_object_name

STAGES = ("conforming", "fill", "strip", "boundary", "validity")


def world_mesh(context, obj) -> tuple[np.ndarray, np.ndarray]:
    vertices, faces = closed_triangle_mesh(context, obj)
    m = np.array(obj.matrix_world, dtype=np.float64)
    world = vertices @ m[:3, :3].T + m[:3, 3]
    if np.linalg.det(m[:3, :3]) < 0:  # a mirroring transform turns the faces inside out
        faces = faces[:, [1, 0, 2]]
    return world, np.ascontiguousarray(faces, dtype=np.int32)


def cache_path_for(name: str) -> tuple[str, str, str | None]:
    """(path stored on the object, absolute path, note): beside the .blend, or a temporary folder."""
    stem = bpy.path.clean_name(name)
    if bpy.data.filepath:
        folder = os.path.dirname(bpy.data.filepath)
        blend_stem = bpy.path.clean_name(os.path.splitext(os.path.basename(bpy.data.filepath))[0])
        filename = f"{blend_stem}.{stem}.amf"
        return "//" + filename, os.path.join(folder, filename), None
    folder = os.path.join(tempfile.gettempdir(), "animanifold")
    absolute = os.path.join(folder, f"{stem}.{uuid.uuid4().hex[:8]}.amf")
    return absolute, absolute, (f"The .blend is not saved: the morph cache is in the temporary folder {folder}; "
                                "save the .blend and morph again to keep the cache beside it")


class ANIMANIFOLD_OT_morph_selected(Operator):
    """Morph from the selected mesh object to the active one over a frame range"""

    bl_idname = "animanifold.morph_selected"
    bl_label = "Morph Selected"
    bl_options = {"REGISTER", "UNDO"}

    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=48)

    @classmethod
    def poll(cls, context):
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        selected = [o for o in context.selected_objects if o.type == "MESH"]
        if len(selected) != 2 or context.active_object not in selected:
            cls.poll_message_set("Select two mesh objects: the source, then the target (active)")
            return False
        return True

    def execute(self, context):
        target = context.active_object
        source = next(o for o in context.selected_objects if o is not target)
        scene = context.scene
        start, end = (scene.frame_start, scene.frame_end) if self.use_scene_range else (self.frame_start, self.frame_end)
        if end <= start:
            self.report({"ERROR"}, f"the frame range {start}–{end} is empty: the end frame must be after the start")
            return {"CANCELLED"}
        name = _unique_object_name(f"{source.name}_to_{target.name}")
        stored, absolute, note = cache_path_for(name)
        wm = context.window_manager
        wm.progress_begin(0, len(STAGES) + 1)
        created = []
        try:
            vs, fs = world_mesh(context, source)
            vt, ft = world_mesh(context, target)
            manifold = am.morph((vs, fs), (vt, ft), t0=float(start), t1=float(end),
                                progress=lambda stage, fraction: wm.progress_update(int(fraction * len(STAGES))) or True)
            manifold.metadata.update({"source_object": source.name, "target_object": target.name,
                                      "frame_range": [float(start), float(end)], "blender": bpy.app.version_string})
            am.save(manifold, absolute)
            created.append(absolute)
            new = self._create_object(context, source, target, name, stored, absolute, manifold, start, end)
        except ValueError as e:  # the core names the input and what is wrong with it
            self._undo(created)
            message = str(e).replace("the source", f"the source '{source.name}'").replace("the target", f"the target '{target.name}'")
            self.report({"ERROR"}, f"Morph failed: {message}")
            return {"CANCELLED"}
        except Exception as e:  # the mesher or Qhull failed, or a bug: report, nothing left behind
            self._undo(created)
            self.report({"ERROR"}, f"Morph failed: {type(e).__name__}: {e}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()

        validity = manifold.validity
        if note:
            self.report({"WARNING"}, note)
        if not validity["ends_reproduced"] or validity["inverted_simplices"]:
            self.report({"WARNING"}, f"'{new.name}': the morph is not fully valid: end frames off by "
                                     f"{validity['source_distance']:.2g} / {validity['target_distance']:.2g} of the size, "
                                     f"{validity['inverted_simplices']} inverted simplices")
        if not validity.get("holes_preserved", True):
            self.report({"WARNING"}, f"'{new.name}': the holes both inputs share could not be cut out of "
                                     f"{len(validity['hole_errors'])} checked frames (those frames show uncut)")
        if not manifold.check()["is_oriented_manifold"]:
            self.report({"WARNING"}, f"'{new.name}': some in-between frames pinch (not a clean surface): shapes of "
                                     "different topology need the skeleton method of §8.6, which is not available yet")
        self.report({"INFO"}, f"'{new.name}': {len(manifold.simplices)} tets, frames {start}–{end}, cache {stored}")
        return {"FINISHED"}

    @staticmethod
    def _undo(created):
        for path in created:
            live.forget(path)
            try:
                os.unlink(path)
            except OSError:
                pass

    @staticmethod
    def _create_object(context, source, target, name, stored, absolute, manifold, start, end):
        mesh = bpy.data.meshes.new(name)
        for slot in source.material_slots:
            mesh.materials.append(slot.material)
        new = bpy.data.objects.new(name, mesh)  # world-space geometry: identity transform
        (source.users_collection[0] if source.users_collection else context.scene.collection).objects.link(new)
        settings = new.animanifold
        settings.frame_start, settings.frame_end = float(start), float(end)
        settings.source = source
        lo, hi = manifold.bounding_box
        settings.time_scale = 2.0 * (float(np.linalg.norm((hi - lo)[:3])) or 1.0) / max(float(end - start), 1.0)
        settings.sweep_value = float((lo[0] + hi[0]) / 2)
        settings.cache_path = stored
        settings.is_manifold = True
        try:
            live.remember(absolute, manifold)
            live.update_object(new, live.scene_frame(context.scene))
        except BaseException:
            bpy.data.objects.remove(new)
            bpy.data.meshes.remove(mesh)
            raise
        context.scene.render.use_lock_interface = True  # live updates during renders (see operators.py)
        for obj in (source, target):
            obj.hide_render = True
            if obj.name in context.view_layer.objects:
                obj.hide_set(True)
                obj.select_set(False)
        new.select_set(True)
        context.view_layer.objects.active = new
        return new


classes = (ANIMANIFOLD_OT_morph_selected,)
