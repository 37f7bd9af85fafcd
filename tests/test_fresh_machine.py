"""A guard for the suite itself: it must pass on any fresh machine of the project's kind.

No test may assert on a wall-clock duration, nor compare one with a deadline that decides
its verdict (a slow or busy machine is not a bug: speed figures live in bench/); the one
bound against a hang is helpers/window_script.py's `stuck`. No test may read data from outside the repository except the
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


def clock_valued(node: ast.AST, names: set[str]) -> bool:
    """Whether `node` is a clock reading, or arithmetic on one (not a container holding one)."""
    if is_clock_call(node) or (isinstance(node, ast.Name) and node.id in names):
        return True
    if isinstance(node, ast.BinOp):
        return clock_valued(node.left, names) or clock_valued(node.right, names)
    return isinstance(node, ast.UnaryOp) and clock_valued(node.operand, names)


def clock_value_names(tree: ast.AST) -> set[str]:
    """Plain names bound to a clock reading or to arithmetic on one, directly or through other such names."""
    names: set[str] = set()
    changed = True
    while changed:
        changed = False
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign) and clock_valued(node.value, names):
                for target in node.targets:
                    if isinstance(target, ast.Name) and target.id not in names:
                        names.add(target.id)
                        changed = True
    return names


# The hang bound: the one place a test compares a wall-clock duration.
HANG_BOUND = ("helpers/window_script.py", "stuck")


def clock_comparisons(path: Path, tree: ast.AST, root: Path) -> list[ast.Compare]:
    """Comparisons of a wall-clock duration with anything, outside the hang bound."""
    names = clock_value_names(tree)
    allowed: set[int] = set()
    if path.is_relative_to(root / "tests") and path.relative_to(root / "tests").as_posix() == HANG_BOUND[0]:
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name == HANG_BOUND[1]:
                allowed |= {id(n) for n in ast.walk(node)}
    return [n for n in ast.walk(tree) if isinstance(n, ast.Compare) and id(n) not in allowed
            and any(clock_valued(operand, names) for operand in [n.left, *n.comparators])]


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
    asserted = {n.lineno for n in ast.walk(tree) if isinstance(n, ast.Assert) and reads_clock(n.test, names)}
    found += [f"{where(n)}  (compares a wall-clock duration: a slow machine reaches the deadline; "
              f"use window_script.stuck for a hang)" for n in clock_comparisons(path, tree, root)
              if n.lineno not in asserted]
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
    watchdog = tmp_path / "tests" / "blender" / "scripts" / "window_x.py"
    watchdog.parent.mkdir(parents=True)
    watchdog.write_text("import time\nstate = {'began': time.perf_counter()}\n\ndef step():\n"
                        "    elapsed = time.perf_counter() - state['began']\n    if elapsed > 100:\n        fail()\n"
                        "    while time.perf_counter() - state['began'] < 60:\n        pass\n"
                        "    if state['phase'] == 'start':\n        go()\n")
    found = offences(watchdog, root=tmp_path)
    assert [line.split(":")[1] for line in found] == ["6", "8"], found
