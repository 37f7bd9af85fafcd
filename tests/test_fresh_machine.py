"""A guard for the suite itself: it must pass on any fresh machine of the project's kind.

No test may assert on a wall-clock duration (a slow or busy machine is not a bug: speed
figures live in bench/), and no test may read data from outside the repository except the
shared data through the `shared_data` fixture (tests/conftest.py), which skips with its reason
when the folder is absent. The scan reads every Python file under tests/ and names the
offending line.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

TESTS = Path(__file__).resolve().parent
CLOCKS = {"perf_counter", "perf_counter_ns", "monotonic", "monotonic_ns", "time", "time_ns", "process_time"}
ALLOWED_ABSOLUTE = re.compile(r"^/(dev|proc|sys|tmp|usr/bin)(/|$)")  # devices, scratch, installed programs
PATH_LIKE = re.compile(r"^(/[\w.-]+/|\.\./)")


def sources() -> list[Path]:
    return sorted(p for p in TESTS.rglob("*.py") if "__pycache__" not in p.parts)


def is_clock_call(node: ast.AST) -> bool:
    if not isinstance(node, ast.Call):
        return False
    f = node.func
    if isinstance(f, ast.Attribute):
        return f.attr in CLOCKS and isinstance(f.value, ast.Name) and f.value.id == "time"
    return isinstance(f, ast.Name) and f.id in CLOCKS - {"time"}


def clock_names(tree: ast.AST) -> set[str]:
    """Names assigned a value computed from a clock reading, directly or through other such names."""
    names: set[str] = set()
    assignments = [n for n in ast.walk(tree) if isinstance(n, (ast.Assign, ast.AugAssign, ast.AnnAssign))]
    changed = True
    while changed:
        changed = False
        for node in assignments:
            if node.value is None or not reads_clock(node.value, names):
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                for name in (n.id for n in ast.walk(target) if isinstance(n, ast.Name)):
                    if name not in names:
                        names.add(name)
                        changed = True
    return names


def reads_clock(node: ast.AST, names: set[str]) -> bool:
    return any(is_clock_call(n) or (isinstance(n, ast.Name) and n.id in names) for n in ast.walk(node))


def docstrings(tree: ast.AST) -> set[int]:
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                found.add(id(first.value))
    return found


def offences(path: Path, root: Path = TESTS.parent) -> list[str]:
    """One line per offence in `path`: where (relative to `root`), the source line and why."""
    text = path.read_text()
    tree = ast.parse(text)
    lines = text.splitlines()
    where = lambda node: f"{path.relative_to(root)}:{node.lineno}: {lines[node.lineno - 1].strip()}"
    names = clock_names(tree)
    found = [f"{where(n)}  (asserts on a wall-clock duration)" for n in ast.walk(tree)
             if isinstance(n, ast.Assert) and reads_clock(n.test, names)]
    skip = docstrings(tree)
    for node in ast.walk(tree):
        if (isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip
                and PATH_LIKE.match(node.value) and not ALLOWED_ABSOLUTE.match(node.value)):
            found.append(f"{where(node)}  (a path outside the repository: use the shared_data fixture or tmp_path)")
    return found


def test_no_test_asserts_on_wall_clock_time_or_reads_outside_the_repository():
    found = [line for path in sources() for line in offences(path)]
    assert not found, "tests that a fresh machine can fail:\n" + "\n".join(found)


def test_the_guard_catches_what_it_is_for(tmp_path):
    bad = tmp_path / "test_bad.py"
    bad.write_text("import time\n\ndef test_x():\n    start = time.perf_counter()\n    work()\n"
                   "    elapsed = time.perf_counter() - start\n    assert elapsed < 1.0\n"
                   "    assert time.monotonic() > 0\n    open('/work/shared/data/x.off')\n"
                   "    open('../shared/data/y.off')\n    open('/dev/null')\n")
    found = offences(bad, root=tmp_path)
    assert [line.split(":")[1] for line in found] == ["7", "8", "9", "10"], found
