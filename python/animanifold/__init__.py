"""animanifold: animations as animation manifolds.

An animation of a surface becomes one tetrahedral 3-manifold in R^4
(x, y, z, t); a frame is its iso-slice at time t, so frames may change
topology. ::

    import animanifold as am
    m = am.stitch(frames, faces, times)      # keyframes with correspondence
    s = m.slice(0.5)                          # s.vertices, s.faces, s.normals
    m2 = am.subdivide(m, levels=1)            # smooth shape and motion (Schaefer et al.)
    s2 = m.slice(0.5, smooth_levels=2)        # Loop-smoothed frame (OpenSubdiv)
    m2 = am.deform(m, anchors, handles, am.handle_transform(translation=[0, 0, 1, 0]))
    m3 = am.deform(m, anchors, handles, T,    # split stretched edges (§4.5.1)
                   options=am.DeformOptions(regularise=am.RegulariseOptions()))
    m4, r = am.refine(m, splits)              # barycentric refinement (chapter 6)
    m5 = am.weld(m)                           # seams (split copies of points) closed
    am.save(m, "walk.amf"); m2 = am.load("walk.amf")
    am.set_threads(2)                         # the core's threads (0: every core); am.threads()
    sk = am.voronoi_skeleton(vertices, faces, side="external")  # chapter 7
    m = am.morph((VS, FS), (VT, FT))          # chapters 5, 8; m.slice(t) honours shared holes
    H = am.hole_space(vertices, faces)        # CH(C) \\ C (§8.6.5), with intersect_/subtract_solid
    am.set_memory_limit(2**30)                # calls that would need more raise am.MemoryLimitError
"""

from ._core import Complex as _Complex  # noqa: F401  (import check: the native module is built)
from ._core import Cancelled, Error, FileError, InputError, MeshingError, TimeLimitError
from .cache import CacheError, load, save
from .deformation import DeformOptions, deform
from .frame_smoothing import SmoothFrame, smooth_slice, subdivide_frame
from .holes import BooleanError, hole_space, intersect_solids, solid_measure, subtract_solid
from .interval_frame import IntervalFrame
from .prism_frames import Prisms
from .laplacian import Deformer, LaplacianOptions, RestoreStatus, handle_transform, laplacian_deform, rotation_matrix
from .manifold import AnimationManifold, HoleSpaceWarning, axis_index
from .memory_limits import MemoryLimitError, memory_limit, set_memory_limit
from .meshio import read_mesh, write_mesh
from .morph_pipeline import morph
from .morph_surface import SurfaceAttributes
from .refinement import Refinement, RefineOptions, refine, refine_complex
from .regularisation import Regularisation, RegularisationMaps, RegulariseOptions, regularise
from .skeleton import EmptySkeletonWarning, SeparabilityWarning, VoronoiSkeleton, voronoi_skeleton
from .slices import Slice
from .stitching import stitch
from .subdivision import SubdivideOptions, subdivide, subdivided_simplex_count
from .thread_count import set_threads, threads
from .welding import weld
from . import mesh_export  # noqa: E402,F401  (frame files with UVs, normals and materials)
from . import display  # noqa: E402,F401  (how slices are shown as frames: the add-on's playback)
from . import frame_quality  # noqa: E402,F401  (frames' topology and pieces: the add-on's morph report)
from . import morph_noise  # noqa: E402,F401  (which whole frames show a morph's noise: the add-on's report)
# Live playback's bpy-free parts, for the add-on: an interval's cut and its frames, the
# memory-bounded cache of them, making them ahead, and the subdivisions kept per manifold.
from . import interval_cuts, cut_cache, cut_prefetch, subdivision_cache  # noqa: E402,F401
from .core_job import CoreJob
from .morph_job import MorphJob

__version__ = "0.1.0"

__all__ = [
    "AnimationManifold",
    "BooleanError",
    "CacheError",
    "EmptySkeletonWarning",
    "Error",
    "FileError",
    "InputError",
    "MeshingError",
    "TimeLimitError",
    "SeparabilityWarning",
    "DeformOptions",
    "Deformer",
    "HoleSpaceWarning",
    "IntervalFrame",
    "Prisms",
    "CoreJob",
    "MorphJob",
    "RestoreStatus",
    "Slice",
    "SurfaceAttributes",
    "SmoothFrame",
    "VoronoiSkeleton",
    "axis_index",
    "Cancelled",
    "deform",
    "handle_transform",
    "hole_space",
    "intersect_solids",
    "LaplacianOptions",
    "laplacian_deform",
    "load",
    "memory_limit",
    "MemoryLimitError",
    "morph",
    "read_mesh",
    "refine",
    "refine_complex",
    "Refinement",
    "RefineOptions",
    "Regularisation",
    "RegularisationMaps",
    "RegulariseOptions",
    "regularise",
    "rotation_matrix",
    "save",
    "set_memory_limit",
    "set_threads",
    "smooth_slice",
    "solid_measure",
    "stitch",
    "subdivide",
    "SubdivideOptions",
    "subdivided_simplex_count",
    "subdivide_frame",
    "subtract_solid",
    "threads",
    "voronoi_skeleton",
    "weld",
    "write_mesh",
]
