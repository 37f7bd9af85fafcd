"""`animanifold_blender` as a name that works however the add-on is installed.

Blender 4.2+ imports an extension as `bl_ext.<repository>.animanifold_blender`, so
`import animanifold_blender` (what a render-farm command line writes: `blender -b
scene.blend --python-expr "from animanifold_blender import farm; ..."`) finds nothing.
When the add-on is loaded under another name, this finder answers for
`animanifold_blender` and every `animanifold_blender.<module>` with the add-on's own
modules (the same module objects, never a second copy with its own state).
A legacy add-on or a folder on PYTHONPATH is `animanifold_blender` already.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys

ALIAS = "animanifold_blender"


class _Existing(importlib.abc.Loader):
    """Loads a module by handing out one that is already imported."""

    def __init__(self, module):
        self.module = module
        self.spec = module.__spec__

    def create_module(self, spec):
        return self.module

    def exec_module(self, module):
        module.__spec__ = self.spec  # the import system set the alias's spec: the module keeps its own


class AliasFinder(importlib.abc.MetaPathFinder):
    """Maps `animanifold_blender[.x]` to `<real package>[.x]`."""

    def __init__(self, real: str):
        self.real = real

    def find_spec(self, fullname, path=None, target=None):
        if fullname != ALIAS and not fullname.startswith(ALIAS + "."):
            return None
        module = importlib.import_module(self.real + fullname[len(ALIAS):])
        return importlib.util.spec_from_loader(fullname, _Existing(module), is_package=hasattr(module, "__path__"))


def install(real: str) -> None:
    """Makes `animanifold_blender` name the package imported as `real` (once; a later
    install for another name replaces it, as re-enabling the add-on would)."""
    if real == ALIAS:
        return
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, AliasFinder)]
    for name in [n for n in sys.modules if n == ALIAS or n.startswith(ALIAS + ".")]:
        del sys.modules[name]  # left by a previous install under another name
    sys.meta_path.insert(0, AliasFinder(real))
