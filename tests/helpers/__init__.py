"""Helpers shared by the tests: shapes, keyframed animations, surface properties, shared data
files and, for the Blender tests, scene and mesh readers.

They live apart from the test modules so that no test module imports another: a test module
is collected once and owns only its tests. tests/ is on sys.path (pytest's rootdir conftest),
so they import as `helpers.<module>`. blender_helpers and morph_scenes import bpy: import
them only after pytest.importorskip("bpy").
"""
