"""animanifold: animations as animation manifolds.

An animation of a surface becomes one tetrahedral 3-manifold in R^4
(x, y, z, t); a frame is its iso-slice at time t, so frames may change
topology. ::

    import animanifold as am
    m = am.stitch(frames, faces, times)      # keyframes with correspondence
    s = m.slice(0.5)                          # s.vertices, s.faces, s.normals
    m2 = m.subdivide(levels=1)                # smooth shape and motion (Schaefer et al.)
    s2 = m.slice(0.5, smooth_levels=2)        # Loop-smoothed frame (OpenSubdiv)
    m2 = m.deform(anchors, handles, am.handle_transform(translation=[0, 0, 1, 0]))
    m3 = m.deform(anchors, handles, T, regularise=True)   # split stretched edges (§4.5.1)
    am.save(m, "walk.amf"); m2 = am.load("walk.amf")
    sk = am.voronoi_skeleton(vertices, faces, side="external")  # chapter 7
    m = am.morph((VS, FS), (VT, FT))          # chapters 5, 8; m.slice(t) honours shared holes
    H = am.hole_space(vertices, faces)        # CH(C) \\ C (§8.6.5), with intersect_/subtract_solid
"""

from ._core import Complex as _Complex  # noqa: F401  (import check: the native module is built)
from ._core import Error
from .cache import CacheError, load, save
from .deform import Deformer, RestoreStatus, handle_transform, laplacian_deform, rotation_matrix
from .holes import BooleanError, hole_space, intersect_solids, solid_measure, subtract_solid
from .manifold import AnimationManifold, HoleSpaceWarning, Slice, SliceMover, axis_index, stitch
from .meshio import read_mesh, write_mesh
from .morph import morph
from .morph_surface import SurfaceAttributes
from .refine import Refinement, refine
from .regularise import Regularisation, RegularisationMaps, regularise
from .smooth import SmoothFrame, subdivide, subdivide_frame
from .skeleton import SeparabilityWarning, VoronoiSkeleton, voronoi_skeleton

__version__ = "0.1.0"

__all__ = [
    "AnimationManifold",
    "BooleanError",
    "CacheError",
    "Error",
    "SeparabilityWarning",
    "Deformer",
    "HoleSpaceWarning",
    "RestoreStatus",
    "Slice",
    "SurfaceAttributes",
    "SliceMover",
    "SmoothFrame",
    "VoronoiSkeleton",
    "axis_index",
    "handle_transform",
    "hole_space",
    "intersect_solids",
    "laplacian_deform",
    "load",
    "morph",
    "read_mesh",
    "refine",
    "Refinement",
    "Regularisation",
    "RegularisationMaps",
    "regularise",
    "rotation_matrix",
    "save",
    "solid_measure",
    "stitch",
    "subdivide",
    "subdivide_frame",
    "subtract_solid",
    "voronoi_skeleton",
    "write_mesh",
]
