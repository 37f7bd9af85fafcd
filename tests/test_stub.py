"""The committed type stub of the native module (python/animanifold/_core.pyi) covers
_core._testing too: its entry points appear as static methods of `class _testing`
(scripts/stub_testing_namespace.py), so readers and type checkers see their signatures."""

from __future__ import annotations

import ast
from pathlib import Path

import animanifold
from animanifold import _core


def _stub() -> ast.Module:
    return ast.parse(Path(animanifold.__file__).with_name("_core.pyi").read_text())


def test_every_testing_entry_point_is_in_the_stub():
    namespace = next(n for n in _stub().body if isinstance(n, ast.ClassDef) and n.name == "_testing")
    stubbed = {n.name for n in namespace.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert stubbed == {name for name in dir(_core._testing) if not name.startswith("_")}
    functions = [n for n in namespace.body if isinstance(n, ast.FunctionDef)]
    assert functions and all(any(isinstance(d, ast.Name) and d.id == "staticmethod" for d in f.decorator_list)
                             for f in functions)


def test_the_stub_does_not_import_a_testing_module_that_has_no_file():
    imports = [n for n in _stub().body if isinstance(n, ast.ImportFrom) and n.module is None]
    assert not any(alias.name == "_testing" for n in imports for alias in n.names)
