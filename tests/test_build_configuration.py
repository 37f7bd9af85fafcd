"""What the build gives each translation unit in every configuration (CMakeLists.txt).

With CGAL's assertions on (Debug, or RelWithDebInfo without NDEBUG), CGAL 5.5's corefinement
never returns on inputs the release build finishes in under a second, so a developer's Debug
build would hang where users do not. Every unit that includes CGAL must therefore get
CGAL_NDEBUG whatever the configuration, while our own assertions stay as the configuration
says. The test configures trees (no compiling) and reads their compile commands.
"""

from __future__ import annotations

import json
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted((ROOT / "cpp" / "src").glob("*.cpp"))


def _includes_cgal(path: Path, cgal_headers: set[str]) -> bool:
    for line in path.read_text().splitlines():
        m = re.match(r'#include [<"]([^>"]+)[>"]', line)
        if m and (m.group(1).startswith("CGAL/") or m.group(1) in cgal_headers):
            return True
    return False


def _cgal_units() -> set[str]:
    """The cpp/src units that include CGAL, directly or through a private header (found here
    independently of cmake/cgal_units.cmake)."""
    headers = sorted((ROOT / "cpp" / "src").glob("*.hpp"))
    cgal_headers: set[str] = set()
    while True:
        found = {h.name for h in headers if _includes_cgal(h, cgal_headers)}
        if found == cgal_headers:
            break
        cgal_headers = found
    return {s.name for s in SOURCES if _includes_cgal(s, cgal_headers)}


def _compile_flags(tmp_path: Path, build_type: str, *extra: str) -> dict[str, list[str]]:
    """Each cpp/src unit's compile command (as arguments) in a freshly configured tree."""
    if shutil.which("cmake") is None or shutil.which("ninja") is None:
        pytest.fail("cmake and ninja are installed by scripts/install-deps.sh")
    build = tmp_path / build_type
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", f"-DCMAKE_BUILD_TYPE={build_type}",
                    "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON", "-DANIMANIFOLD_TESTS=OFF", "-DANIMANIFOLD_BENCH=OFF", *extra],
                   check=True, capture_output=True, text=True, timeout=600)
    commands = json.loads((build / "compile_commands.json").read_text())
    flags: dict[str, list[str]] = {}
    for entry in commands:
        source = Path(entry["file"])
        # The core's own library (animanifold_core / animanifold_shared_units), not the module's copies.
        if source.parent == ROOT / "cpp" / "src" and "animanifold_" in entry["output"]:
            flags[source.name] = shlex.split(entry["command"])
    return flags


def _defined(arguments: list[str], name: str) -> bool:
    """Whether the command line leaves `name` defined (-D and -U are read in order)."""
    state = False
    for a in arguments:
        if a == f"-D{name}" or a.startswith(f"-D{name}="):
            state = True
        elif a == f"-U{name}":
            state = False
    return state


@pytest.mark.parametrize("build_type, extra", [
    ("Debug", ()),
    ("RelWithDebInfo", ("-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g",)),  # without NDEBUG
    ("Release", ()),
])
def test_cgal_assertions_are_off_in_every_configuration_and_ours_follow_it(tmp_path, build_type, extra):
    cgal_units = _cgal_units()
    assert {"hole_space_3d.cpp", "isolated_boolean.cpp"} & cgal_units, "the Boolean units include CGAL"
    flags = _compile_flags(tmp_path, build_type, *extra)
    assert set(flags) == {s.name for s in SOURCES}, "every unit of cpp/src is compiled once into the core"
    for name, arguments in flags.items():
        ndebug = _defined(arguments, "NDEBUG")
        assert ndebug == (build_type == "Release"), f"{name}: NDEBUG in {build_type}"
        if name in cgal_units:
            assert ndebug or _defined(arguments, "CGAL_NDEBUG"), f"{name} includes CGAL with its assertions on"
