"""Every choice users make is the core's bound enum: the Python checks accept exactly its
members, the CLI offers exactly them, and a bad value's error names it and the choices."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from animanifold.choices import checked, names
from animanifold.cli import build_parser
from animanifold.frame_smoothing import FRAME_SCHEMES
from animanifold.laplacian import BOUNDARY_RULES, METHODS
from animanifold.refinement import ORDERS
from animanifold.skeleton import SIDES, WRAP_SHAPES
from animanifold.subdivision import MANIFOLD_SCHEMES


def subcommand(name: str) -> argparse.ArgumentParser:
    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return commands.choices[name]


def cli_choices(command: str, option: str) -> tuple[str, ...]:
    action = next(a for a in subcommand(command)._actions if option in a.option_strings)
    return tuple(action.choices)


def test_the_bound_enums_are_named_as_users_type_them():
    assert names(_core.LaplacianMethod) == ("dual", "graph", "uniform", "cotangent")
    assert names(_core.BoundaryRule) == ("grow", "ghost_anchors", "error")
    assert names(_core.ManifoldScheme) == ("schaefer", "linear")
    assert names(_core.FrameScheme) == ("loop", "catmull_clark", "bspline")
    assert names(_core.RefineOrder) == ("given", "degeneracy")
    assert names(_core.SkeletonSide) == ("internal", "external", "both")
    assert names(_core.WrapShape) == ("box", "sphere", "none")


def test_module_choices_are_the_enum_members():
    assert METHODS == tuple(_core.LaplacianMethod.__members__)
    assert BOUNDARY_RULES == tuple(_core.BoundaryRule.__members__)
    assert MANIFOLD_SCHEMES == tuple(_core.ManifoldScheme.__members__)
    assert FRAME_SCHEMES == tuple(_core.FrameScheme.__members__)
    assert ORDERS == tuple(_core.RefineOrder.__members__)
    assert SIDES == tuple(_core.SkeletonSide.__members__)
    assert WRAP_SHAPES == tuple(_core.WrapShape.__members__)


def test_cli_choices_are_the_enum_members():
    assert cli_choices("skeleton", "--side") == tuple(_core.SkeletonSide.__members__)
    assert cli_choices("skeleton", "--wrap") == tuple(_core.WrapShape.__members__)
    assert cli_choices("morph", "--method") == tuple(_core.MorphMethod.__members__)


@pytest.mark.parametrize("enum", [_core.LaplacianMethod, _core.BoundaryRule, _core.ManifoldScheme,
                                  _core.FrameScheme, _core.RefineOrder, _core.SkeletonSide, _core.WrapShape])
def test_checked_accepts_names_and_members_and_nothing_else(enum):
    for name, member in enum.__members__.items():
        assert checked(name, enum, "choice") == name
        assert checked(member, enum, "choice") == name
        assert enum(name) == member  # the binding's str conversion
    with pytest.raises(ValueError, match="unknown choice 'nonsense': use one of " + ", ".join(enum.__members__)):
        checked("nonsense", enum, "choice")
    with pytest.raises(_core.InputError, match="unknown .* 'nonsense': use '"):
        enum("nonsense")


def test_laplacian_options_accept_exactly_the_members():
    for method in _core.LaplacianMethod.__members__:
        for boundary in _core.BoundaryRule.__members__:
            options = am.LaplacianOptions(method=method, boundary=boundary)
            assert (options.method, options.boundary) == (method, boundary)
    given = am.LaplacianOptions(method=_core.LaplacianMethod.graph, boundary=_core.BoundaryRule.error)
    assert (given.method, given.boundary) == ("graph", "error")
    with pytest.raises(ValueError, match="unknown method 'cotan': use one of dual, graph, uniform, cotangent"):
        am.LaplacianOptions(method="cotan")
    with pytest.raises(ValueError, match="unknown boundary rule 'pin': use one of grow, ghost_anchors, error"):
        am.LaplacianOptions(boundary="pin")


def test_skeleton_and_refine_name_a_bad_choice_and_the_choices():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(ValueError, match="unknown skeleton side 'inside': use one of internal, external, both"):
        am.voronoi_skeleton(v, f, side="inside")
    with pytest.raises(ValueError, match="unknown wrap shape 'cone': use one of box, sphere, none"):
        am.voronoi_skeleton(v, f, wrap="cone")
    with pytest.raises(ValueError, match="unknown order 'random': use one of given, degeneracy"):
        am.refine_complex(v, np.array([[0, 1, 2, 3]]), [], order="random")
