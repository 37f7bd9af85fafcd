"""Operator: Morph Selected (chapters 5 and 8).

Two selected mesh objects (the active one is the target) become one manifold
object that is the source at the start frame and the target at the end
frame, in world space (the objects' transforms align them), played live and
baked like a converted action. Validity (§8.3) is checked and reported; the
sources are hidden, never changed; on failure nothing is added (the object is
made by morph_object).

The core solves every morph over a time span proportional to the shapes'
size and maps it onto t0..t1 (the frame range here), so the morph is the same
whatever the range.

Invoked from the interface, the operator is modal: the core runs in a worker
thread (am.MorphJob), a timer shows its stage in the status bar, Esc cancels,
and the object is made in the main thread once the job is done. Executed (a
script, `blender -b`, redo), it blocks with a progress bar.
"""

from __future__ import annotations

import time

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty
from bpy.types import Operator

from . import preferences
from ._lib import am
from .mesh_input import morph_input, morph_looks, world_mesh  # noqa: F401  (world_mesh: the tests' reader)
from .morph_object import BEST_METHOD, METHOD_ITEMS, METHODS, make_morph_object, report_validity  # noqa: F401
from .job_modal import CoreJobModal
from .progress import Progress
from .polls import in_object_mode
from .reporting import OperatorError, reporting

MorphJob = am.MorphJob  # the morph in a worker thread that invoke() starts


class ANIMANIFOLD_OT_morph_selected(CoreJobModal, Operator):
    """Morph from the selected mesh object to the active one over a frame range"""

    bl_idname = "animanifold.morph_selected"
    bl_label = "Morph Selected"
    bl_options = {"REGISTER", "UNDO"}
    _status_label = "Morph Selected"

    method: EnumProperty(name="Method", items=METHOD_ITEMS, default=BEST_METHOD.upper(),
                         description="How the core builds the morph (the best available is the default)")
    use_scene_range: BoolProperty(name="Scene Range", default=True,
                                  description="Morph over the scene's frame range (else Start–End)")
    frame_start: IntProperty(name="Start", default=1, description="Frame where the morph is the source")
    frame_end: IntProperty(name="End", default=48, description="Frame where the morph is the target")
    # Shown as "Max Push", the name the README and the CLI (--max-push) use: am.morph's max_push.
    transition: FloatProperty(name="Max Push", default=0.45, min=0.05, max=0.49, subtype="FACTOR",
                              description="Skeleton method: the share of the range over which the source's holes "
                                          "and dents close after the start and the target's open before the end "
                                          "(max_push)")
    field_resolution: IntProperty(name="Field Resolution", default=24, min=8, soft_max=40, max=48,
                                  description="Field method: lattice cells across the shapes' size. Finer resolves "
                                              "thinner parts and smaller holes in between, in more time and "
                                              "memory (field_resolution)")

    @classmethod
    def poll(cls, context):
        if not in_object_mode(cls, context):
            return False
        selected = [o for o in context.selected_objects if o.type == "MESH"]
        if len(selected) != 2 or context.active_object not in selected:
            cls.poll_message_set("Select two mesh objects: the source, then the target (active)")
            return False
        return True

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "method")
        layout.prop(self, "use_scene_range")
        row = layout.row(align=True)
        row.enabled = not self.use_scene_range
        row.prop(self, "frame_start")
        row.prop(self, "frame_end")
        row = layout.row()
        row.enabled = self.method == "SKELETON"
        row.prop(self, "transition")
        row = layout.row()
        row.enabled = self.method == "FIELD"
        row.prop(self, "field_resolution")

    def _inputs(self, context):
        """(source, target, start, end, source input, target input) (mesh_input.MorphInput); raises
        when there is nothing to morph."""
        target = context.active_object
        # the other selected mesh (other selected objects, a camera or an empty, play no part)
        source = next(o for o in context.selected_objects if o.type == "MESH" and o is not target)
        scene = context.scene
        start, end = (scene.frame_start, scene.frame_end) if self.use_scene_range else (self.frame_start, self.frame_end)
        if end <= start:
            raise OperatorError(f"Morph failed: the frame range {start}–{end} is empty: the end frame must be after "
                                "the start")
        try:
            return source, target, start, end, morph_input(context, source), morph_input(context, target)
        except ValueError as e:  # an open or non-manifold input, named
            raise OperatorError(self._input_message(e, source, target)) from e

    @staticmethod
    def _input_message(e: Exception, source, target) -> str:
        message = str(e).replace("the source", f"the source '{source.name}'").replace("the target", f"the target '{target.name}'")
        return f"Morph failed: {message}"

    def execute(self, context):
        """Blocking: scripts, `blender -b`, and redo from the Adjust Last Operation panel."""
        preferences.apply_threads(context)
        inputs = self._read_inputs(context)
        if inputs is None:
            return {"CANCELLED"}
        source, target, start, end, source_input, target_input = inputs
        progress = self._job_progress(context.window_manager)
        began = time.perf_counter()
        manifold = None
        with reporting(self, lambda: f"Morph failed {progress.where}", name_type=True):
            try:
                progress.at(5.0, "in the core's conforming and fill stages")
                manifold = am.morph(source_input.mesh, target_input.mesh, progress=progress,
                                    **self._options(start, end, source_input, target_input))
            except ValueError as e:  # the core names the input and what is wrong with it
                raise OperatorError(self._input_message(e, source, target)) from e
            finally:
                progress.end()
        if manifold is None:
            return {"CANCELLED"}
        return self._finish(context, source, target, start, end, source_input, target_input, manifold, began)

    def _read_inputs(self, context):
        """_inputs, or None once a failure is reported."""
        with reporting(self, "Morph failed reading the inputs", name_type=True):
            return self._inputs(context)
        return None

    def _options(self, start, end, source_input, target_input) -> dict:
        """am.morph's options from the operator's properties and the inputs' looks."""
        _, _, source_look, target_look = morph_looks(source_input, target_input)
        return dict(t0=float(start), t1=float(end), method=self.method.lower(), max_push=self.transition,
                    field_resolution=self.field_resolution, source_attributes=source_look,
                    target_attributes=target_look)

    def _start(self, context) -> set:
        """From the interface (CoreJobModal.invoke): the morph runs in a worker thread (am.MorphJob),
        the status bar shows its stage, Esc cancels; the interface keeps drawing and the view can be
        turned meanwhile."""
        inputs = self._read_inputs(context)
        if inputs is None:
            return {"CANCELLED"}
        source, target, start, end, source_input, target_input = inputs
        job = MorphJob(source_input.mesh, target_input.mesh, **self._options(start, end, source_input, target_input))
        return self._start_job(context, job, inputs)

    def _job_progress(self, wm) -> Progress:
        """Reading the inputs (0–5), the core's stages (5–85: it reports each one as it finishes,
        with the fraction of the whole done), saving the cache and making the object."""
        return Progress(wm, 5.0, 85.0, words="after the core's {} stage")

    def _job_done(self, context) -> set:
        job = self._job
        source, target, start, end, source_input, target_input = self._source
        if job.cancelled:
            self.report({"WARNING"}, f"Morph cancelled after {time.perf_counter() - job.started:.1f} s: nothing was added")
            return {"CANCELLED"}
        if isinstance(job.error, ValueError):
            self.report({"ERROR"}, self._input_message(job.error, source, target))
            return {"CANCELLED"}
        if job.error is not None:
            self.report({"ERROR"}, f"Morph failed after the core's {job.stage} stage: "
                                   f"{type(job.error).__name__}: {job.error}")
            return {"CANCELLED"}
        return self._finish(context, source, target, start, end, source_input, target_input, job.manifold,
                            job.started)

    def _finish(self, context, source, target, start, end, source_input, target_input, manifold, began):
        """Saves the cache, makes the object and reports what the validity checks found."""
        method = self.method.lower()
        made = None
        with reporting(self, "Morph failed while saving the cache or making the object", name_type=True):
            made = make_morph_object(context, source, target, start, end, source_input, target_input, manifold)
        if made is None:
            return {"CANCELLED"}
        if made.note:
            self.report({"WARNING"}, made.note)
        new, validity = made.obj, manifold.validity
        report_validity(self.report, new, manifold, method, source, target, source_input.mesh, target_input.mesh)
        stages = ", ".join(f"{stage} {seconds:.2f}" for stage, seconds in validity.get("stage_seconds", []))
        self.report({"INFO"}, f"'{new.name}': {method} morph, {len(manifold.simplices)} tets, frames {start}–{end}, "
                              f"{time.perf_counter() - began:.2f} s ({stages}), cache {made.stored}")
        return {"FINISHED"}


classes = (ANIMANIFOLD_OT_morph_selected,)
