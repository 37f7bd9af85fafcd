"""Appends the stub of _core._testing to _core's as a namespace class.

pybind11-stubgen writes the submodule to its own file (_core/_testing.pyi), which
cannot sit beside the compiled _core module; inside _core.pyi, `class _testing` with
static methods gives type checkers and readers the same signatures under the same
name (`_core._testing.delaunay(...)`). Usage (scripts/generate-stubs.sh):

    python3 stub_testing_namespace.py <_core stub> <_testing stub>   # prints the merged stub
"""

from __future__ import annotations

import sys

INDENT = "    "


def testing_body(text: str) -> tuple[list[str], str, list[str]]:
    """The submodule stub's import lines, docstring and body (defs and classes)."""
    lines = text.splitlines()
    docstring = ""
    if lines and lines[0] == '"""':
        end = lines.index('"""', 1)
        docstring = " ".join(line.strip() for line in lines[1:end])
        lines = lines[end + 1:]
    imports = [line for line in lines if line.startswith(("import ", "from "))]
    body = [line for line in lines if not line.startswith(("import ", "from ", "__all__"))]
    return imports, docstring, body


def as_namespace(docstring: str, body: list[str]) -> list[str]:
    """`body` (module level) as the body of `class _testing`: functions become static methods,
    names qualified by the module refer to the class or to _core's own names."""
    out = ["class _testing:", f'{INDENT}"""{docstring} (the submodule _core._testing)"""']
    for line in body:
        line = line.replace("animanifold._core._testing.", "_testing.").replace("animanifold._core.", "")
        if line.startswith("def "):
            out.append(f"{INDENT}@staticmethod")
        out.append(INDENT + line if line else line)
    return out


def merged(core: str, testing: str) -> str:
    imports, docstring, body = testing_body(testing)
    lines = [line for line in core.splitlines() if line != "from . import _testing"]
    have = set(lines)
    last_import = max(i for i, line in enumerate(lines) if line.startswith(("import ", "from ")))
    extra = [line for line in imports if line not in have and line != "import animanifold._core"]
    lines[last_import + 1:last_import + 1] = extra
    return "\n".join(lines + as_namespace(docstring, body)) + "\n"


if __name__ == "__main__":
    core_path, testing_path = sys.argv[1:3]
    with open(core_path) as core, open(testing_path) as testing:
        sys.stdout.write(merged(core.read(), testing.read()))
