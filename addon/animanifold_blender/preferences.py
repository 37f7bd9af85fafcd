"""The add-on's preferences (Edit > Preferences > Add-ons > Animanifold): the core's thread
count and the memory playback keeps frames in.

* Threads: 0 follows Blender's own setting (Render Properties > Performance >
  Threads: `scene.render.threads`, read when it is applied), so the core's OpenMP
  loops use the cores Blender was given and no more; OpenBLAS follows the same count
  (the Laplacian's factorisation runs it on one thread, for results that do not depend
  on the count: `cpp/include/animanifold/threads.hpp`). Applied when the add-on registers, when
  the preference changes, and by `apply_threads` before long work (convert, bake,
  morph, deform, skeleton).
* Frame Cache Budget: the memory, in MB, for each of playback's two caches (the
  interval cuts and their kept integer frames, `am.cut_cache.CutCache`), read each time
  the cache decides what to keep.

`bl_idname` is the add-on's package name as Blender imported it: `animanifold_blender`
as a legacy add-on, `bl_ext.<repository>.animanifold_blender` as a 4.2+ extension
(module_alias.py).
"""


import bpy
from bpy.props import IntProperty
from bpy.types import AddonPreferences

from ._lib import am

DEFAULT_BUDGET_MB = 256
PACKAGE = __package__


def addon_preferences():
    """This add-on's preferences, or None when Blender did not enable it as an add-on
    (registered by a script or a test, or in the middle of enabling)."""
    addon = bpy.context.preferences.addons.get(PACKAGE)
    return None if addon is None else addon.preferences


def blender_threads(context=None) -> int:
    """Blender's own thread count: the scene's render threads (the machine's cores when
    Blender detects them), or 0 (every core) where no scene is at hand (registering)."""
    scene = getattr(context or bpy.context, "scene", None)
    return int(scene.render.threads) if scene is not None else 0


def wanted_threads(context=None) -> int:
    """The thread count the preferences ask for, Blender's setting resolved."""
    prefs = addon_preferences()
    count = prefs.threads if prefs is not None else 0
    return count if count > 0 else blender_threads(context)


def apply_threads(context=None) -> int:
    """Sets the core's thread count from the preferences; returns the count in use."""
    return am.set_threads(wanted_threads(context))


def frame_cache_budget_bytes() -> int:
    """The Frame Cache Budget preference in bytes (the default when the add-on is not enabled)."""
    prefs = addon_preferences()
    megabytes = prefs.frame_cache_budget if prefs is not None else DEFAULT_BUDGET_MB
    return int(megabytes) * 2**20


def _threads_changed(_prefs, context):
    apply_threads(context)


class AnimanifoldPreferences(AddonPreferences):
    bl_idname = PACKAGE

    threads: IntProperty(
        name="Threads", default=0, min=0, max=1024, update=_threads_changed,
        description="Threads for the core's parallel work (slicing, stitching, subdivision, morphs; the Laplacian's "
                    "solver stays on one so results never depend on it); 0 uses Blender's own setting "
                    "(Render Properties > Performance > Threads)")
    frame_cache_budget: IntProperty(
        name="Frame Cache Budget", default=DEFAULT_BUDGET_MB, min=16, max=65536, subtype="NONE",
        description="Memory in MB for each of playback's caches: the cut of every topology interval "
                    "shown, and the integer frames copied from it")

    def draw(self, context):
        layout = self.layout
        row = layout.row()
        row.prop(self, "threads")
        row.label(text=f"In use: {am.threads()}")
        layout.prop(self, "frame_cache_budget", text="Frame Cache Budget (MB)")


classes = (AnimanifoldPreferences,)


def register_preferences():
    """Applies the thread count once the class is registered."""
    apply_threads()
