"""The sidebar's wording and enabling (bpy 4.5): every label fits the default sidebar width
(a split layout's label column: ui.LABEL_CHARS), Convert is off on a manifold object, and
messages take the right article."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import os  # noqa: E402
from types import SimpleNamespace  # noqa: E402

from helpers.blender_helpers import BLENDER, NO_BLENDER_BINARY, NO_XVFB, XVFB, run_blender_in_window  # noqa: E402

pytestmark = pytest.mark.blender

# A full-width line (a button, a heading) at the default sidebar width.
LINE_CHARS = 30


class Recorder:
    """A layout that records each drawn text: (kind, text, split) with the label Blender
    would show (the `text` given, else the property's or operator's name)."""

    def __init__(self, log, split=False, icons=None):
        self.log, self.enabled, self.use_property_split, self.use_property_decorate = log, True, split, True
        self.icons = {} if icons is None else icons  # property or operator -> its icon

    def _child(self, **_kw):
        return Recorder(self.log, self.use_property_split, self.icons)

    box = row = column = _child

    def label(self, text="", **_kw):
        self.log.append(("label", text, False))

    def prop(self, data, name, text=None, expand=False, icon="NONE", **_kw):
        prop = data.bl_rna.properties[name]
        label = prop.name if text is None else text
        self.log.append(("prop", label, self.use_property_split))
        self.icons[name] = icon
        if expand and prop.type == "ENUM" and not self.use_property_split:
            pytest.fail(f"'{name}': an expanded row without a label")

    def prop_search(self, data, name, *_args, text=None, **kw):
        self.prop(data, name, text=text, **kw)

    def operator(self, idname, text=None, icon="NONE", **_kw):
        module, name = idname.split(".")
        op = getattr(getattr(bpy.ops, module), name)
        self.log.append(("operator", op.get_rna_type().name if text is None else text, False))
        self.icons[idname] = icon
        return SimpleNamespace()


def drawn(addon, panel, icons=None) -> list:
    log = []
    layout = Recorder(log, icons=icons)
    panel.draw(SimpleNamespace(layout=layout), bpy.context)
    return log


def panels(addon):
    return (addon.ui.VIEW3D_PT_animanifold, addon.ui.VIEW3D_PT_animanifold_smooth,
            addon.ui_tools.VIEW3D_PT_animanifold_tools)


def assert_labels_fit(addon, what):
    for panel in panels(addon):
        for kind, text, split in drawn(addon, panel):
            if kind == "label" and text == bpy.context.active_object.name:
                continue  # a name is the user's
            limit = addon.ui.LABEL_CHARS if split else LINE_CHARS
            assert len(text) <= limit, f"{what}: {panel.__name__} draws {kind} {text!r}, cut beyond {limit} characters"
            if kind == "prop":
                assert split, f"{what}: {panel.__name__}: {text!r} is not in a split layout"


def test_every_label_fits_the_default_sidebar(demo, addon):
    assert_labels_fit(addon, "a plain mesh")
    demo.vertex_groups.new(name="anchor")
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    man = bpy.context.active_object
    man.animanifold_deform.regularise = True
    assert_labels_fit(addon, "a live manifold")
    man.animanifold.axis = "x"
    man.animanifold.subdivision_levels = 1
    man.animanifold.smooth_levels = 1
    assert_labels_fit(addon, "a sweep view, smoothed")


def test_convert_is_disabled_on_a_manifold_object(demo):
    assert bpy.ops.animanifold.convert_action.poll()
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    assert bpy.context.active_object.animanifold.is_manifold
    assert not bpy.ops.animanifold.convert_action.poll()


def test_convert_and_live_deform_have_distinct_icons(demo, addon):
    icons = {}
    for panel in panels(addon):
        drawn(addon, panel, icons)
    assert icons["animanifold.convert_action"] != icons["interactive"]


def test_anchor_and_handle_fields_start_empty_and_use_the_conventional_groups(demo):
    settings = demo.animanifold_deform
    assert settings.anchor_group == "" and settings.handle_group == ""
    assert settings.anchor_group_used == "" and settings.handle_group_used == ""
    demo.vertex_groups.new(name="handle")
    assert settings.handle_group_used == "handle" and settings.anchor_group_used == ""
    settings.handle_group = "grip"
    assert settings.handle_group_used == "grip"


def test_articles(addon):
    from animanifold_blender import messages

    assert [messages.with_article(w) for w in ("armature", "empty", "curve", "light probe")] == [
        "an armature", "an empty", "a curve", "a light probe"]


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
@pytest.mark.skipif(XVFB is None, reason=NO_XVFB)
def test_sidebar_screenshot_in_a_real_window(tmp_path):
    """Debian's Blender 3.4 in a window on a virtual screen (tests/blender/scripts/
    window_sidebar_blender34.py) draws the sidebar with a live manifold active and saves a
    screenshot, tmp_path/sidebar.png, for a person to look at (no label cut)."""
    proc = run_blender_in_window(tmp_path, "window_sidebar_blender34.py")
    lines = proc.stdout.strip().splitlines()
    assert proc.returncode == 0 and lines and lines[-1].startswith("WINDOW SIDEBAR OK"), \
        (proc.returncode, proc.stdout[-3000:], proc.stderr[-3000:])
    assert (tmp_path / "sidebar.png").stat().st_size > 0
