"""The package's layout: `animanifold.<name>` means one thing, and the modules import one way.

A function exported under a module's name (`am.morph` the function over `animanifold.morph` the module)
hides the module from readers and tools; imports inside functions hide dependencies and cycles.
"""

from __future__ import annotations

import ast
import pkgutil
import types
from pathlib import Path

import animanifold as am

PACKAGE = Path(am.__file__).parent
# matplotlib renders the optional contact sheet only: importing it when asked keeps it optional.
OPTIONAL_IMPORTS = {"matplotlib", "mpl_toolkits"}


def _modules() -> dict[str, ast.Module]:
    return {info.name: ast.parse((PACKAGE / f"{info.name}.py").read_text())
            for info in pkgutil.iter_modules([str(PACKAGE)]) if (PACKAGE / f"{info.name}.py").exists()}


def _relative_imports(tree: ast.Module) -> set[str]:
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                names.add(node.module.split(".")[0])
            else:
                names.update(alias.name for alias in node.names)
    return names


def test_no_exported_name_shadows_a_submodule():
    for name in _modules():
        value = getattr(am, name, None)
        assert value is None or isinstance(value, types.ModuleType), f"am.{name} is {value!r}, not the module"


def test_imports_are_at_module_level():
    nested = []
    for name, tree in _modules().items():
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(function):
                if isinstance(node, ast.Import):
                    roots = {alias.name.split(".")[0] for alias in node.names}
                elif isinstance(node, ast.ImportFrom):
                    roots = {"." if node.level else node.module.split(".")[0]}
                else:
                    continue
                if not roots <= OPTIONAL_IMPORTS:
                    nested.append(f"{name}.{function.name}: line {node.lineno}")
    assert not nested


def test_module_imports_have_no_cycle():
    modules = _modules()
    graph = {name: _relative_imports(tree) & set(modules) for name, tree in modules.items()}
    state: dict[str, str] = {}

    def visit(name: str, path: list[str]) -> None:
        state[name] = "open"
        for other in sorted(graph[name]):
            assert state.get(other) != "open", f"import cycle: {' -> '.join(path + [other])}"
            if other not in state:
                visit(other, path + [other])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
