"""Operators: Convert (keyframed action → manifold object) and Bake.

Both check everything that can fail before touching the scene, report every
failure with self.report({'ERROR'}, ...) and leave the scene as it was: on an
error, whatever they created is removed again and the current frame restored.
"""

from __future__ import annotations

import math
import os
import tempfile
import uuid

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty
from bpy.types import Operator
from mathutils import Matrix

from . import bake, live, live_nodes, sampling
from ._lib import am
from .properties import _BLEND_RELATIVE, EXPORT_ITEMS, SAMPLING_ITEMS


class OperatorError(am.Error):
    """A failure to report to the user (the message is the report)."""


def _option(op, settings, name, settings_name=None):
    """The operator's property when set by the caller, else the scene setting."""
    if op.properties.is_property_set(name):
        return getattr(op, name)
    return getattr(settings, settings_name or name)


class _Progress:
    def __init__(self, context, total):
        self.wm = context.window_manager
        self.total = max(int(total), 1)
        self.wm.progress_begin(0, self.total)

    def __call__(self, done):
        self.wm.progress_update(min(int(done), self.total))

    def end(self):
        self.wm.progress_end()


def _blend_dir() -> str | None:
    path = bpy.data.filepath
    return os.path.dirname(path) if path else None


def _unique_object_name(base: str) -> str:
    name, i = base, 0
    while name in bpy.data.objects or name in bpy.data.meshes:
        i += 1
        name = f"{base}.{i:03d}"
    return name


def _is_relative(path: str) -> bool:
    return path.startswith("//")


class ANIMANIFOLD_OT_convert_action(Operator):
    """Turn the active object's keyframed animation into an animation manifold object"""

    bl_idname = "animanifold.convert_action"
    bl_label = "Convert to Manifold"
    bl_options = {"REGISTER", "UNDO"}

    sampling: EnumProperty(name="Sampling", items=SAMPLING_ITEMS, default="KEYFRAMES")
    step: IntProperty(name="N", default=5, min=1)
    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=250)
    cache_directory: StringProperty(name="Cache Folder", subtype="DIR_PATH", options=_BLEND_RELATIVE)

    @classmethod
    def poll(cls, context):
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        if context.active_object is None:
            cls.poll_message_set("Select the object to convert")
            return False
        return True

    def execute(self, context):
        try:
            return self._execute(context)
        except (OperatorError, sampling.SamplingError) as e:
            self.report({"ERROR"}, str(e))
        except (ValueError, RuntimeError, OSError) as e:  # from the core or the file system
            self.report({"ERROR"}, f"Convert failed: {e}")
        except Exception as e:  # a bug: still report it, nothing was left behind
            self.report({"ERROR"}, f"Convert failed unexpectedly: {type(e).__name__}: {e}")
        return {"CANCELLED"}

    # -- steps ------------------------------------------------------------------
    def _frame_range(self, context, settings):
        scene = context.scene
        if _option(self, settings, "use_scene_range"):
            return scene.frame_start, scene.frame_end
        return _option(self, settings, "frame_start"), _option(self, settings, "frame_end")

    def _cache_path(self, settings, name):
        """(path stored on the object, absolute path, note for the report)."""
        directory = _option(self, settings, "cache_directory")
        stem = bpy.path.clean_name(name)
        blend = _blend_dir()
        if directory:
            if _is_relative(directory) and blend is None:
                raise OperatorError(
                    f"the cache folder '{directory}' is relative to the .blend, which is not saved yet: "
                    "save the .blend or choose an absolute folder"
                )
            absolute = os.path.join(bpy.path.abspath(directory), stem + ".amf")
            stored = bpy.path.relpath(absolute) if blend is not None else absolute
            return stored, absolute, None
        if blend is not None:
            blend_stem = os.path.splitext(os.path.basename(bpy.data.filepath))[0]
            filename = f"{bpy.path.clean_name(blend_stem)}.{stem}.amf"
            return "//" + filename, os.path.join(blend, filename), None
        folder = os.path.join(tempfile.gettempdir(), "animanifold")
        absolute = os.path.join(folder, f"{stem}.{uuid.uuid4().hex[:8]}.amf")
        note = (f"The .blend is not saved: the manifold cache is in the temporary folder {folder}; "
                "save the .blend and convert again to keep the cache beside it")
        return absolute, absolute, note

    def _execute(self, context):
        scene = context.scene
        settings = scene.animanifold
        obj = context.active_object
        if obj.type != "MESH":
            raise OperatorError(f"'{obj.name}' is a {obj.type.lower()}, not a mesh: only mesh objects can be converted")
        if getattr(obj, "animanifold", None) is not None and obj.animanifold.is_manifold:
            raise OperatorError(f"'{obj.name}' is already a manifold object")
        start, end = self._frame_range(context, settings)
        if end <= start:
            raise OperatorError(f"the frame range {start}–{end} is empty: the end frame must be after the start")
        mode = _option(self, settings, "sampling")
        step = _option(self, settings, "step")
        frames = sampling.sample_frames(obj, start, end, mode, step)

        name = _unique_object_name(f"{obj.name}_manifold")  # its cache file is named after it
        stored, absolute, note = self._cache_path(settings, name)

        progress = _Progress(context, len(frames) + 2)
        try:
            keys = sampling.sample_object(context, obj, frames, progress)
            vertex_attributes = {"source_vertex": keys.source_vertex.astype(np.float64)}
            if keys.smooth.all():  # smooth-shaded: carry the source's vertex normals
                vertex_attributes["normal"] = keys.normals
            if keys.uv is not None:
                vertex_attributes["uv"] = keys.uv
            manifold = am.stitch(
                keys.positions, keys.faces, keys.times, vertex_attributes=vertex_attributes,
                face_attributes={"material_index": keys.material_index, "smooth": keys.smooth},
            )
            manifold.metadata.update({
                "source_object": obj.name,
                "frame_range": [float(start), float(end)],
                "sampling": mode if mode == "KEYFRAMES" else f"EVERY_{step}",
                "uv_map": keys.uv_name,
                "object_motion_baked": bool(keys.moves),
                "blender": bpy.app.version_string,
            })
            progress(len(frames) + 1)
            existed = os.path.exists(absolute)
            am.save(manifold, absolute)
            try:
                new = self._create_object(context, obj, name, stored, absolute, manifold, keys, start, end)
            except BaseException:
                if not existed:
                    try:
                        os.unlink(absolute)
                    except OSError:
                        pass
                live.forget(absolute)
                raise
            progress(len(frames) + 2)
        finally:
            progress.end()

        if note:
            self.report({"WARNING"}, note)
        self.report({"INFO"}, f"'{new.name}': {len(manifold.simplices)} tets from {len(frames)} samples "
                              f"(frames {start}–{end}), cache {stored}")
        return {"FINISHED"}

    def _create_object(self, context, obj, name, stored, absolute, manifold, keys, start, end):
        mesh = new = None
        try:
            mesh = bpy.data.meshes.new(name)
            for slot in obj.material_slots:
                mesh.materials.append(slot.material)
            new = bpy.data.objects.new(name, mesh)
            new.matrix_world = Matrix(keys.matrix_world.tolist())  # the source's world matrix at the first sample
            collections = list(obj.users_collection) or [context.scene.collection]
            for coll in collections:
                coll.objects.link(new)
            settings = new.animanifold
            settings.uv_name = keys.uv_name or "UVMap"
            settings.frame_start = float(start)
            settings.frame_end = float(end)
            settings.source = obj
            lo, hi = manifold.bounding_box
            size = float(np.linalg.norm((hi - lo)[:3])) or 1.0
            settings.time_scale = 2.0 * size / max(float(end - start), 1.0)
            settings.sweep_value = float((lo[0] + hi[0]) / 2)
            settings.cache_path = stored
            settings.is_manifold = True
            live.remember(absolute, manifold)
            live.update_object(new, live.scene_frame(context.scene))
        except BaseException:
            if new is not None:
                bpy.data.objects.remove(new)
            if mesh is not None:
                bpy.data.meshes.remove(mesh)
            live_nodes.remove_unused_group()  # made for the new object's first frame
            raise
        # Rendering an animation from the UI runs frame_change_post while the render
        # thread reads meshes: Blender's "Lock Interface" makes the live update safe.
        context.scene.render.use_lock_interface = True
        # Done: hide the source (never modify or delete it) and select the result.
        obj.hide_render = True
        if obj.name in context.view_layer.objects:
            obj.hide_set(True)
            obj.select_set(False)
        if new.name in context.view_layer.objects:
            new.select_set(True)
            context.view_layer.objects.active = new
        return new


class ANIMANIFOLD_OT_bake(Operator):
    """Bake the active manifold object's frames: a frames collection shown by a node group
    (plays and renders without the add-on), optionally Alembic and an OBJ/PLY sequence"""

    bl_idname = "animanifold.bake"
    bl_label = "Bake Frames"
    bl_options = {"REGISTER", "UNDO"}

    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1, description="First frame (a farm bakes chunks)")
    frame_end: IntProperty(name="End", default=250)
    alembic: BoolProperty(name="Alembic", default=True)
    use_mesh_cache: BoolProperty(name="Use Mesh Sequence Cache", default=False)
    export: EnumProperty(name="Sequence", items=EXPORT_ITEMS, default="NONE")
    directory: StringProperty(name="Folder", subtype="DIR_PATH", options=_BLEND_RELATIVE)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        if obj is None or not getattr(obj, "animanifold", None) or not obj.animanifold.is_manifold:
            cls.poll_message_set("Select a manifold object (made by Convert)")
            return False
        return True

    def execute(self, context):
        try:
            return self._execute(context)
        except (OperatorError, bake.BakeError, am.CacheError, live.SmoothingError) as e:
            self.report({"ERROR"}, str(e))
        except (ValueError, RuntimeError, OSError) as e:
            self.report({"ERROR"}, f"Bake failed: {e}")
        except Exception as e:  # a bug: still report it, the transaction has rolled back
            self.report({"ERROR"}, f"Bake failed unexpectedly: {type(e).__name__}: {e}")
        return {"CANCELLED"}

    def _execute(self, context):
        scene = context.scene
        settings = scene.animanifold
        obj = context.active_object
        live.manifold_for(obj)  # validates the cache before anything changes
        manifold = live.shown_manifold(obj)  # and subdivides it (Smooth settings) before anything changes
        if _option(self, settings, "use_scene_range", "bake_use_scene_range"):
            start, end = scene.frame_start, scene.frame_end
        else:
            start, end = _option(self, settings, "frame_start", "bake_start"), _option(self, settings, "frame_end", "bake_end")
        t0, t1 = manifold.time_range
        first, last = max(start, math.ceil(t0 - 1e-9)), min(end, math.floor(t1 + 1e-9))
        if last < first:
            raise OperatorError(f"the frames {start}–{end} are outside the manifold's frames {t0:g}–{t1:g}: nothing to bake")
        frames = list(range(first, last + 1))

        alembic = _option(self, settings, "alembic", "bake_alembic") and bake.alembic_supported()
        use_cache = _option(self, settings, "use_mesh_cache", "bake_use_mesh_cache")
        export = _option(self, settings, "export", "bake_export")
        directory = _option(self, settings, "directory", "bake_directory") or "//animanifold_bake/"
        if use_cache and not alembic:
            raise OperatorError("a Mesh Sequence Cache needs the Alembic bake, which this Blender "
                                + ("does not support" if not bake.alembic_supported() else "was told to skip"))
        if (alembic or export != "NONE") and _is_relative(directory) and not bpy.data.filepath:
            raise OperatorError(f"the bake folder '{directory}' is relative to the .blend, which is not saved yet: "
                                "save the .blend or choose an absolute folder")
        folder = bpy.path.abspath(directory)
        chunk = "" if (first, last) == (scene.frame_start, scene.frame_end) else f"_{first:06d}-{last:06d}"
        stem = bpy.path.clean_name(obj.name)

        progress = _Progress(context, 2 * len(frames) + 2)
        transaction = bake.NodeGroupBake(obj)
        written = []
        try:
            transaction.apply(frames, progress)
            notes = [f"{len(frames)} frames {first}–{last} (node group)"]
            if alembic:
                path = os.path.join(folder, f"{stem}{chunk}.abc")
                existed = os.path.exists(path)
                bake.export_alembic(context, obj, path, first, last)
                if not existed:
                    written.append(path)
                stored = bpy.path.relpath(path) if bpy.data.filepath and _is_relative(directory) else path
                notes.append(f"Alembic {stored}")
                if use_cache:
                    bake.use_mesh_sequence_cache(obj, path, stored, transaction.new_cache_files)
                    notes.append("shown by a Mesh Sequence Cache modifier")
            progress(len(frames) + 1)
            if export != "NONE":
                files = bake.export_sequence(obj, frames, folder, export, lambda i: progress(len(frames) + 1 + i))
                notes.append(f"{len(files)} {export} files in {folder}")
        except BaseException:
            transaction.rollback()
            for path in written:
                try:
                    os.unlink(path)
                except OSError:
                    pass
            raise
        finally:
            progress.end()
        transaction.commit()
        notes[0] = f"{len(frames)} frames {first}–{last} in collection '{transaction.collection.name}' (node group)"
        if _option(self, settings, "alembic", "bake_alembic") and not bake.alembic_supported():
            notes.append("no Alembic: this Blender was built without it")
        self.report({"INFO"}, f"Baked '{obj.name}': " + "; ".join(notes))
        return {"FINISHED"}


class ANIMANIFOLD_OT_make_live(Operator):
    """Slice the manifold object live again (turn off its bake modifiers)"""

    bl_idname = "animanifold.make_live"
    bl_label = "Back to Live"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and getattr(obj, "animanifold", None) is not None and obj.animanifold.is_manifold \
            and obj.animanifold.mode == "BAKED"

    def execute(self, context):
        obj = context.active_object
        try:
            live.manifold_for(obj)
        except am.CacheError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        for name in (bake.MODIFIER_NAME, bake.CACHE_MODIFIER_NAME):
            mod = obj.modifiers.get(name)
            if mod is not None:
                mod.show_viewport = False
                mod.show_render = False
        obj.animanifold.mode = "LIVE"
        return {"FINISHED"}


classes = (ANIMANIFOLD_OT_convert_action, ANIMANIFOLD_OT_bake, ANIMANIFOLD_OT_make_live)
