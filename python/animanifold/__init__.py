"""animanifold: animations as animation manifolds.

An animation of a surface becomes one tetrahedral 3-manifold in R^4
(x, y, z, t); a frame is its iso-slice at time t, so frames may change
topology. ::

    import animanifold as am
    m = am.stitch(frames, faces, times)      # keyframes with correspondence
    s = m.slice(0.5)                          # s.vertices, s.faces, s.normals
    m2 = m.deform(anchors, handles, am.handle_transform(translation=[0, 0, 1, 0]))
    am.save(m, "walk.amf"); m2 = am.load("walk.amf")
"""

from ._core import Complex as _Complex  # noqa: F401  (import check: the native module is built)
from .cache import CacheError, load, save
from .deform import Deformer, RestoreStatus, handle_transform, laplacian_deform, rotation_matrix
from .manifold import AnimationManifold, Slice, axis_index, stitch
from .meshio import read_mesh, write_mesh

__version__ = "0.1.0"

__all__ = [
    "AnimationManifold",
    "CacheError",
    "Deformer",
    "RestoreStatus",
    "Slice",
    "axis_index",
    "handle_transform",
    "laplacian_deform",
    "load",
    "read_mesh",
    "rotation_matrix",
    "save",
    "stitch",
    "write_mesh",
]
