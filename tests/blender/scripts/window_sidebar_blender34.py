"""A screenshot of the Animanifold sidebar at its default width, in a real window (Debian's
Blender 3.4 on a virtual screen: Xvfb), with a live manifold object active, so that a person
can look at it for cut labels. Run:
    blender --factory-startup --enable-event-simulate --python window_sidebar_blender34.py -- ZIP DIR

Writes DIR/sidebar.png, prints "WINDOW SIDEBAR OK <path>" and quits with status 0; on a
failure prints "WINDOW SIDEBAR FAILED: <why>" and quits with status 1.
"""
import os
import sys
import traceback

import addon_utils
import bpy

zip_path, out_dir = sys.argv[sys.argv.index("--") + 1:][:2]
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, os.path.join(ROOT, "blender_scenes"))
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)


def fail(why):
    print(f"WINDOW SIDEBAR FAILED: {why}", flush=True)
    os._exit(1)


def view3d():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                return window, area
    fail("no 3D view")


def setup():
    from build_demo_scene import build_demo_scene

    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    build_demo_scene(segments=16, rings=8)
    window, area = view3d()
    with bpy.context.temp_override(window=window, area=area):
        if bpy.ops.animanifold.convert_action() != {"FINISHED"}:
            fail("Convert did not finish")
    area.spaces.active.show_region_ui = True
    # The splash screen (factory startup) would cover the view and take the events.
    x, y = area.x + area.width // 3, area.y + area.height // 3
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    window.event_simulate(type="ESC", value="PRESS", x=x, y=y)
    window.event_simulate(type="ESC", value="RELEASE", x=x, y=y)


# Blender 3.4 has no API for the sidebar's tab: a click on the Animanifold tab, where the
# factory layout draws it (the fourth tab from the top, at the region's right edge).
TAB_FROM_RIGHT, TAB_FROM_TOP = 13, 232


def click_tab():
    window, area = view3d()
    x, y = area.x + area.width - TAB_FROM_RIGHT, area.y + area.height - TAB_FROM_TOP
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    window.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    window.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    bpy.app.timers.register(shoot, first_interval=1.0)


def shoot():
    try:
        window, area = view3d()
        path = os.path.join(out_dir, "sidebar.png")
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.screen.screenshot_area(filepath=path)
        if not os.path.exists(path):
            fail("no screenshot written")
        print(f"WINDOW SIDEBAR OK {path}", flush=True)
        os._exit(0)
    except Exception:
        traceback.print_exc()
        fail("screenshot raised")


def first():
    try:
        setup()
    except Exception:
        traceback.print_exc()
        fail("setup raised")
    bpy.app.timers.register(click_tab, first_interval=2.0)


bpy.app.timers.register(first, first_interval=1.0)
