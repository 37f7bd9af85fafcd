"""The add-on's EnumProperty items are the core's bound enums: the same names, in the same order."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

pytestmark = pytest.mark.blender


def operator_items(operator, prop: str) -> tuple[str, ...]:
    return tuple(operator.get_rna_type().properties[prop].enum_items.keys())


def test_deform_items_are_the_laplacian_enums(addon):
    from animanifold_blender._lib import am
    assert operator_items(bpy.ops.animanifold.deform, "method") == tuple(am._core.LaplacianMethod.__members__)
    assert operator_items(bpy.ops.animanifold.deform, "boundary") == tuple(am._core.BoundaryRule.__members__)


def test_skeleton_items_are_the_skeleton_enums(addon):
    from animanifold_blender._lib import am
    skeleton = bpy.ops.animanifold.skeleton
    assert operator_items(skeleton, "side") == tuple(n.upper() for n in am._core.SkeletonSide.__members__)
    assert operator_items(skeleton, "wrap") == tuple(n.upper() for n in am._core.WrapShape.__members__)


def test_deform_settings_offer_the_enum_members(addon):
    from animanifold_blender._lib import am
    from animanifold_blender.properties import AnimanifoldDeformSettings
    rna = AnimanifoldDeformSettings.bl_rna
    assert tuple(rna.properties["method"].enum_items.keys()) == tuple(am._core.LaplacianMethod.__members__)
    assert tuple(rna.properties["boundary"].enum_items.keys()) == tuple(am._core.BoundaryRule.__members__)
